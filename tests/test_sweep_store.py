"""sweep/store.py: the rows file (torn lines, fingerprints checked on --resume) and the lock on the
output stem."""

import json

import pytest
from sweep_cases import EXAMPLE, ROOT, SHORT

from upliftcli.errors import InputError
from upliftcli.sweep import store as store_module
from upliftcli.sweep.executors import SerialExecutor
from upliftcli.sweep.plan import (
    plan_sweep,
)
from upliftcli.sweep.run import run_sweep
from upliftcli.sweep.store import RowStore

# ----------------------------------------------------------------------------- parsing


def test_row_store_appends_and_ignores_a_torn_line(tmp_path):
    store = RowStore(tmp_path / "rows.jsonl")
    store.open(fresh=True)
    store.append({"key": "a", "status": "ok", "x": 1.0})
    store.append({"key": "b", "status": "failed", "message": "boom"})
    store.close()
    with open(store.path, "a") as handle:
        handle.write('{"key": "c", "sta')  # killed while writing
    assert set(store.read()) == {"a", "b"}
    store.open(fresh=False)
    store.append({"key": "c", "status": "ok"})
    store.close()
    lines = store.path.read_text().splitlines()
    assert [json.loads(line)["key"] for line in lines] == ["a", "b", "c"]


def _deck_with_own_record(tmp_path):
    record = tmp_path / "rec.txt"
    record.write_bytes((ROOT / "records" / "elcentro_1940_ns_chopra.txt").read_bytes())
    deck = tmp_path / "deck.toml"
    deck.write_text(EXAMPLE.read_text().replace("../records/elcentro_1940_ns_chopra.txt", "rec.txt"))
    return deck, record


def test_resume_refuses_rows_of_a_changed_record_or_reruns_them(tmp_path):
    deck, record = _deck_with_own_record(tmp_path)
    store = RowStore(tmp_path / "rows.jsonl")
    plan = plan_sweep(deck, SHORT, ["building.period=0.5,1"], ["simplified"], ["rigid"])
    first = run_sweep(plan, SerialExecutor(), store)
    header = json.loads(store.path.read_text().splitlines()[0])["run"]
    assert header["fingerprint"] == plan.fingerprint and header["records"] == plan.records
    lines = record.read_text().splitlines()  # double the record
    record.write_text("\n".join(line if line.startswith("#") else f"{line.split()[0]} {2 * float(line.split()[1])}"
                                for line in lines) + "\n")
    doubled = plan_sweep(deck, SHORT, ["building.period=0.5,1"], ["simplified"], ["rigid"])
    assert [c.key for c in doubled.cases] == [c.key for c in plan.cases] and doubled.fingerprint != plan.fingerprint
    with pytest.raises(InputError, match=r"^--resume: .*rows.jsonl: rows computed from the inputs of this run; 2 rows "
                                         r"were computed from another content of the record .*rec.txt \(its SHA-256 "
                                         r"changed\): pass --rerun-stale"):
        run_sweep(doubled, SerialExecutor(), store, resume=True)
    again = run_sweep(doubled, SerialExecutor(), store, resume=True, rerun_stale=True)
    assert again.reused == 0
    for old, new in zip(first.rows, again.rows, strict=True):
        assert new["base_shear_N"] == pytest.approx(2 * old["base_shear_N"], rel=1e-12)  # linear: twice the record
    assert run_sweep(doubled, SerialExecutor(), store, resume=True).reused == 2  # now they match


def test_resume_refuses_rows_without_a_fingerprint(small_plan, serial_rows, tmp_path):
    path = tmp_path / "rows.jsonl"
    path.write_text("".join(json.dumps(row) + "\n" for row in serial_rows[:3]))  # as older versions wrote them
    with pytest.raises(InputError, match="3 rows were computed by a run that recorded no fingerprint"):
        run_sweep(small_plan, SerialExecutor(), RowStore(path), resume=True)


def test_stem_lock_refuses_a_second_sweep(tmp_path):
    from upliftcli.sweep.store import stem_lock

    out = tmp_path / "out"
    with stem_lock(out, "deck.sweep"):
        assert (out / ".deck.sweep.lock").exists()
        with pytest.raises(InputError, match=r"^--out: .*deck.sweep: an output stem no other sweep is writing"), \
                stem_lock(out, "deck.sweep"):
            pass
        with stem_lock(out, "other.sweep"):  # another stem: fine
            pass
    assert not out.exists()  # created for the lock, left empty: removed
    out.mkdir()
    with stem_lock(out, "deck.sweep"):
        pass
    assert out.exists() and list(out.iterdir()) == []


def test_rows_are_flushed_at_once_and_fsynced_at_most_every_interval(tmp_path, monkeypatch):
    synced = []
    real_fsync = store_module.os.fsync
    monkeypatch.setattr(store_module.os, "fsync", lambda fd: synced.append(fd) or real_fsync(fd))
    clock = [100.0]
    monkeypatch.setattr(store_module.time, "monotonic", lambda: clock[0])
    store = RowStore(tmp_path / "rows.jsonl")
    store.open(fresh=True)
    for k in range(50):  # 50 rows within 0.49 s: one fsync (the first)
        store.append({"key": str(k), "status": "ok"})
        assert len(store.path.read_text().splitlines()) == k + 1  # another reader sees it at once
        clock[0] += 0.01
    assert len(synced) == 1
    clock[0] += store_module.FSYNC_SECONDS
    store.append({"key": "late", "status": "ok"})
    assert len(synced) == 2
    store.close()
    assert len(synced) == 3  # and at close
    assert [json.loads(line)["key"] for line in store.path.read_text().splitlines()][-1] == "late"


@pytest.mark.parametrize("fresh", [True, False])
def test_the_rows_file_is_opened_without_following_a_symlink(tmp_path, fresh, monkeypatch):
    # a link put there after the check (refuse_symlink) is still not followed: O_NOFOLLOW
    outside = tmp_path / "outside.txt"
    outside.write_text("keep\n")
    store = RowStore(tmp_path / "rows.jsonl")
    store.path.symlink_to(outside)
    monkeypatch.setattr(store_module, "refuse_symlink", lambda path: None)
    with pytest.raises(OSError):
        store.open(fresh=fresh)
    assert outside.read_text() == "keep\n"


# ----------------------------------------------------------------------------- read back (issue 38 item 5)

def test_the_rows_are_read_back_from_the_file_in_case_order(small_plan, serial_rows, tmp_path):
    """keep_rows=False: the outcome keeps the cases' keys, not their rows; stored_rows reads them back,
    the last row of each case, in case order, each time it is iterated: the rows kept in memory."""
    from upliftcli.sweep.run import stored_rows

    store = RowStore(tmp_path / "rows.jsonl")
    outcome = run_sweep(small_plan, SerialExecutor(), store, keep_rows=False)
    assert outcome.rows == [] and outcome.finished == len(serial_rows) == len(small_plan.cases)
    rows = stored_rows(small_plan, store, outcome)
    assert list(rows) == serial_rows and list(rows) == serial_rows
    scanned = store.scan()
    assert len(scanned) == len(serial_rows) and {e.status for e in scanned.values()} == {"ok"}
    assert store.fields() == {"foundation.frequency_ratio", "building.period"}


def test_a_later_row_of_a_case_is_the_one_read_back(tmp_path):
    """A case run again (crashed, then ok) has its last row read back; a key not asked for is not."""
    store = RowStore(tmp_path / "rows.jsonl")
    store.open(fresh=True)
    store.append({"key": "a", "case": 0, "status": "crashed", "message": "died"}, "f1")
    store.append({"key": "b", "case": 1, "status": "ok", "x": 2.0}, "f1")
    store.append({"key": "a", "case": 0, "status": "ok", "x": 1.0}, "f2")
    store.close()
    assert list(store.rows_of(["a", "b", "z"])) == [{"key": "a", "case": 0, "status": "ok", "x": 1.0},
                                                     {"key": "b", "case": 1, "status": "ok", "x": 2.0}]
    assert store.scan()["a"].fingerprint == "f2" and list(store.scan()) == ["a", "b"]


def test_a_torn_line_after_a_long_file_is_cut_off(tmp_path, monkeypatch):
    """The torn last line is found reading backwards a block at a time (the file is never read whole)."""
    monkeypatch.setattr(store_module, "TAIL_BYTES", 16)
    store = RowStore(tmp_path / "rows.jsonl")
    store.open(fresh=True)
    for k in range(20):
        store.append({"key": f"k{k}", "status": "ok", "text": "x" * 40})
    store.close()
    whole = store.path.read_bytes()
    with open(store.path, "ab") as handle:
        handle.write(b'{"key": "torn", "status": "ok", "text": "' + b"y" * 100)
    store.open(fresh=False)
    store.close()
    assert store.path.read_bytes() == whole
    store.path.write_bytes(b'{"key": "only torn"')
    store.open(fresh=False)
    store.close()
    assert store.path.read_bytes() == b""
