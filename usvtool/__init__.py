"""usvtool: USV path planning on real nautical charts."""

__version__ = "0.1.0"
