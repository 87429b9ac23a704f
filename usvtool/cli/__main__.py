"""``python -m usvtool.cli``: the same as the ``usvtool`` console script."""

from usvtool.cli import main

main()
