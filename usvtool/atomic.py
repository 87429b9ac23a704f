"""All-or-nothing output: stage every output of a command, rename them all once all are complete.

:class:`staged` hands out one temporary path per target, beside it (same directory, a hidden
name that keeps the target's suffix so that GDAL and OpenCV pick the format, mode 0666 less
the umask). On normal exit it renames every temporary onto its target (``os.replace``, atomic
on POSIX); on any exception it removes every temporary, and every target keeps its old bytes
(or stays absent). :class:`atomic_path` is the same for one file.

How the pieces fit:

- A command does the work that can fail (a preview too large, ...) in memory first, then stages
  all its outputs in one ``staged`` block. The writers (``write_grid``, ``write_png``, ...) keep
  their own ``atomic_path``, so they are atomic when called alone from Python; a path that an
  active staging handed out is written in place (that staging renames it), so a writer given
  a staged temporary makes no second one.
- Signals: inside :class:`catch_signals` (a whole CLI command, and every ``staged`` block)
  SIGINT and SIGTERM raise :class:`Interrupted` in the main thread, so that the cleanup runs
  (Python's default for SIGTERM kills the process on the spot). The previous handlers come
  back afterwards; other threads install nothing (Python runs handlers in the main thread).
- A signal interrupts only the caller's code. While this module's own code runs (creating the
  temporaries, the renames, the cleanup, installing and restoring handlers) it is held, and
  raised when that code is done: so either every rename is done or none has started, and the
  temporaries are always removed. A signal held before the renames start cancels them. The
  first target (the main output, the one Makefiles look at) is renamed last.
- A target that exists and is not a regular file (``/dev/null``, ``/dev/stdout``, a FIFO, or a
  link to one: :func:`in_place`) is written where it is, never renamed onto: that would
  replace the node with a regular file.
- Limits: a rename that fails by itself (a target turned into a directory meanwhile; a sticky
  directory where the target belongs to another user) is reported naming it, and targets
  renamed before it keep their new content: the main output, renamed last, is then untouched.
  There is no fsync: a power cut right after a run may lose the new content.
- An ``OSError`` of the block that names no file (a write on a full disk: ``ENOSPC``) becomes a
  :class:`UsvError` naming the first target, once the temporaries are removed.

Hand-written: the atomic-write libraries (``atomicwrites``, archived; ``atomik``) write one file
or one folder and leave signals alone.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import signal
import stat
import threading
from collections.abc import Callable, Iterable
from pathlib import Path
from types import CodeType

from usvtool.errors import UsvError

SIGNALS = (signal.SIGINT, signal.SIGTERM)  # installed in this order, restored in reverse

_CRITICAL: set[CodeType] = set()  # code during which a signal is held (see _on_signal)
_saved: list[dict] = []  # the handlers each active catch_signals replaced, outermost first
_pending: int | None = None  # the first signal held
#: The temporaries of active stagings (absolute paths), each with its target.
_handed_out: dict[str, Path] = {}


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM received inside :class:`catch_signals`; ``signum`` says which."""

    def __init__(self, signum: int):
        self.signum = signum
        super().__init__(signal.Signals(signum).name)


def check_output_path(path: str | os.PathLike, option: str = "-o") -> Path:
    """Refuse an output whose directory does not exist, before any work is done."""
    p = Path(path)
    label = f"{option} {p}" if option else str(p)
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise UsvError(f"{label}: directory {parent} does not exist")
    if p.is_dir():
        raise UsvError(f"{label}: is a directory")
    return p


def in_place(target: str | os.PathLike) -> bool:
    """Whether ``target`` is written where it is rather than staged: it exists and is not a
    regular file (``/dev/null``, ``/dev/stdout``, a FIFO, a terminal, or a link to one).
    Renaming a file onto it would replace the node itself (run as root, ``-o /dev/null``
    would remove the system's); such a target cannot be all-or-nothing anyway."""
    try:
        return not stat.S_ISREG(os.stat(target).st_mode)
    except (OSError, ValueError):
        return False


def check_outputs(outputs: Iterable[tuple[str, str | os.PathLike | None]]) -> None:
    """:func:`check_output_path` for each (option, path) given, and refuse one file named twice
    (but for a device or a pipe: :func:`in_place`)."""
    seen: dict[Path, str] = {}
    for option, path in outputs:
        if path is None:
            continue
        p = check_output_path(path, option)
        label = f"{option} {os.fspath(path)}" if option else os.fspath(path)
        if in_place(p):  # /dev/null for two outputs: both written there
            continue
        if p.resolve() in seen:
            raise UsvError(f"{label}: same file as {seen[p.resolve()]}")
        seen[p.resolve()] = label


def _critical(method: Callable) -> Callable:
    """Hold SIGINT and SIGTERM while ``method`` (or anything it calls) runs."""
    _CRITICAL.add(method.__code__)
    return method


def _on_signal(signum: int, frame) -> None:
    """Raise :class:`Interrupted` in the caller's code; hold the signal in this module's own.

    The test is on the stack, not on a flag the code would set: a signal can be handled on
    entry to any Python function (``__exit__`` included) before its first statement runs.
    """
    global _pending
    while frame is not None:
        if frame.f_code in _CRITICAL:
            if _pending is None:
                _pending = signum
            return
        frame = frame.f_back
    raise Interrupted(signum)


class catch_signals:  # lower case: used like contextlib.suppress
    """Make SIGINT and SIGTERM raise :class:`Interrupted` in the block (main thread only).

    A signal held while the handlers are being installed or restored is raised on exit, unless
    an interruption is already on its way.
    """

    _previous: dict | None = None

    @_critical
    def __enter__(self) -> None:
        if threading.current_thread() is threading.main_thread():
            previous = {s: signal.getsignal(s) for s in SIGNALS}
            for s in SIGNALS:
                if previous[s] != signal.SIG_IGN:  # an ignored signal stays ignored (nohup, &)
                    signal.signal(s, _on_signal)
            self._previous = previous
            _saved.append(previous)
            if _pending is not None:
                self.__exit__(None, None, None)  # restores the handlers and raises it

    @_critical
    def __exit__(self, exc_type, exc, tb) -> None:
        global _pending
        if self._previous is None:
            return
        _saved.pop()
        _restore(self._previous)
        self._previous = None
        signum, _pending = _pending, None
        if signum is not None and not isinstance(exc, KeyboardInterrupt):
            raise Interrupted(signum)


class staged(catch_signals):
    """``with staged(*targets) as temporaries:`` a temporary path per target (None for None),
    all renamed onto their targets when the block ends normally, all removed otherwise. A
    target that is not a regular file (:func:`in_place`) is handed back as it is.

    Refuses a target in a missing directory, a directory, and one file given twice. A target
    that is the temporary of an active staging is handed back as it is (nested staging).
    """

    def __init__(self, *targets: str | os.PathLike | None):
        check_outputs(("", t) for t in targets)
        self._targets = targets
        self._temps: dict[Path, Path] = {}  # target -> temporary not renamed yet, in order

    @_critical
    def __enter__(self) -> tuple[Path | None, ...]:
        super().__enter__()
        try:
            for t in self._targets:
                if t is not None and os.path.abspath(t) not in _handed_out and not in_place(t):
                    self._temps[Path(t)] = tmp = _new_temporary(Path(t))
                    _handed_out[os.path.abspath(tmp)] = Path(t)
            if self._previous is not None and _pending is not None:
                raise Interrupted(_pending)  # held while creating: the block does not start
        except BaseException as exc:
            self.__exit__(type(exc), exc, exc.__traceback__)
            raise
        temps = self._temps
        return tuple(None if t is None else temps.get(Path(t), Path(t)) for t in self._targets)

    @_critical
    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None and (self._previous is None or _pending is None):
                for target, tmp in reversed(list(self._temps.items())):  # the first one last
                    _rename(tmp, target)
                    _handed_out.pop(os.path.abspath(tmp), None)
                    del self._temps[target]
        finally:
            for tmp in self._temps.values():
                with contextlib.suppress(FileNotFoundError):
                    tmp.unlink()
                _handed_out.pop(os.path.abspath(tmp), None)
            self._temps.clear()
            super().__exit__(exc_type, exc, tb)  # a signal held: raised now
        if isinstance(exc, OSError) and exc.filename is None:  # a write's error names no file
            target = next(t for t in self._targets if t is not None)
            target = _handed_out.get(os.path.abspath(target), target)  # a nested staging's
            raise UsvError(f"{target}: cannot write it: {exc.strerror or exc}") from None


class atomic_path(staged):
    """:class:`staged` for one output: ``with atomic_path(path) as tmp:``."""

    def __init__(self, path: str | os.PathLike):
        super().__init__(path)

    @_critical
    def __enter__(self) -> Path:
        return super().__enter__()[0]


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def jsonable(value):
    """``json`` default for NumPy values (arrays, scalars) and anything else as a string."""
    return value.tolist() if hasattr(value, "tolist") else str(value)


def _restore(handlers: dict) -> None:
    for s in reversed(SIGNALS):  # SIGINT last: its previous handler may raise at once
        handler = handlers[s]
        signal.signal(s, signal.SIG_DFL if handler is None else handler)  # None: set from C


def _reset_in_child() -> None:
    """A forked worker (``ProcessPoolExecutor``) starts with the handlers found before any
    catch_signals: SIGTERM kills it quietly as before."""
    if _saved and threading.current_thread() is threading.main_thread():
        _restore(_saved[0])


os.register_at_fork(after_in_child=_reset_in_child)


def _new_temporary(target: Path) -> Path:
    """A new empty file beside ``target``: hidden, its suffix kept, mode 0666 less the umask.

    Not ``tempfile.mkstemp``: it makes the file 0600, and reading the umask means setting it,
    which races with other threads creating files.
    """
    while True:
        tmp = target.with_name(f".{target.name}.{secrets.token_hex(4)}{target.suffix}")
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
        except FileExistsError:
            continue
        except OSError as exc:
            raise UsvError(f"{target}: cannot write in {target.parent}: {exc.strerror}") from None
        return tmp


def _rename(tmp: Path, target: Path) -> None:
    try:
        os.replace(tmp, target)
    except OSError as exc:
        raise UsvError(f"{target}: cannot replace it: {exc.strerror}") from None
