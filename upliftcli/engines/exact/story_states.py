"""The contact states of a building whose stories yield, assembled from what they share (docs/theory.md
15.2 and 15.7): the states of one contact pattern of the foundation differ only in the signs of their
stories, and only in the rows of the plastic drifts p_j in A ((1 - alpha) d_j' while story j yields,
else zero) and in the stories' event rows (each chosen from the onset, unloading and never rows). The
base of each foundation pattern (A with every story elastic, the velocity map, the foundation's
event rows and those candidate rows) is assembled once (patterns.contact_states) and kept; a state
is then a copy of its A with some rows set and its event rows chosen: the same arrays, bit for bit,
as contact_states assembles for it (tests/test_story_states.py). The signs P and N of a story give
the same A, so the states whose stories yield in the same places share their step operators
(operators.add_states copies them).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import stories
from .patterns import contact_states
from .statespace import ContactState, StateSpace


@dataclass(frozen=True)
class StoryBase:
    """What the states of one foundation pattern share: the base state (every story elastic), the rows
    of the p_j in A while story j yields (n_y, n_aug), and the event rows each story may have
    (stories.event_candidates), by its sign's code (0 elastic, 1 positive, 2 negative: sign % 3):
    rows_up[code, j] its row 2 j (the onset of P, the unloading from P, never) and rows_down[code, j] its
    row 2 j + 1 (the onset of N, never, the unloading from N), each (3, n_y, n_aug)."""

    state: ContactState
    soil_rows: int
    plastic: np.ndarray
    rows_up: np.ndarray
    rows_down: np.ndarray


def story_base(space: StateSpace, lifted: np.ndarray, yielding: np.ndarray | None, criterion: str,
               soil_rows: int) -> StoryBase:
    """The StoryBase of one foundation pattern (lifted, and yielding with a bearing capacity) of a model
    with yielding stories. Raises ZeroDivisionError as contact_states does."""
    lay = space.layout
    sign = np.zeros((1, lay.n_plastic), dtype=np.int8)
    (state,) = contact_states([space], lifted[None], criterion, None if yielding is None else yielding[None], sign)
    story = space.model.stories
    drift_rate = (story.drift @ space.to_modal @ state.velocity)[None]  # as patterns._yielding_stories
    plastic = stories.plastic_rows(story, drift_rate, np.ones_like(sign))[0]
    up, down, rate, never = stories.event_candidates(story, space.drift_rows, drift_rate, lay.plastic_indices,
                                                     lay.index_one)
    return StoryBase(state, soil_rows, plastic, np.stack((up, -rate[0], never[0])), np.stack((down, never[0], rate[0])))


def story_state(base: StoryBase, plastic_indices: np.ndarray, sign: np.ndarray) -> ContactState:
    """The state of the base's foundation pattern with the stories' signs `sign` (n_y: +1, -1, 0), as
    patterns.contact_states assembles it."""
    state = base.state
    yields = sign != 0
    matrix = state.matrix.copy()
    matrix[plastic_indices[yields]] = base.plastic[yields]
    events = state.events.copy()
    code, story = sign % 3, np.arange(sign.size)
    events[base.soil_rows::2] = base.rows_up[code, story]
    events[base.soil_rows + 1::2] = base.rows_down[code, story]
    return ContactState(state.lifted.copy(), matrix, state.velocity, events,
                        None if state.yielding is None else state.yielding.copy(), sign.copy())
