"""The rows file of a sweep (upliftcli.sweep.store): every row readable as soon as it is
appended (flushed), fsynced at most FSYNC_SECONDS later and at close, not once per row."""

from __future__ import annotations

import json

from upliftcli.sweep import store as store_module
from upliftcli.sweep.store import RowStore


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
