"""usvtool.atomic: staged outputs appear together or not at all, also on SIGINT and SIGTERM."""

import os
import signal
import threading
from pathlib import Path

import pytest

from usvtool import atomic
from usvtool.atomic import Interrupted, atomic_path, catch_signals, staged, write_text
from usvtool.errors import UsvError


def listing(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


def umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@pytest.fixture(autouse=True)
def default_handlers():
    """Python's own SIGINT and SIGTERM handlers during each test, whatever the test run
    inherited (a run started in the background of a non-interactive shell ignores SIGINT)."""
    saved = {s: signal.getsignal(s) for s in atomic.SIGNALS}
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    yield
    for s, handler in saved.items():
        signal.signal(s, handler)


@pytest.fixture
def handlers():
    """The SIGINT and SIGTERM handlers before the test; the test must leave them so."""
    before = {s: signal.getsignal(s) for s in atomic.SIGNALS}
    yield before
    assert {s: signal.getsignal(s) for s in atomic.SIGNALS} == before


def test_outputs_appear_together_on_success(tmp_path, handlers):
    a, b = tmp_path / "grid.tif", tmp_path / "grid.png"
    with staged(a, None, b) as (ta, none, tb):
        assert none is None
        for tmp, target in ((ta, a), (tb, b)):
            # beside the target, hidden, its suffix kept, the usual mode of a new file
            assert tmp.parent == target.parent and tmp.name.startswith(f".{target.name}.")
            assert tmp.suffix == target.suffix and tmp.stat().st_size == 0
            assert tmp.stat().st_mode & 0o777 == 0o666 & ~umask()
        ta.write_bytes(b"grid")
        tb.write_bytes(b"png")
        assert listing(tmp_path) == sorted([ta.name, tb.name])  # no target before the end
        assert signal.getsignal(signal.SIGTERM) == atomic._on_signal
    assert listing(tmp_path) == ["grid.png", "grid.tif"]
    assert a.read_bytes() == b"grid" and b.read_bytes() == b"png"
    assert a.stat().st_mode & 0o777 == 0o666 & ~umask()


def test_the_first_target_is_renamed_last(tmp_path, monkeypatch):
    renamed = []
    real = os.replace
    monkeypatch.setattr(os, "replace", lambda s, d: (renamed.append(Path(d).name), real(s, d)))
    with staged(tmp_path / "main", tmp_path / "second", tmp_path / "third") as temps:
        for t in temps:
            t.write_text("x")
    assert renamed == ["third", "second", "main"]


def test_an_exception_leaves_no_target_and_no_temporary(tmp_path, handlers):
    with pytest.raises(ValueError, match="boom"):
        with staged(tmp_path / "a.tif", tmp_path / "b.png") as (ta, tb):
            ta.write_bytes(b"half")
            raise ValueError("boom")
    assert listing(tmp_path) == []


def test_an_existing_target_keeps_its_bytes_after_a_failed_run(tmp_path):
    old = tmp_path / "grid.tif"
    old.write_bytes(b"the old grid \x00\x01")
    with pytest.raises(UsvError):
        with staged(old, tmp_path / "grid.png") as (ta, tb):
            ta.write_bytes(b"new grid")
            raise UsvError("--preview-resolution: too fine")
    assert old.read_bytes() == b"the old grid \x00\x01"
    assert listing(tmp_path) == ["grid.tif"]


def test_one_file_named_twice_is_refused_before_anything_is_created(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "link.tif").symlink_to(tmp_path / "sub" / "a.tif")
    for other in (tmp_path / "sub" / "a.tif", tmp_path / "sub" / ".." / "sub" / "a.tif",
                  tmp_path / "link.tif"):
        with pytest.raises(UsvError, match="same file as"):
            staged(tmp_path / "sub" / "a.tif", other)
    assert listing(tmp_path / "sub") == []


def test_a_missing_directory_or_a_directory_is_refused(tmp_path):
    with pytest.raises(UsvError, match=r"nowhere/a.tif: directory .*nowhere does not exist"):
        staged(tmp_path / "ok.tif", tmp_path / "nowhere" / "a.tif")
    with pytest.raises(UsvError, match="is a directory"):
        staged(tmp_path)
    assert listing(tmp_path) == []


def test_an_unwritable_directory_is_one_error_and_removes_the_first_temporary(tmp_path,
                                                                             monkeypatch):
    ro = tmp_path / "ro"
    ro.mkdir()
    real = os.open

    def refuse_in_ro(path, flags, mode=0o777):  # as a directory without write permission
        if Path(path).parent == ro:
            raise PermissionError(13, "Permission denied", str(path))
        return real(path, flags, mode)

    monkeypatch.setattr(os, "open", refuse_in_ro)
    with pytest.raises(UsvError, match="ro/a.tif: cannot write in .*ro: Permission denied"):
        with staged(tmp_path / "b.tif", ro / "a.tif"):
            pytest.fail("the block ran")
    assert listing(tmp_path) == ["ro"] and listing(ro) == []


def test_a_writer_given_a_staged_temporary_writes_it_in_place(tmp_path):
    with staged(tmp_path / "a.txt") as (tmp,):
        with atomic_path(tmp) as inner:
            assert inner == tmp
            inner.write_text("a")
        write_text(tmp, "b")  # the writers' own atomic_path: no second temporary
        assert listing(tmp_path) == [tmp.name]
    assert (tmp_path / "a.txt").read_text() == "b" and listing(tmp_path) == ["a.txt"]
    assert not atomic._handed_out


def test_atomic_path_and_write_text_alone(tmp_path):
    write_text(tmp_path / "t.txt", "hello\n")
    assert (tmp_path / "t.txt").read_text() == "hello\n"
    with pytest.raises(RuntimeError), atomic_path(tmp_path / "t.txt") as tmp:
        tmp.write_text("half")
        raise RuntimeError
    assert (tmp_path / "t.txt").read_text() == "hello\n" and listing(tmp_path) == ["t.txt"]


# ---- signals: SIGINT and SIGTERM are exceptions in the block, held in the module's own code ----


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_inside_the_block_cleans_up(tmp_path, signum, handlers):
    old = tmp_path / "grid.tif"
    old.write_bytes(b"old")
    with pytest.raises(Interrupted) as caught:
        with staged(old, tmp_path / "grid.png") as (ta, tb):
            ta.write_bytes(b"new")
            os.kill(os.getpid(), signum)
            pytest.fail("the signal did not interrupt the block")
    assert caught.value.signum == signum and isinstance(caught.value, KeyboardInterrupt)
    assert old.read_bytes() == b"old" and listing(tmp_path) == ["grid.tif"]


def test_a_signal_during_the_renames_waits_until_all_are_done(tmp_path, monkeypatch, handlers):
    # the signal arrives in the first rename; without the hold it would be raised as that call
    # returns, and the second target would keep its old bytes
    real = os.replace

    def replace_and_signal(src, dst):
        real(src, dst)
        if Path(dst).name == "b":
            os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(os, "replace", replace_and_signal)
    (tmp_path / "a").write_text("old a")
    (tmp_path / "b").write_text("old b")
    with pytest.raises(Interrupted):
        with staged(tmp_path / "a", tmp_path / "b") as (ta, tb):
            ta.write_text("new a")
            tb.write_text("new b")
    assert (tmp_path / "a").read_text() == "new a" and (tmp_path / "b").read_text() == "new b"
    assert listing(tmp_path) == ["a", "b"]


def test_a_signal_while_creating_the_temporaries_stops_before_the_block(tmp_path, monkeypatch,
                                                                         handlers):
    real = os.open

    def open_and_signal(path, flags, mode=0o777):
        fd = real(path, flags, mode)
        os.kill(os.getpid(), signal.SIGINT)
        return fd

    monkeypatch.setattr(os, "open", open_and_signal)
    with pytest.raises(Interrupted) as caught:
        with staged(tmp_path / "a", tmp_path / "b"):
            pytest.fail("the block ran")
    assert caught.value.signum == signal.SIGINT
    assert listing(tmp_path) == []


def test_a_second_signal_during_the_cleanup_does_not_stop_it(tmp_path, monkeypatch, handlers):
    real = Path.unlink
    calls = []

    def unlink_and_signal(self, missing_ok=False):
        calls.append(self)
        if len(calls) == 1:
            os.kill(os.getpid(), signal.SIGTERM)
        real(self, missing_ok)

    monkeypatch.setattr(Path, "unlink", unlink_and_signal)
    with pytest.raises(Interrupted) as caught:  # the signal wins over the error it follows
        with staged(tmp_path / "a", tmp_path / "b", tmp_path / "c") as temps:
            for t in temps:
                t.write_text("x")
            raise UsvError("bad input")
    assert caught.value.signum == signal.SIGTERM and isinstance(caught.value.__context__, UsvError)
    assert len(calls) == 3 and listing(tmp_path) == []


def test_nested_catching_restores_each_level(handlers):
    with catch_signals():
        with staged():
            assert signal.getsignal(signal.SIGTERM) == atomic._on_signal
        assert signal.getsignal(signal.SIGTERM) == atomic._on_signal
    assert not atomic._saved


def test_an_ignored_signal_stays_ignored(handlers):
    previous = signal.signal(signal.SIGTERM, signal.SIG_IGN)
    try:
        with catch_signals():
            assert signal.getsignal(signal.SIGTERM) == signal.SIG_IGN
            assert signal.getsignal(signal.SIGINT) == atomic._on_signal
    finally:
        signal.signal(signal.SIGTERM, previous)


def test_other_threads_stage_without_touching_handlers(tmp_path, handlers):
    seen = []

    def work():
        with staged(tmp_path / "t.txt") as (tmp,):
            tmp.write_text("thread")
            seen.append(signal.getsignal(signal.SIGTERM))

    thread = threading.Thread(target=work)
    thread.start()
    thread.join()
    assert seen == [handlers[signal.SIGTERM]]
    assert (tmp_path / "t.txt").read_text() == "thread"


def test_a_forked_worker_gets_the_handlers_found_before(handlers):
    if handlers[signal.SIGTERM] != signal.SIG_DFL:
        pytest.skip("SIGTERM is not at its default here")
    read, write = os.pipe()
    with catch_signals():
        pid = os.fork()
        if pid == 0:  # the child: report its SIGTERM handler, leave at once
            os.write(write, b"dfl" if signal.getsignal(signal.SIGTERM) == signal.SIG_DFL else b"?")
            os._exit(0)
        os.close(write)
        assert os.read(read, 8) == b"dfl"
        os.waitpid(pid, 0)
    os.close(read)


def test_a_full_disk_inside_the_block_names_the_output_and_leaves_nothing(tmp_path):
    import errno

    (tmp_path / "a.csv").write_text("old")
    with pytest.raises(UsvError) as info:
        with staged(tmp_path / "a.csv", tmp_path / "b.json") as (a, b):
            a.write_text("new")
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))  # what a full disk's write says
    assert str(info.value) == f"{tmp_path / 'a.csv'}: cannot write it: No space left on device"
    assert listing(tmp_path) == ["a.csv"] and (tmp_path / "a.csv").read_text() == "old"
    # an error naming its own file is left as it is
    with pytest.raises(FileNotFoundError):
        with atomic_path(tmp_path / "c.txt"):
            open(tmp_path / "missing" / "x")


def test_a_full_disk_in_a_nested_staging_names_the_real_output(tmp_path):
    """A writer staging a path its caller's staging handed out names the caller's target."""
    import errno

    with pytest.raises(UsvError) as info:
        with staged(tmp_path / "trace.csv") as (outer,):
            with atomic_path(outer):  # write_trace given the staged temporary
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    assert str(info.value).startswith(f"{tmp_path / 'trace.csv'}: cannot write it: No space")
    assert listing(tmp_path) == []
