"""The one exception type the library raises for bad input.

The CLI turns it into a one-line message and exit status 1; the message must name the file or
option at fault.
"""


class UsvError(Exception):
    """Bad input or an impossible request, explained in one line."""
