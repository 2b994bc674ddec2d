"""The requests of runs whose stories yield, built one at a time without operators.add_states' batch machinery
(docs/theory.md 15.9). A yielding run asks for one state at a time, hundreds of times (the README example x2:
151 on the rigid base), and each the same as add_states builds it alone: A and the event rows taken from the
base of its foundation pattern (story_states.story_state), the operators of a state with the same A shared
(a copy of its slot, the same A object), else computed in place (level_operators.state_levels). add_states
builds them here where every request qualifies (quick_requests): a run whose operators are not a yielding mat
of many elements (Operators.quick), the base of its foundation pattern kept, a valid pattern within the run's
state limit, some story yielding or an A built before, and no two requests of one run (whose order among the
states add_states builds together would differ). The others, and any error, stay with add_states.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ...runtime import backend
from .statespace import ContactState, Layout
from .stories import sign_of_fields, story_fields, valid_story_pattern
from .story_states import StoryBase, soil_rows
from .yielding import valid_pattern


class QuickOperators(Protocol):
    """What a quick request reads and writes of operators.Operators."""

    quick: bool
    layout: Layout
    h: float
    most_states: int
    ops: np.ndarray
    contact: list[ContactState]
    bases: dict[int, StoryBase]
    by_matrix: dict[tuple[int, bytes], int]

    def store(self, pattern: int, state: ContactState, ops: np.ndarray | None, events: bool) -> int: ...


#: a qualified request: (operators, pattern, with event rows, its base, its stories' fields, key of its A)
Quick = tuple[QuickOperators, int, bool, StoryBase, np.ndarray, tuple[int, bytes]]


def quick_requests(requests: list[tuple[QuickOperators, int, bool]]) -> list[Quick] | None:
    """Each request with what its state is built from (quick_request), or None where one does not qualify
    or two come from one run."""
    if len({id(operators) for operators, _, _ in requests}) != len(requests):
        return None
    out = []
    for request in requests:
        quick = quick_request(*request)
        if quick is None:
            return None
        out.append(quick)
    return out


def quick_request(operators: QuickOperators, pattern: int, events: bool) -> Quick | None:
    """(operators, pattern, events, base, the fields of the stories' bits, key of A) of a request that
    qualifies (module docstring), else None."""
    lay = operators.layout
    n_soil = soil_rows(lay)
    soil = pattern & ((1 << n_soil) - 1)
    base = operators.bases.get(soil)
    if base is None or not events or not _room(operators) or not _valid(pattern, lay, n_soil):
        return None
    fields = story_fields(pattern, n_soil, lay.n_plastic)
    yields = fields != 0
    key = (soil, yields.tobytes())  # story_states.matrix_key
    if key not in operators.by_matrix and not yields.any():  # the elastic stories' A: add_states' stacked expm
        return None
    return operators, pattern, events, base, fields, key


def _room(operators: QuickOperators) -> bool:
    """Whether the operators are built here (Operators.quick) and hold another state (Operators.most_states)."""
    return operators.quick and len(operators.contact) < operators.most_states


def _valid(pattern: int, lay: Layout, n_soil: int) -> bool:
    """Whether the pattern is a state (no element lifted and yielding, no story yielding both ways)."""
    if lay.n_settlements and not valid_pattern(pattern, lay.n_elements):
        return False
    return valid_story_pattern(pattern, n_soil, lay.n_plastic)


def add_quick(requests: list[Quick]) -> list[int]:
    """Build and store the states of qualified requests (quick_requests); their indices."""
    levels = backend.loops(f"{__package__}._levels", f"{__package__}.levels_numpy")
    return [_added(request, levels) for request in requests]


def _added(request: Quick, levels) -> int:
    """Store the state of one qualified request: with the operators of the state of the same A, or with its
    own (levels.state_levels, written into its slot); its index."""
    operators, pattern, events, base, fields, key = request
    n_aug = operators.layout.n_aug
    picks = base.pick_base + base.pick_step * fields.take(base.pick_story)  # story_states.story_state
    source = operators.by_matrix.get(key)
    matrix = base.matrices.take(picks[:n_aug], axis=0) if source is None else operators.contact[source].matrix
    state = ContactState(base.state.lifted, matrix, base.state.velocity, base.events.take(picks[n_aug:], axis=0),
                         base.state.yielding, sign_of_fields(fields))
    if source is not None:
        return operators.store(pattern, state, operators.ops[source], events)
    index = operators.store(pattern, state, None, events)
    levels.state_levels(matrix, float(operators.h), operators.ops[index])
    operators.by_matrix[key] = index
    return index
