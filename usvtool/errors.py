"""The one exception type the library raises for bad input.

The CLI turns it into a one-line message and exit status 1; the message must name the file or
option at fault.
"""


import os


class UsvError(Exception):
    """Bad input or an impossible request, explained in one line."""


def check_input_file(path: str | os.PathLike) -> None:
    """Refuse a missing path, a directory or an empty file, naming it."""
    if not os.path.exists(path):
        raise UsvError(f"{path}: no such file")
    if os.path.isdir(path):
        raise UsvError(f"{path}: is a directory, not a file")
    if os.path.getsize(path) == 0:
        raise UsvError(f"{path}: empty file")
