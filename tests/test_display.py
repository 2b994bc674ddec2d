"""Display units (upliftcli.display): the one table of how values are shown, SI and US, checked
against conversion factors from their definitions (1 lbf = 0.45359237 kg x 9.80665 m/s^2,
1 in = 25.4 mm exactly) and published values."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from upliftcli import display
from upliftcli.display import DISPLAY, SUMMARY, heading, intermediate_kind, label, number, show
from upliftcli.engines.quantities import COMPARED, INTERMEDIATES, QUANTITIES, ROCKING, display_kind

LBF = 0.45359237 * 9.80665  # N
KIP, INCH, FOOT = 1000 * LBF, 0.0254, 0.3048

#: SI value of one US display unit, from the definitions (and a published value, for the eye)
ONE_US_UNIT = {
    "N": KIP,                              # 4.448222 kN
    "N m": KIP * FOOT,                     # 1.355818 kN m
    "mm": INCH,
    "m": FOOT,
    "N/m": KIP / INCH,                     # 175.1268 kN/m
    "N/m^2": KIP / INCH**2,
    "N s/m": KIP / INCH,
    "N s/m^2": KIP / INCH**2,
    "N m/rad": KIP * FOOT,
    "N m s/rad": KIP * FOOT,
    "kg": KIP / INCH,                      # kip s^2/in = 175126.8 kg
    "kg m": KIP,                           # kip s^2 = kip / (in/s^2) x in
    "kg m^2": KIP * FOOT,                  # kip ft s^2
    "kg/m^3": 0.45359237 / FOOT**3,        # 16.01846 kg/m^3
    "Pa": KIP / INCH**2,                   # ksi = 6.894757 MPa
    "J": KIP * FOOT,
    "m/s": FOOT,
    "m/s^2": INCH,
    "mm/s": INCH,                          # in/s: PGV, S_v
}


@pytest.mark.parametrize("kind", sorted(ONE_US_UNIT))
def test_us_units_from_their_definitions(kind):
    us = DISPLAY[kind][1]
    assert ONE_US_UNIT[kind] * us.factor == pytest.approx(1.0, rel=1e-12)


def test_published_values():
    assert abs(KIP - 4448.2216) < 1e-4  # N, the published value
    assert show(KIP / INCH, "N/m") == "175.13"  # kN/m of one kip/in
    assert show(6.894757e6, "Pa", "us") == "1" and show(6.894757e6, "Pa") == "6.8948"  # ksi, MPa
    assert show(16.01846, "kg/m^3", "us") == "1"


def test_si_is_kilo_newtons_millimetres_and_g():
    assert [label(kind) for kind in ("N", "N m", "mm", "m", "g", "%", "N/m", "N m/rad", "Pa")] == \
        ["kN", "kN m", "mm", "m", "g", "%", "kN/m", "kN m/rad", "MPa"]
    assert [label(kind, "us") for kind in ("N", "N m", "mm", "m", "g", "%", "N/m", "N m/rad", "Pa")] == \
        ["kip", "kip ft", "in", "ft", "g", "%", "kip/in", "kip ft/rad", "ksi"]
    assert show(26861.4e3, "N") == "26861.4" and show(9.80665, "g") == "1.0000" and show(0.0031, "%") == "0.310"
    assert show(2.686e7, "N/m") == "26860"  # a stiffness, plain (it was 2.686e+07 N/m)
    assert label("s") == "s" and show(0.5, "s") == "0.5"  # a kind without a display unit: as it is
    # a velocity (PGV, S_v) in mm/s, or in/s; stated with its unit
    assert display.stated(0.3608, "mm/s") == "360.8 mm/s" and display.stated(0.3608, "mm/s", "us") == "14.20 in/s"
    assert display.stated(1.724, "m/s", "us", ".4g") == f"{1.724 / FOOT:.4g} ft/s"


def test_every_quantity_and_intermediate_has_a_display_unit():
    for quantity in QUANTITIES.values():
        assert quantity.display in DISPLAY, quantity.name
        assert quantity.heading("us").endswith(f"[{label(quantity.display, 'us')}]")
    for name, (unit, _) in INTERMEDIATES.items():
        kind = intermediate_kind(name, unit)
        assert kind in DISPLAY or unit in ("-", "s", "rad", "rad/s"), name
    assert intermediate_kind("Sa_n", "m/s^2") == "g" and intermediate_kind("max_uplift_left", "m") == "mm"
    assert display_kind("max_drift_ratio") == "%" and display_kind("roof_displacement") == "mm"
    assert display_kind("base_shear") == "N" and display_kind("base_shear_coefficient") == "coefficient"
    # the improved procedure's mat motion and impacts, and xi1bar/xi1 (issue 25), shown as the check shows them
    assert [intermediate_kind(name, INTERMEDIATES[name][0]) for name in (
        "max_uplift", "max_rotation", "impact_acceleration", "xi1bar/xi1")] == ["mm", "mrad", "g", "coefficient"]
    assert show(0.0123, "mrad") == "12.300" and label("mrad", "us") == "mrad"


def test_every_compared_value_and_rocking_quantity_has_a_display_unit():
    """The compared values of the accuracy check (quantities.COMPARED) and the rocking quantities
    (quantities.ROCKING) are shown in display units, SI and US."""
    for compared in COMPARED.values():
        assert compared.display in DISPLAY and display_kind(compared.name) == compared.display, compared.name
    assert [c.heading() for c in COMPARED.values()] == [
        "V_b [kN]", "M_b [kN m]", "largest drift ratio [%]", "roof displacement [mm]",
        "largest floor acceleration [g]", "edge uplift [mm]", "mat rotation [mrad]"]
    assert COMPARED["max_uplift"].heading("us") == "edge uplift [in]"
    for quantity in ROCKING.values():
        assert quantity.display in DISPLAY or quantity.display == "-", quantity.name
        assert display_kind(quantity.name) == quantity.display


def test_number_is_plain_without_exponent_for_ordinary_magnitudes():
    assert number(1650700000.0) == "1650700000"  # I_b in kg m^2 (was 1.6507e+09)
    assert number(0.000123456) == "0.00012346" and number(1.5e-7) == "1.5e-07"
    assert number(2.0) == "2" and number(np.float64(3.25)) == "3.25" and number(7) == "7"
    assert number(True) == "yes" and number([1.0, 2.5]) == "1, 2.5" and number(math.nan) == "-"
    assert number(None) == "-" and number("text") == "text"
    assert show([1e3, 2e3], "N") == "1.0, 2.0" and show(None, "N") == "-" and show(math.inf, "N") == "-"


def test_a_value_of_round_off_size_below_zero_is_shown_as_zero():
    """A residual settlement of -1e-19 m is 0 to the display's decimals: '0.00 mm', never
    '-0.00' (display.unsigned_zero); a value that shows a digit keeps its sign."""
    assert show(-1e-19, "mm") == "0.00" and show(-1e-19, "mm", "us") == "0.000"
    assert show(-0.0, "mrad") == "0.000" and show(-4e-6, "mm") == "0.00" and show(-6e-6, "mm") == "-0.01"
    assert show(-2.5e-3, "mm") == "-2.50" and number(-0.0) == "0" and number(-1e-20) == "-1e-20"
    assert display.stated(-1e-19, "mm") == "0.00 mm" and display.stated(-1e-19, "mm", spec=".1f") == "0.0 mm"
    assert display.unsigned_zero("-0.000%") == "0.000%" and display.unsigned_zero("-") == "-"


def replace_yielded(result, yielded):
    return SimpleNamespace(**{**vars(result), "yielded": yielded})


def test_the_display_record_of_the_scalar_results():
    result = SimpleNamespace(base_shear=7293.9e3, base_shear_coefficient=0.21254, base_moment=100592.4e3,
                             base_moment_coefficient=0.1252, critical_base_shear=3432.3e3,
                             critical_base_moment=80376.9e3, critical_coefficient=0.1, uplift=True)
    assert [column.heading() for column in SUMMARY.values()] == [
        "V_b [kN]", "V_b/W", "M_b [kN m]", "M_b/(W h_1*)", "V_c [kN]", "M_c [kN m]", "b/h_1*", "uplift", "yielded"]
    assert [column.cell(replace_yielded(result, None)) for column in SUMMARY.values()] == [
        "7293.9", "0.2125", "100592.4", "0.1252", "3432.3", "80376.9", "0.1000", "yes", "-"]
    assert SUMMARY["yielded"].cell(replace_yielded(result, True)) == "yes"
    assert SUMMARY["yielded"].cell(replace_yielded(result, False)) == "no"
    assert display.verdicts([result]) == ("uplift",)  # no capacity: no yielded column
    assert display.verdicts([result, replace_yielded(result, False)]) == ("uplift", "yielded")
    assert display.verdicts([SimpleNamespace(intermediates={"Q_y": 1e6})]) == ("uplift", "yielded")
    assert SUMMARY["base_shear"].heading("us") == "V_b [kip]"
    assert SUMMARY["base_shear"].cell(result, "us") == f"{7293.9e3 / KIP:.1f}"
    assert SUMMARY["critical_base_shear"].stated(result) == "V_c = 3432.3 kN"
    assert SUMMARY["critical_coefficient"].stated(result) == "b/h_1* = 0.1000"
    assert heading("elevation", "m", "us") == "elevation [ft]" and heading("V_b/W", "coefficient") == "V_b/W"
