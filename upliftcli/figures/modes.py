"""Fixed-base mode shapes (`uplift modes --plot`): one panel per mode, titled with T_n and
m_n*/m_t (docs/theory.md section 5.1, paper Eq. 9)."""

from __future__ import annotations

import numpy as np

from ..model.system import System
from .analysis import elevation_label
from .spec import FigureSpec, Line, Panel, Series
from .style import SUPPORT_COLORS

MAX_MODES = 6  # panels drawn at most (the rest of the table is in `uplift modes`)
COLUMNS = 3  # panels a row (six print on A4 with text of 7 pt at least)


def normalized_shape(shapes: np.ndarray, mode: int) -> np.ndarray:
    """phi_n scaled to a largest |phi_jn| of 1 with a positive roof value [-]."""
    phi = np.asarray(shapes[:, mode], dtype=float)
    phi = phi / np.max(np.abs(phi))
    return -phi if phi[-1] < 0.0 else phi


def mode_shape_figure(system: System, n_modes: int | None = None, title: str = "", units: str = "si"
                      ) -> FigureSpec:
    """Shapes of the first n_modes (at most MAX_MODES) fixed-base modes against the elevation
    (display units), zero at the mat, in the rigid base's colour; each panel names T_n [s] and
    m_n*/m_t [-] on two lines of its title."""
    from ..display import unit

    modes = system.modes
    count = min(n_modes or modes.n_modes, modes.n_modes, MAX_MODES)
    levels = np.concatenate(([0.0], system.building.heights)) * unit("m", units).factor
    panels = [_mode_panel(system, n, levels, units) for n in range(count)]
    return FigureSpec(title or "Fixed-base mode shapes", "", panels, columns=min(count, COLUMNS) or 1,
                      panel_size=(2.3, 3.0), sharey=True)


def _mode_panel(system: System, n: int, levels: np.ndarray, units: str) -> Panel:
    """Mode n + 1 against the levels (plotted units), titled with T_n and m_n*/m_t."""
    modes = system.modes
    phi = np.concatenate(([0.0], normalized_shape(modes.shapes, n)))
    ratio = modes.effective_mass[n] / system.total_mass
    return Panel(f"mode {n + 1}: T_{n + 1} = {modes.periods[n]:.4g} s\nm_{n + 1}*/m_t = {ratio:.3f}",
                 elevation_label(units), [Series(f"mode {n + 1}", phi, levels, "-", SUPPORT_COLORS["rigid"], 1.8, "o")],
                 [Line(0.0, "", "x", "-", "#999999")], xlabel="phi_jn / max |phi_jn| [-]", legend=False, ymin=0.0)
