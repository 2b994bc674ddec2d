"""Atomic writes follow the umask (a replaced file keeps its permissions) and never replace an input."""

import os
import stat
from pathlib import Path

import pytest

from upliftcli.errors import InputError
from upliftcli.runtime.atomic import current_umask, refuse_inputs, write_set, write_text


def mode(path):
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture()
def umask():
    def set_mask(mask):
        os.umask(mask)
    saved = os.umask(0o022)
    yield set_mask
    os.umask(saved)


def test_new_files_follow_the_umask(tmp_path, umask):
    for mask, expected in ((0o022, 0o644), (0o002, 0o664), (0o077, 0o600)):
        umask(mask)
        assert current_umask() == mask
        path = tmp_path / f"out{mask:o}.txt"
        write_text(path, "x")
        assert mode(path) == expected and path.read_text() == "x"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary file left


def test_the_umask_is_read_the_same_without_proc(umask, monkeypatch):
    """Off Linux (no /proc/self/status) the umask is set and restored to be read: the same mask,
    left as it was."""
    from upliftcli.runtime import atomic

    for mask in (0o022, 0o027, 0o077):
        umask(mask)
        from_proc = current_umask()
        with monkeypatch.context() as without_proc:
            without_proc.setattr(atomic, "PROC_STATUS", str(Path("/nonexistent") / "self" / "status"))
            assert current_umask() == from_proc == mask
        assert os.umask(mask) == mask  # restored


def test_a_replaced_file_keeps_its_permissions(tmp_path, umask):
    umask(0o022)
    path = tmp_path / "table.csv"
    path.write_text("old")
    os.chmod(path, 0o640)
    write_text(path, "new")
    assert path.read_text() == "new" and mode(path) == 0o640


def test_outputs_may_not_replace_inputs(tmp_path):
    deck = tmp_path / "d" / "deck.toml"
    deck.parent.mkdir()
    deck.write_text("x")
    refuse_inputs([tmp_path / "out" / "deck.toml"], [deck], "--out")  # another folder: fine
    with pytest.raises(InputError, match=r"^--out: .*deck.toml: a path that does not replace an input of the run"):
        refuse_inputs([tmp_path / "d" / ".." / "d" / "deck.toml"], [deck], "--out")
    link = tmp_path / "link.toml"
    link.symlink_to(deck)
    with pytest.raises(InputError):  # the same file under another name
        refuse_inputs([link], [deck], "--histories")


def test_temporary_files_are_named_by_the_tool_and_its_pid(tmp_path, monkeypatch):
    from upliftcli.runtime import atomic

    seen = []
    original = atomic._finish
    monkeypatch.setattr(atomic, "_finish", lambda tmp, target: (seen.append(tmp.name), original(tmp, target)))
    write_text(tmp_path / "r.json", "{}")
    assert len(seen) == 1 and seen[0].startswith(f".r.json.uplift-tmp-{os.getpid()}-") and seen[0].endswith(".json")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.json"]


def test_results_are_flushed_to_the_disk_before_the_rename(tmp_path, monkeypatch):
    flushed = []
    original = os.fsync
    monkeypatch.setattr(os, "fsync", lambda fd: (flushed.append(os.readlink(f"/proc/self/fd/{fd}")), original(fd)))
    write_text(tmp_path / "a.csv", "x")
    assert len(flushed) == 2 and ".uplift-tmp-" in flushed[0] and flushed[1] == str(tmp_path)


@pytest.mark.skipif(os.geteuid() != 0, reason="giving a file another owner needs root")
def test_a_replaced_file_keeps_its_owner_and_group(tmp_path):
    path = tmp_path / "shared.csv"
    path.write_text("old")
    os.chown(path, 1234, 2345)
    write_text(path, "new")
    status = os.stat(path)
    assert (status.st_uid, status.st_gid) == (1234, 2345) and path.read_text() == "new"


def test_stale_temporary_files_of_dead_processes_are_removed(tmp_path):
    """A SIGKILL leaves the temporary file; the next write into its folder removes it once its
    process is gone; a live process's temporary file and other hidden files are kept."""
    import signal
    import subprocess
    import sys

    from upliftcli.runtime import atomic

    script = ("import sys, time; from upliftcli.runtime.atomic import atomic_path\n"
              "with atomic_path(sys.argv[1]) as tmp:\n"
              "    tmp.write_text('half'); print(tmp, flush=True); time.sleep(60)\n")
    child = subprocess.Popen([sys.executable, "-c", script, str(tmp_path / "fig.png")], stdout=subprocess.PIPE,
                             text=True)
    left = Path(child.stdout.readline().strip())
    assert left.exists() and left.name.startswith(".fig.png.uplift-tmp-")
    alive = tmp_path / f".x.csv.uplift-tmp-{os.getpid()}-abc123.csv"
    alive.write_text("mine")
    (tmp_path / ".hidden").write_text("not ours")
    assert atomic.remove_stale(tmp_path) == []  # the writer still runs
    child.send_signal(signal.SIGKILL)
    child.wait(timeout=30)
    assert left.exists()  # SIGKILL cleans nothing
    write_text(tmp_path / "next.csv", "x")  # a write into the folder, in a new process as the next run
    assert not left.exists()
    assert alive.exists() and (tmp_path / ".hidden").exists() and (tmp_path / "next.csv").read_text() == "x"


def test_sigterm_removes_the_temporary_file(tmp_path):
    import signal
    import subprocess
    import sys

    script = ("import os, signal, sys, time; from upliftcli.runtime.atomic import atomic_path\n"
              "from upliftcli.runtime.process import exit_on_stop_signals\n"
              "exit_on_stop_signals()\n"
              "with atomic_path(sys.argv[1]) as tmp:\n"
              "    tmp.write_text('half'); os.kill(os.getpid(), signal.SIGTERM); time.sleep(60)\n")
    done = subprocess.run([sys.executable, "-c", script, str(tmp_path / "fig.png")], timeout=60)
    assert done.returncode == 128 + signal.SIGTERM
    assert list(tmp_path.iterdir()) == []


def test_a_set_is_written_all_or_none(tmp_path, monkeypatch):
    """write_set: a failure while writing (a full disk) leaves no file of the set, no temporary
    file and no folder it created; the files it would replace are unchanged."""
    import errno

    from upliftcli.runtime import atomic
    from upliftcli.runtime.atomic import write_set

    out = tmp_path / "new" / "records"
    files = {out / f"r{k}.txt": f"record {k}" for k in range(4)}
    files[out / "manifest.json"] = "{}"
    calls = []
    original = atomic._finish

    def full_disk(tmp, target):
        calls.append(target)
        if len(calls) == 3:
            raise OSError(errno.ENOSPC, "No space left on device")
        original(tmp, target)

    monkeypatch.setattr(atomic, "_finish", full_disk)
    with pytest.raises(OSError, match="No space left"):
        write_set(files)
    assert list(tmp_path.iterdir()) == []  # nor the folders it created
    existing = tmp_path / "kept"
    existing.mkdir()
    (existing / "r0.txt").write_text("old")
    calls.clear()
    with pytest.raises(OSError):
        write_set({existing / "r0.txt": "new", existing / "r1.txt": "x", existing / "m.json": "{}"})
    assert sorted(p.name for p in existing.iterdir()) == ["r0.txt"] and (existing / "r0.txt").read_text() == "old"
    monkeypatch.setattr(atomic, "_finish", original)
    assert write_set(files) == list(files) and (out / "manifest.json").read_text() == "{}"
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in files)


@pytest.mark.parametrize("write", [lambda p: write_text(p, "new"), lambda p: write_set({p: "new"})])
def test_an_atomic_write_onto_a_symlink_is_refused(tmp_path, write):
    # issue 38 item 2: outputs are never followed through (or put in place of) a symbolic link
    outside = tmp_path / "outside.txt"
    outside.write_text("keep")
    link = tmp_path / "out" / "result.json"
    link.parent.mkdir()
    link.symlink_to(outside)
    with pytest.raises(InputError, match=r"^--out: .*result\.json: a path that is not a symbolic link"):
        write(link)
    assert outside.read_text() == "keep" and link.is_symlink()
    assert os.listdir(link.parent) == ["result.json"]
