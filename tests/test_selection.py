"""Selection of recorded motions: the fits and misfits in closed form, the per-event cap, the
factor limits, each error naming its option."""

from __future__ import annotations

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.motion.selection import check_factors, fits, select

TARGET = np.array([1.0, 2.0, 4.0, 2.0, 1.0])


def test_fits_and_misfits_in_closed_form():
    # proportional spectra: the fit is the ratio, the misfit 0; a shape off by exp(+-0.1): RMS 0.1
    shape = np.exp(np.array([0.1, -0.1, 0.1, -0.1, 0.0]) * np.sqrt(5 / 4))
    spectra = np.vstack((0.5 * TARGET, 2.0 * TARGET, 0.25 * TARGET * shape))
    factors, misfits = fits(spectra, TARGET)
    np.testing.assert_allclose(factors, [2.0, 0.5, 4.0], rtol=1e-12)
    np.testing.assert_allclose(misfits, [0.0, 0.0, 0.1], atol=1e-12)
    # a fit beyond the limits is clipped, and the misfit is that of the clipped factor
    factors, misfits = fits(0.1 * TARGET, TARGET, (0.25, 4.0))
    assert factors[0] == 4.0 and misfits[0] == pytest.approx(np.log(2.5))


def test_best_first_and_at_most_per_event():
    spectra = np.vstack([TARGET * np.exp(0.05 * k * np.array([1, -1, 1, -1, 0])) for k in range(6)])
    events = ["A", "A", "A", "B", "B", "C"]
    choice = select(spectra, TARGET, events, 4, per_event=2)
    assert choice.indices == (0, 1, 3, 4)  # the third of A is skipped for B's
    assert list(choice.misfits) == sorted(choice.misfits)
    with pytest.raises(InputError, match=r"--count: at most 5 records from 3 earthquakes with --per-event 2 "
                                          r"\(6 usable candidates\), got --count 6"):
        select(spectra, TARGET, events, 6, per_event=2)


def test_factor_limits_name_their_option():
    check_factors([0.5, 3.9], (0.25, 4.0), 0.9)
    with pytest.raises(InputError, match=r"--factor-max: .* the chosen records need up to 4\.5"):
        check_factors([0.5, 4.5], (0.25, 4.0), 0.9)
    with pytest.raises(InputError, match=r"--factor-min: .* the chosen records need 0\.2"):
        check_factors([0.2, 1.0], (0.25, 4.0), 0.9)
