"""The fixed-base modes table of `uplift modes` (and of `uplift analyze`'s tables): apart from
render.py so that `uplift modes` imports none of the result tables (their analysis, suite and
report modules)."""

from __future__ import annotations

from rich.markup import escape
from rich.table import Table

from ..display import label, show
from ..model.system import System, fixed_base_mode_rows
from .tables import add_columns, add_rows


def modes_table(system: System, n_modes: int | None = None, units: str = "si") -> Table:
    """Periods, w_n/w_1, m_n*/m_t (and cumulative), h_n* and h_n*/b (docs/theory.md sections 5, 6)."""
    table = Table(title=escape(f"Fixed-base modes (m_t = {show(system.total_mass, 'kg', units)} {label('kg', units)}, "
                               f"b = {show(system.half_width, 'm', units)} {label('m', units)})"))
    add_columns(table, ("mode", "T_n [s]", "w_n/w_1", "m_n*/m_t", "cumulative", f"h_n* [{label('m', units)}]",
                        "h_n*/b"))
    table.caption = _mat_mass_caption(system, units)
    return add_rows(table, (_mode_cells(row, units) for row in fixed_base_mode_rows(system)[:n_modes]))


def _mat_mass_caption(system: System, units: str) -> str | None:
    """With a mat mass: m_t includes it, and the m_n* add up to the building mass; else None."""
    if system.mat_mass <= 0.0:
        return None
    return escape(f"m_t includes the mat mass m_0 = {show(system.mat_mass, 'kg', units)} "
                  f"{label('kg', units)}: the m_n* add up to the building mass, "
                  f"{1 - system.mat_mass / system.total_mass:.4f} m_t")


def _mode_cells(row: dict, units: str) -> tuple[str, ...]:
    """A mode's row (model/system.fixed_base_mode_rows) in the display units."""
    return (str(row["mode"]), f"{row['period']:.4f}", f"{row['frequency_ratio']:.3f}",
            f"{row['effective_mass_ratio']:.4f}", f"{row['cumulative_mass_ratio']:.4f}",
            show(row["effective_height"], "m", units), f"{row['effective_height_over_b']:.3f}")
