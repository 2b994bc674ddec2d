"""The requests of runs whose stories yield, built one at a time without operators.add_states' batch machinery
(docs/theory.md 15.9). A yielding run asks for one state at a time, hundreds of times (the README example x2:
151 on the rigid base), and each the same as add_states builds it alone: A and the event rows taken from the
base of its foundation pattern (story_states.story_state), the operators of a state with the same A shared
(a copy of its slot, the same A object), else computed in place (level_operators.state_levels). add_states
builds them here where every request qualifies (quick_requests): a run whose operators are not a yielding mat
of many elements (Operators.quick), the base of its foundation pattern kept, a valid pattern within the run's
state limit, some story yielding or an A built before, and no two requests of one run (whose order among the
states add_states builds together would differ). The others, and any error, stay with add_states. The module
that builds them (_levels.c or its twin) is the one its base was made with (StoryBase.levels: asked once, not for
each state).

The rates G A of the stories' event rows are written by the same compiled call as the rows (story_rows: each
entry summed in the order of its terms, levels_numpy.product), the foundation's by np.matmul, and
Operators.store gives a state of yielding stories the same (event_rates).

The compiled stepping loop builds the states that qualify itself, with the same C code in the same order
(_stepping.c's builds.h, from what loop_builds hands it: a rigid or bonded run's, whose foundation rows are
zero), instead of returning NEED_STATE for each; adopt then makes their ContactState and keeps their keys of A.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from . import levels_numpy
from .levels_numpy import product
from .statespace import ContactState, Layout
from .stepping_kernels import MAX_BASES, Builds
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
    rows: np.ndarray
    fields: np.ndarray
    keys: np.ndarray
    patterns: np.ndarray
    events: np.ndarray
    event_rates: np.ndarray
    matrices: np.ndarray
    contact: list[ContactState]
    bases: dict[int, StoryBase]
    by_matrix: dict[tuple[int, int], int]

    def slot(self) -> int: ...

    def keep(self, index: int, pattern: int, state: ContactState) -> int: ...

    def share(self, index: int, source: int) -> None: ...

    def record(self, key: tuple[int, int], index: int) -> None: ...


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


def add_quick(requests: list[tuple[QuickOperators, int, bool]]) -> list[int] | None:
    """Build and store the states of the requests (operators, pattern, with event rows) where each qualifies
    (quick_requests); their indices, else None (operators.add_states builds them all)."""
    quick = quick_requests(requests)
    return None if quick is None else [_added(request) for request in quick]


def _added(request: Quick) -> int:
    """Store the state of one qualified request: its A and event rows from its base's table (into operators.rows),
    its event rows, their rates (the foundation's of an uplift run: _foundation_rates) and A^T in its slot
    (levels.story_rows), and the operators of the state of the same A or its own (levels.state_levels, written into
    the slot); its index. The compiled loop builds the same with the same code (stepping_kernels.Builds)."""
    operators, pattern, base, key = request
    n_aug, index, soil, levels = operators.layout.n_aug, operators.slot(), base.soil_rows, base.levels
    zero_rows = 0 if operators.uplift else soil
    levels.story_rows(pattern >> soil, base.table, base.picks, operators.rows[index], operators.events[index],
                      operators.event_rates[index], operators.matrices[index], operators.fields[index], zero_rows,
                      soil)
    matrix = operators.rows[index, :n_aug]
    if zero_rows < soil:
        _foundation_rates(operators, index, matrix, soil)
    source = operators.by_matrix.get(key)
    if source is None:
        levels.state_levels(matrix, float(operators.h), operators.ops[index])
        operators.record(key, index)
    else:  # the same A as a state built before: its operators, bit for bit
        operators.share(index, source)
    return operators.keep(index, pattern, _contact_state(operators, index, base))


def _contact_state(operators: QuickOperators, index: int, base: StoryBase) -> ContactState:
    """The ContactState of state `index`, written by story_rows: views of its A and event rows (operators.rows),
    its stories' signs from their fields, the rest its base's."""
    rows, state = operators.rows[index], base.state
    n_aug = operators.layout.n_aug
    return ContactState(state.lifted, rows[:n_aug], state.velocity, rows[n_aug:], state.yielding,
                        sign_of_fields(operators.fields[index]))


def loop_builds(operators: QuickOperators) -> Builds | None:
    """What the compiled loop builds the states of a run's yielding stories with (stepping_kernels.Builds), None
    where it builds none: not built here (Operators.quick) or an uplift run's foundation rates (_foundation_rates,
    np.matmul: Python's)."""
    if not operators.quick:
        return None
    lay, soil = operators.layout, soil_rows(operators.layout)
    if operators.uplift and soil:
        return None
    return Builds(operators.rows, operators.fields, operators.keys, np.array([len(operators.contact)]),
                  _compiled_bases(operators), float(operators.h), operators.most_states, soil, lay.n_elements,
                  bool(lay.n_settlements))


def _compiled_bases(operators: QuickOperators) -> tuple[tuple[int, np.ndarray, np.ndarray], ...]:
    """(foundation pattern, table, picks) of the bases made with _levels.c, at most MAX_BASES (the states of the
    others, those of the numpy twin levels_numpy, are built by Python: their arithmetic is the twin's)."""
    bases = tuple((pattern, base.table, base.picks) for pattern, base in operators.bases.items()
                  if base.levels is not levels_numpy)
    return bases[:MAX_BASES]


def adopt(operators: QuickOperators, builds: Builds | None) -> None:
    """Keep the states the compiled loop built (builds.count: those after operators.contact): each one's
    ContactState (_contact_state) and, where its operators are its own, its key of A (by_matrix)."""
    if builds is None:
        return
    mask = (1 << soil_rows(operators.layout)) - 1
    for index in range(len(operators.contact), int(builds.count[0])):
        pattern, key = int(operators.patterns[index]), operators.keys[index]
        operators.contact.append(_contact_state(operators, index, operators.bases[pattern & mask]))
        if key[0] >= 0:  # its operators its own: the first of its A (the loop wrote its key)
            operators.record((int(key[0]), int(key[1])), index)


def _foundation_rates(operators: QuickOperators, index: int, matrix: np.ndarray, soil: int) -> None:
    """The rates of the foundation's event rows of state `index` (an uplift run's), as event_rates has them."""
    np.matmul(operators.events[index, :soil], matrix, out=operators.event_rates[index, :soil])


def event_rates(rows: np.ndarray, matrix: np.ndarray, out: np.ndarray, soil: int) -> None:
    """out = rows A, the rates of a state's event rows (Operators.store): the foundation's first `soil` rows by
    np.matmul (all of them without yielding stories: as ever), the stories' each entry summed in the order of its
    terms (levels_numpy.product), as _levels.story_rows writes them."""
    np.matmul(rows[:soil], matrix, out=out[:soil])
    if soil < rows.shape[0]:
        out[soil:] = product(rows[soil:], matrix)
