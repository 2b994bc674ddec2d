"""The contact states of a building whose stories yield, assembled from what they share (docs/theory.md
15.2 and 15.9): the states of one contact pattern of the foundation differ only in the signs of their
stories, and only in the rows of the plastic drifts p_j in A ((1 - alpha) d_j' while story j yields,
else zero) and in the stories' event rows (each chosen from the onset, unloading and never rows). The
base of each foundation pattern (A with every story elastic, the velocity map, the foundation's
event rows and those candidate rows) is assembled once (patterns.contact_states) and kept; a state
is then a copy of its A with some rows set and its event rows chosen: the same arrays, bit for bit,
as contact_states assembles for it (tests/test_story_states.py). The signs P and N of a story give
the same A, so the states whose stories yield in the same places share their step operators
(operators.add_states copies them). A yielding run's one request per round is built by story_requests.py
from the base's table (StoryBase.table, .picks) in one compiled call (level_operators.story_rows).
"""

from __future__ import annotations

from dataclasses import dataclass
from types import ModuleType
from typing import Protocol

import numpy as np

from . import stories
from .level_operators import loops
from .patterns import contact_states
from .statespace import ContactState, Layout, StateSpace


@dataclass(frozen=True)
class StoryBase:
    """What the states of one foundation pattern share, as tables a state takes its rows from (story_state):
    the base state (every story elastic); matrices (3 n_aug, n_aug): its A, then twice its A with the row of
    every story's p_j as while the story yields (for the codes 1 and 2 of its sign: 0 elastic, 1 positive, 2
    negative, sign % 3); events (n_s + 6 n_y, n_aug): the foundation's n_s = soil_rows event rows, then the
    stories' 2 n_y rows for each code (stories.event_candidates): row 2 j the onset of P, the unloading from
    P, never; row 2 j + 1 the onset of N, never, the unloading from N. A state takes rows picks[:n_aug] of
    matrices and picks[n_aug:] of events, picks = pick_base + pick_step * code[pick_story] (_picks). table and
    picks: the same as one table (matrices, then events) and the picks into it (3, n_aug + n_e: base, step,
    story), as level_operators.story_rows takes them (story_requests.py); levels: the module that builds the
    states from them (level_operators.loops when the base was made: _levels.c or its twin)."""

    state: ContactState
    soil_rows: int
    matrices: np.ndarray
    events: np.ndarray
    pick_base: np.ndarray
    pick_step: np.ndarray
    pick_story: np.ndarray
    table: np.ndarray
    picks: np.ndarray
    levels: ModuleType


def story_bases(spaces: list[StateSpace], lifted: np.ndarray, yielding: np.ndarray | None, criterion: str,
                soil_rows: int) -> list[StoryBase]:
    """The StoryBase of foundation patterns of models with yielding stories (one layout): item r that of
    spaces[r] in the pattern lifted[r] (R, n_e) (and yielding[r] with a bearing capacity), assembled
    together (patterns.contact_states: each item the bits it gets alone). Raises ZeroDivisionError as
    contact_states does."""
    lay = spaces[0].layout
    sign = np.zeros((len(spaces), lay.n_plastic), dtype=np.int8)
    states = contact_states(spaces, lifted, criterion, yielding, sign)
    return [_base(space, state, soil_rows) for space, state in zip(spaces, states, strict=True)]


def _base(space: StateSpace, state: ContactState, soil_rows: int) -> StoryBase:
    """The StoryBase of the base state `state` (every story elastic) of a model."""
    lay, story = space.layout, space.model.stories
    drift_rate = (story.drift @ space.to_modal @ state.velocity)[None]  # as patterns._yielding_stories
    plastic = stories.plastic_rows(story, drift_rate, np.ones((1, lay.n_plastic), dtype=np.int8))[0]
    yielding = state.matrix.copy()
    yielding[lay.plastic_indices] = plastic
    up, down, rate, never = stories.event_candidates(story, space.drift_rows, drift_rate, lay.plastic_indices,
                                                     lay.index_one)
    codes = np.empty((3, 2 * lay.n_plastic, lay.n_aug))  # by code: rows 2 j (up) and 2 j + 1 (down)
    codes[:, 0::2] = np.stack((up, -rate[0], never[0]))
    codes[:, 1::2] = np.stack((down, never[0], rate[0]))
    matrices = np.vstack((state.matrix, yielding, yielding))
    events = np.vstack((state.events[:soil_rows], codes.reshape(-1, lay.n_aug)))
    picks = _picks(lay.n_aug, lay.plastic_indices, soil_rows)
    into_table = np.stack(picks)
    into_table[0, lay.n_aug:] += matrices.shape[0]  # the event rows after the matrices' rows
    return StoryBase(state, soil_rows, matrices, events, *picks, np.vstack((matrices, events)), into_table, loops())


def _picks(n_aug: int, plastic: np.ndarray, soil_rows: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """StoryBase's pick_base, pick_step and pick_story (int64, n_aug + n_e): the row of its tables a state takes
    for each row of its A, then of its event rows, given the codes of its stories (story_state)."""
    n_y = plastic.size
    n_e = soil_rows + 2 * n_y
    step, story = np.zeros(n_aug + n_e, dtype=np.int64), np.zeros(n_aug + n_e, dtype=np.int64)
    step[plastic], story[plastic] = n_aug, np.arange(n_y)
    step[n_aug + soil_rows:], story[n_aug + soil_rows:] = 2 * n_y, np.repeat(np.arange(n_y), 2)
    return np.concatenate((np.arange(n_aug), np.arange(n_e))), step, story


def story_state(base: StoryBase, sign: np.ndarray) -> ContactState:
    """The state of the base's foundation pattern with the stories' signs `sign` (n_y: +1, -1, 0), as
    patterns.contact_states assembles it: its rows taken from the base's tables, one take each (a yielding run
    builds hundreds of states: copies and row assignments cost 11 us a state, this less than half of that,
    measured)."""
    state = base.state
    picks = base.pick_base + base.pick_step * (sign % 3).take(base.pick_story)
    n_aug = base.matrices.shape[1]
    return ContactState(state.lifted.copy(), base.matrices.take(picks[:n_aug], axis=0), state.velocity,
                        base.events.take(picks[n_aug:], axis=0),
                        None if state.yielding is None else state.yielding.copy(), sign.copy())


def soil_rows(lay: Layout) -> int:
    """Event rows (and pattern bits) of the foundation's elements: one per element, two with a bearing
    capacity; the yielding stories' come after them (stories.py). Called about seven times per state a yielding
    run builds: a conditional, not max()."""
    n_elements = lay.n_elements
    return (n_elements if n_elements > 0 else 0) + lay.n_settlements


def matrix_key(pattern: int, lay: Layout) -> tuple[int, int]:
    """What the A of a state with yielding stories depends on: the foundation's bits of its pattern and where
    its stories yield (the signs P and N give the same A): bit 2 s set where story s yields."""
    n_soil = soil_rows(lay)
    bits = pattern >> n_soil
    return pattern & ((1 << n_soil) - 1), (bits | (bits >> 1)) & stories.EVEN_BITS[lay.n_plastic]


class StoryOperators(Protocol):
    """What add_bases and state_of read of operators.Operators: the bases kept, the model and the pattern bits."""

    bases: dict[int, StoryBase]
    space: StateSpace
    layout: Layout
    criterion: str

    def lifted(self, pattern: int) -> np.ndarray: ...

    def yielding(self, pattern: int) -> np.ndarray | None: ...

    def story_sign(self, pattern: int) -> np.ndarray | None: ...


def add_bases(requests: list[tuple[StoryOperators, int]]) -> None:
    """Assemble together (story_bases) the bases of the foundation patterns of the requests, (operators,
    pattern) of one layout, that have none yet, and keep them in operators.bases."""
    missing = _missing_bases(requests)
    if not missing:
        return
    wanted = list(missing.values())
    lay = wanted[0][0].layout
    lifted = np.array([operators.lifted(pattern) for operators, pattern in wanted], dtype=bool)
    yielding = None
    if lay.n_settlements:
        yielding = np.array([operators.yielding(pattern) for operators, pattern in wanted], dtype=bool)
    bases = story_bases([operators.space for operators, _ in wanted], lifted.reshape(len(wanted), lay.n_elements),
                        yielding, wanted[0][0].criterion, soil_rows(lay))
    for ((_, soil), (operators, _)), base in zip(missing.items(), bases, strict=True):
        operators.bases[soil] = base


def _missing_bases(requests: list[tuple[StoryOperators, int]]) -> dict[tuple[int, int], tuple[StoryOperators, int]]:
    """(id of the operators, foundation pattern) -> (operators, a pattern) of each base the requests need that is
    not kept yet."""
    missing: dict[tuple[int, int], tuple[StoryOperators, int]] = {}
    for operators, pattern in requests:
        soil = pattern & ((1 << soil_rows(operators.layout)) - 1)
        if soil not in operators.bases:
            missing.setdefault((id(operators), soil), (operators, pattern))
    return missing


def state_of(operators: StoryOperators, pattern: int) -> ContactState:
    """The state of a contact pattern of a model with yielding stories, from the base of its foundation
    pattern (add_bases first)."""
    base = operators.bases[pattern & ((1 << soil_rows(operators.layout)) - 1)]
    return story_state(base, operators.story_sign(pattern))
