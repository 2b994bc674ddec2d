"""engines/exact/digest.py: a run stepped in chunks gives the results of one pass."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from paper_example import paper_system

from upliftcli.engines.exact import engine as exact
from upliftcli.engines.exact import stepping
from upliftcli.engines.options import ExactOptions
from upliftcli.motion.records import read_record
from upliftcli.runtime import backend

RECORD = Path(__file__).resolve().parents[1] / "records" / "elcentro_1940_ns_chopra.txt"


def _round_off() -> float:
    """0 where the compiled loops run: they step and sum alike whatever the chunks; 1e-9 on the
    numpy twins, whose block recurrence restarts and whose BLAS products change size with each
    chunk (the tolerance of tests/test_backend_agreement.py)."""
    compiled = backend.choice() != "numpy" and len(backend.built()) == len(backend.EXTENSIONS)
    return 0.0 if compiled else 1e-9


@pytest.mark.parametrize("support", ["rigid", "uplift"])
def test_chunks_fold_to_the_single_pass(monkeypatch, support):
    record = read_record(RECORD)
    short = SimpleNamespace(acceleration=record.acceleration[:500], dt=record.dt)
    system = paper_system(0.3)
    options = ExactOptions(histories=True)
    whole = exact.analyze(system, short, support, options)
    monkeypatch.setattr(stepping, "CHUNK_SAMPLES", 600)  # several chunks, each with 256 samples kept free
    chunked = exact.analyze(system, short, support, options)
    assert chunked.intermediates["samples"] == whole.intermediates["samples"] > 1400  # 3 chunks or more
    assert chunked.intermediates["transitions"] == whole.intermediates["transitions"]
    twins = _round_off()
    for name, values in whole.peaks.items():
        np.testing.assert_allclose(chunked.peaks[name], values, rtol=twins, atol=0.0, err_msg=name)
        np.testing.assert_allclose(chunked.times[name], whole.times[name], rtol=max(twins, 1e-12), err_msg=name)
    for name, value in whole.details["uplift_summary"].items():
        assert chunked.details["uplift_summary"][name] == pytest.approx(value, rel=max(twins, 1e-12)), name
    scale = abs(whole.details["energy"]["input"])  # sums in another order: round-off of the work done
    for name, value in whole.details["energy"].items():
        if name != "relative_residual":
            assert chunked.details["energy"][name] == pytest.approx(value, abs=max(twins, 1e-12) * scale), name
    for name, values in whole.histories.items():  # matrix products of other sizes: 1 ulp
        np.testing.assert_allclose(chunked.histories[name], values, rtol=max(twins, 1e-14),
                                   atol=twins * np.abs(values).max(initial=0.0) or 1e-300, err_msg=name)
