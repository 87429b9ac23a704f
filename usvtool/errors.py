"""The one exception type the library raises for bad input.

The CLI turns it into a one-line message and exit status 1; the message must name the file or
option at fault.
"""


import os

#: The longest error line the CLI prints (characters, the paths it names included; a value
#: quoted in it is cut much shorter: usvtool.yamlfile.show).
LINE = 500


def one_line(text: str, limit: int = LINE) -> str:
    """``text`` on one line (runs of white space as one space), cut in the middle past
    ``limit`` characters so that both the file it names and its remedy survive.

    >>> one_line("a.yaml: x\\n  must be " + "9" * 500 + " at most", 40)
    'a.yaml: x must be 9 [...] 999999 at most'
    """
    text = " ".join(text.split())
    if len(text) <= limit:
        return text
    head = (limit - 7) * 3 // 5
    return f"{text[:head]} [...] {text[len(text) - (limit - 7 - head):]}"


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
