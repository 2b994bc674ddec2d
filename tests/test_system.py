"""The whole system (model/system.py): the fixed-base mode rows every table prints, against the
paper's table (docs/theory.md section 6) and the mass identity with a mat."""

import pytest
from paper_example import paper_system

PAPER_FREQUENCY_RATIOS = [1.0, 2.98, 4.89, 6.69, 8.34]
PAPER_MASS_RATIOS = [0.844, 0.091, 0.031, 0.014, 0.007]
PAPER_SLENDERNESS = [10.0, -3.4, 2.0, -1.5, 1.2]


def test_mode_rows_give_the_papers_table():
    from upliftcli.model.system import MODE_ROW_UNITS, fixed_base_mode_rows

    rows = fixed_base_mode_rows(paper_system())
    assert len(rows) == 10 and set(rows[0]) == set(MODE_ROW_UNITS)
    for row, frequency, mass, slenderness in zip(rows, PAPER_FREQUENCY_RATIOS, PAPER_MASS_RATIOS, PAPER_SLENDERNESS,
                                                 strict=False):
        assert row["frequency_ratio"] == pytest.approx(frequency, abs=0.01)
        assert row["effective_mass_ratio"] == pytest.approx(mass, abs=0.005)
        assert row["effective_height_over_b"] == pytest.approx(slenderness, abs=0.05)
    assert rows[0]["period"] == pytest.approx(0.5, rel=1e-12) and rows[0]["damping"] == 0.05  # 5 % in every mode
    assert rows[-1]["cumulative_mass_ratio"] == pytest.approx(1.0, rel=1e-12)  # sum of m_n* = building mass


def test_with_a_mat_the_effective_masses_add_up_to_the_building_mass():
    from upliftcli.model.system import fixed_base_mode_rows

    system = paper_system(mat_mass=0.25 * 3.5e6)
    rows = fixed_base_mode_rows(system)
    assert rows[-1]["cumulative_mass_ratio"] == pytest.approx(1 - system.mat_mass / system.total_mass, rel=1e-12)
    running = 0.0
    for row in rows:
        running += row["effective_mass_ratio"]
        assert row["cumulative_mass_ratio"] == pytest.approx(running, rel=1e-12)
