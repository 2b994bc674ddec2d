"""ASCE 7-22 spectrum levels: design or MCE_R, and the MCE_R target of a chapter 16 suite."""

from __future__ import annotations

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.motion.design_spectra import ASCE7MultiPeriodSpectrum, ASCE7Spectrum, EC8Spectrum, from_mapping
from upliftcli.motion.levels import MCE_R_FACTOR, suite_target

PERIODS = np.array([0.0, 0.1, 0.5, 1.0, 3.0])


def test_design_level_targets_are_raised_to_mce_r():
    design = ASCE7Spectrum(1.0, 0.6, 8.0)
    target = suite_target(design, "asce7-22")
    assert MCE_R_FACTOR == 1.5 and target.level == "mce_r"
    np.testing.assert_allclose(target.sa(PERIODS, 0.05), 1.5 * design.sa(PERIODS, 0.05), rtol=1e-15)
    np.testing.assert_allclose(target.sa(PERIODS, 0.1), 1.5 * design.sa(PERIODS, 0.1), rtol=1e-15)
    assert target.name.startswith("MCE_R = 1.5 x ASCE 7-22 two-period (S_DS = 1 g")
    assert "16.2.1" in target.name and target.period_range == design.period_range
    assert target.permitted_procedures == ("elf",)  # the two-period spectrum's warning is kept


def test_mce_r_level_other_codes_and_rules_are_their_own_targets():
    mce = from_mapping({"type": "asce7", "sds": 1.5, "sd1": 0.9, "tl": 8.0, "level": "mce_r"}, "deck.toml")
    assert suite_target(mce, "asce7-22") is mce and mce.name.startswith("ASCE 7-22 two-period MCE_R (S_MS = 1.5 g")
    design = ASCE7Spectrum(1.0, 0.6, 8.0)
    assert suite_target(design, "mean") is design  # no code: the spectrum as given
    ec8 = EC8Spectrum(0.3, "B")
    assert suite_target(ec8, "ec8") is ec8 and suite_target(ec8, "asce7-22") is ec8
    multi = from_mapping({"type": "asce7-multiperiod", "sa": [0.5] * 22, "level": "mce_r"}, "deck.toml")
    assert isinstance(multi, ASCE7MultiPeriodSpectrum) and "MCE_R (S_MS" in multi.name


def test_a_bad_level_names_the_key():
    # the one field checker (motion/spectrum_fields.SPECTRUM_FIELDS declares `level`)
    with pytest.raises(InputError, match=r"deck\.toml: spectrum\.level: one of design, mce_r, got 'MCE'"):
        from_mapping({"type": "asce7", "sds": 1.0, "sd1": 0.6, "tl": 8.0, "level": "MCE"}, "deck.toml")
    with pytest.raises(InputError, match=r"spectrum\.level: a key of a ec8 spectrum|spectrum\.level"):
        from_mapping({"type": "ec8", "ag": 0.3, "ground_type": "B", "level": "design"}, "deck.toml")
