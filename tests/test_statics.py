"""engines/statics.py: story maps and the reactions of a rigid mat, against hand statics."""

from __future__ import annotations

import numpy as np

from upliftcli.engines.statics import story_maps
from upliftcli.model.building import shear_building


def test_story_maps_by_hand():
    building = shear_building([1.0, 1.0, 1.0], [4.0, 3.0, 3.0], [1.0, 1.0, 1.0])
    maps = story_maps(building)
    forces = np.array([1.0, 2.0, 3.0])
    np.testing.assert_allclose(maps.shear @ forces, [6.0, 5.0, 3.0])
    # about the bottom of story 1 (z = 0), 2 (z = 4) and 3 (z = 7); floors at 4, 7, 10 m
    np.testing.assert_allclose(maps.moment @ forces, [1 * 4 + 2 * 7 + 3 * 10, 2 * 3 + 3 * 6, 3 * 3])
    np.testing.assert_allclose(maps.drift @ np.array([0.1, 0.25, 0.3]), [0.1, 0.15, 0.05])
