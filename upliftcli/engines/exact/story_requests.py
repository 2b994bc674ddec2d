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

from types import ModuleType
from typing import Protocol

import numpy as np

from ...runtime import backend
from .statespace import ContactState, Layout
from .stories import sign_of_fields, valid_story_pattern
from .story_states import StoryBase, matrix_key, soil_rows
from .yielding import valid_pattern


class QuickOperators(Protocol):
    """What a quick request reads and writes of operators.Operators."""

    quick: bool
    uplift: bool
    layout: Layout
    h: float
    most_states: int
    ops: np.ndarray
    events: np.ndarray
    event_rates: np.ndarray
    matrices: np.ndarray
    contact: list[ContactState]
    bases: dict[int, StoryBase]
    by_matrix: dict[tuple[int, int], int]

    def slot(self) -> int: ...

    def keep(self, index: int, pattern: int, state: ContactState) -> int: ...


#: a qualified request: (operators, pattern, the base of its foundation pattern, the key of its A)
Quick = tuple[QuickOperators, int, StoryBase, tuple[int, int]]


def quick_requests(requests: list[tuple[QuickOperators, int, bool]]) -> list[Quick] | None:
    """Each request with what its state is built from (quick_request), or None where one does not qualify
    or two come from one run."""
    if len(requests) == 1:  # a yielding run alone: its one request of each round
        quick = quick_request(*requests[0])
        return None if quick is None else [quick]
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
    """(operators, pattern, base, key of A: story_states.matrix_key) of a request that qualifies (module
    docstring), else None."""
    base = operators.bases.get(pattern & ((1 << soil_rows(operators.layout)) - 1))
    if base is None or not (events and _room(operators)):
        return None
    key = matrix_key(pattern, operators.layout)
    return (operators, pattern, base, key) if _buildable(operators, pattern, base, key) else None


def _buildable(operators: QuickOperators, pattern: int, base: StoryBase, key: tuple[int, int]) -> bool:
    """Whether the pattern is a state (_valid) whose A has a story yielding or was built before (the elastic
    stories' A is add_states': a stacked exponentiation)."""
    return _valid(pattern, operators.layout, base.soil_rows) and (key[1] != 0 or key in operators.by_matrix)


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


def _added(request: Quick, levels: ModuleType) -> int:
    """Store the state of one qualified request: its A and event rows from its base's table, its event rows, their
    rates and A^T in its slot (levels.story_rows), and the operators of the state of the same A or its own
    (levels.state_levels, written into the slot); its index."""
    operators, pattern, base, key = request
    n_aug, index = operators.layout.n_aug, operators.slot()
    rows = np.empty((base.picks.shape[1], n_aug))
    fields = np.empty(operators.layout.n_plastic, dtype=np.int64)
    levels.story_rows(pattern >> base.soil_rows, base.table, base.picks, rows, operators.events[index],
                      operators.matrices[index], fields, 0 if operators.uplift else base.soil_rows)
    matrix = rows[:n_aug]
    np.matmul(operators.events[index], matrix, out=operators.event_rates[index])
    source = operators.by_matrix.get(key)
    if source is None:
        levels.state_levels(matrix, float(operators.h), operators.ops[index])
        operators.by_matrix[key] = index
    else:  # the same A as a state built before: its operators, bit for bit
        operators.share(index, source)
    state = ContactState(base.state.lifted, matrix, base.state.velocity, rows[n_aug:], base.state.yielding,
                         sign_of_fields(fields))
    return operators.keep(index, pattern, state)
