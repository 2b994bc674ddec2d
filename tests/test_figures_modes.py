"""Mode-shape figure data (upliftcli.figures.modes) against an independent eigen-solution."""

import numpy as np
import pytest
from paper_example import paper_system

from upliftcli.figures.modes import MAX_MODES, mode_shape_figure


def test_mode_shapes_titles_and_values():
    system = paper_system(period=0.5, mat_mass=0.5 * 3.5e6)
    spec = mode_shape_figure(system)
    assert len(spec.panels) == MAX_MODES and spec.sharey
    building = system.building
    # independent eigen-solution of K phi = w^2 M phi (numpy, not scipy's eigh)
    m_half = np.diag(1 / np.sqrt(building.masses))
    w2, vectors = np.linalg.eigh(m_half @ building.stiffness @ m_half)
    shapes = m_half @ vectors
    periods = 2 * np.pi / np.sqrt(w2)
    levels = np.concatenate(([0.0], building.heights))
    for n, panel in enumerate(spec.panels):
        (series,) = panel.series
        np.testing.assert_array_equal(series.y, levels)
        phi = shapes[:, n] / np.max(np.abs(shapes[:, n]))
        phi = phi if phi[-1] > 0 else -phi
        np.testing.assert_allclose(series.x, np.concatenate(([0.0], phi)), atol=1e-10)
        effective = (shapes[:, n] @ building.masses) ** 2 / (shapes[:, n] ** 2 @ building.masses)
        ratio = effective / system.total_mass
        # two lines: six panels' titles never run into each other
        assert panel.title == f"mode {n + 1}: T_{n + 1} = {periods[n]:.4g} s\nm_{n + 1}*/m_t = {ratio:.3f}"
    assert abs(periods[0] - 0.5) < 1e-12
    # the m_n* add up to the building mass (the mat mass is in m_t, not in any mode)
    effective = (shapes.T @ building.masses) ** 2 / ((shapes**2).T @ building.masses)
    assert np.sum(effective) == pytest.approx(building.masses.sum())
    assert len(mode_shape_figure(system, n_modes=2).panels) == 2


def test_six_mode_titles_never_run_into_each_other():
    """Drawn: each panel's title lies within its own column (they overlapped at six panels a row)."""
    from matplotlib.transforms import Bbox

    from upliftcli.figures.draw import line_figure

    figure = line_figure(mode_shape_figure(paper_system(period=1.234567, mat_mass=0.5 * 3.5e6)))
    renderer = figure.canvas.get_renderer()
    titles = [axes.title.get_window_extent(renderer) for axes in figure.axes]
    assert len(titles) == MAX_MODES
    for i, first in enumerate(titles):
        for second in titles[i + 1:]:
            assert not Bbox.intersection(first, second), "two titles overlap"
    assert all(box.x0 >= 0 and box.x1 <= figure.bbox.width for box in titles)
