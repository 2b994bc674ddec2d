"""The exact step operators of the contact states a run meets, built on demand (docs/theory.md
sections 4 and 14.3): per state E_j = expm(A h / 2^j), j = 0..LEVELS (level 0 steps, the finer
ones bisect a crossing), its event rows and their rates, kept in arrays that the stepping loop
(stepping_kernels.integrate) reads. add_states builds the states several runs ask for in one
vectorised batch.
"""

from __future__ import annotations

import numpy as np

from ...errors import AnalysisError
from ...runtime.limits import MAX_OPERATOR_BYTES
from .expm import expm, squared_levels
from .patterns import contact_states
from .statespace import ContactState, Layout, StateSpace
from .stories import story_bits, valid_story_pattern
from .story_states import StoryBase, add_bases, matrix_key, soil_rows, state_of
from .yielding import pattern_bits, step_operators, valid_pattern

#: levels of bisection operators: crossings are bracketed to h / 2^LEVELS, then interpolated
LEVELS = 12
#: with a bearing capacity on more contact elements than this, the step operators come from a
#: small block of each state, written straight into Operators.ops (yielding.step_operators: 28 x 28
#: instead of 66 x 66 on the 20-element mat of benchmarks/bench_yielding.py, whatever the contact
#: pattern); on two elements the block is n_aug - 2 of n_aug and one stacked exponentiation of all
#: the states asked for is faster (1.7 ms instead of 2.9 ms for the 7 states of the first round,
#: measured)
BLOCK_ELEMENTS = 2


class Operators:
    """Exact step operators of the contact states met so far, grown on demand (stored
    transposed, as kernel.integrate takes them). States are built by add_states."""

    def __init__(self, space: StateSpace, h: float, criterion: str, uplift: bool = True):
        self.space, self.layout, self.h, self.criterion = space, space.layout, h, criterion
        self.uplift = uplift  # False: the foundation's event rows are kept zero (bonded), the stories' kept
        n_aug, n_e = self.layout.n_aug, soil_rows(self.layout)
        n_e += 2 * self.layout.n_plastic  # two event rows per yielding story (stories.py)
        self.capacity = reserved_states(self.layout)
        # the states of yielding stories (not on a yielding mat of many elements, whose block operators write
        # only their nonzero entries: _block_operators) write their operators, event rows and rates whole:
        # those arrays are left as allocated (np.empty: served from the memory an earlier run freed, kept by
        # runtime/process.keep_freed_memory, neither zeroed nor faulted in again; the states not yet stored
        # are never read); the others' start as zeros, mapped only as states are stored
        self.fill = None if self.layout.n_plastic and not block_operators(self.layout) else 0.0
        self.ops = _reserve((self.capacity, LEVELS + 1, n_aug, n_aug), self.fill)
        self.events = _reserve((self.capacity, n_e, n_aug), self.fill)
        self.event_rates = _reserve((self.capacity, n_e, n_aug), self.fill)
        self.matrices = np.empty((self.capacity, n_aug, n_aug))
        self.patterns = np.full(self.capacity, -1, dtype=np.int64)
        self.contact: list[ContactState] = []
        # yielding stories (story_states.py): the base of each foundation pattern, and the state whose
        # operators a state with the same A copies, by (foundation pattern, where the stories yield)
        self.bases: dict[int, StoryBase] = {}
        self.by_matrix: dict[tuple[int, bytes], int] = {}

    def lifted(self, pattern: int) -> np.ndarray:
        """Where the elements are lifted in the pattern (bits 0 .. n_e - 1: yielding.pattern_bits)."""
        return pattern_bits(pattern, self.layout.n_elements)[0]

    def yielding(self, pattern: int) -> np.ndarray | None:
        """Where the elements yield in the pattern (None without a bearing capacity)."""
        return pattern_bits(pattern, self.layout.n_elements)[1] if self.layout.n_settlements else None

    def story_sign(self, pattern: int) -> np.ndarray | None:
        """The sign of each yielding story in the pattern (stories.story_bits; None: elastic stories)."""
        lay = self.layout
        return story_bits(pattern, soil_rows(lay), lay.n_plastic) if lay.n_plastic else None

    def store(self, pattern: int, state: ContactState, ops: np.ndarray | None, events: bool) -> int:
        """Keep a built state: ops[j] = expm(A^T h / 2^j) for j = 0..LEVELS (None: the caller
        writes them into self.ops[index] itself, with no copy between: it holds zeros until then)."""
        index = len(self.contact)
        if index == self.capacity:
            self._grow()
        if ops is not None:
            self.ops[index] = ops
        if events:
            rows = state.events
            if not self.uplift:  # a bonded run with yielding stories: its elements never switch
                rows = rows.copy()
                rows[:soil_rows(self.layout)] = 0.0
            self.events[index] = rows
            self.event_rates[index] = rows @ state.matrix
        elif self.fill is None:  # no event rows: zero, as in arrays that start as zeros
            self.events[index] = self.event_rates[index] = 0.0
        self.matrices[index] = state.matrix.T
        self.patterns[index] = pattern
        self.contact.append(state)
        return index

    def _grow(self) -> None:
        """More room for states: doubled (_doubled: the operators zeros, mapped only as stored, which
        yielding.step_operators writes into without a fill; the matrices, never read before, not filled), or
        those of yielding stories (no fill) fourfold, a third of the copying (the README example: 151 states)."""
        if self.fill is not None:
            self.capacity *= 2
            self.ops, self.matrices = _doubled(self.ops, 0.0), _doubled(self.matrices)
            self.events, self.event_rates = _doubled(self.events, 0.0), _doubled(self.event_rates, 0.0)
            self.patterns = _doubled(self.patterns, -1)
            return
        self.capacity *= 4
        self.ops, self.matrices = _grown(self.ops, None, 4), _grown(self.matrices, None, 4)
        self.events, self.event_rates = _grown(self.events, None, 4), _grown(self.event_rates, None, 4)
        self.patterns = _grown(self.patterns, -1, 4)


def block_operators(lay: Layout) -> bool:
    """Whether the step operators come from a small block of each state (a bearing capacity on more than
    BLOCK_ELEMENTS elements: _block_operators)."""
    return bool(lay.n_settlements) and lay.n_elements > BLOCK_ELEMENTS


#: the most memory reserved up front for the operators of one run [bytes] (virtual: untouched
#: pages cost nothing); beyond it the arrays double as states are added
RESERVE_BYTES = 2**30


#: contact states a run of a building whose stories yield is expected to meet, per yielding story (the
#: README example at El Centro x2 with a base-shear strength 0.4 W met 151 on the rigid base, 122
#: bonded: docs/theory.md 15.9)
STATES_PER_STORY = 16


def expected_states(lay: Layout) -> int:
    """About how many contact states a run meets, when that is many: n_e^2 with more than two
    elements with a bearing capacity (a yielding Winkler mat of 20 elements met 441 under El Centro
    with FS_v = 1.5: docs/theory.md 14.3), STATES_PER_STORY per yielding story, else 0 (the elastic
    mat met 31: they are not counted)."""
    soil = lay.n_elements**2 if lay.n_settlements and lay.n_elements > 2 else 0
    return max(soil, STATES_PER_STORY * lay.n_plastic)


def state_bytes(lay: Layout) -> int:
    """Memory of the step operators of one contact state [bytes] (LEVELS + 1 matrices n_aug x n_aug:
    450 kB for the 20-element mat)."""
    return (LEVELS + 1) * lay.n_aug**2 * 8


def reserved_states(lay: Layout) -> int:
    """How many contact states a run's operator arrays hold before they first grow: 4, or on a yielding
    mat of many elements twice expected_states (2 n_e^2), so that the 450 kB per state of such a run
    are not copied at every doubling (a fifth of its run time, measured). Not with yielding stories: a
    run that never yields would pay for the reserve (its pages, or zeroing them), and the doublings of
    one that does copy without a fill (Operators.fill)."""
    expected = lay.n_elements**2 if block_operators(lay) else 0
    if not expected:
        return 4
    return max(4, min(2 * expected, RESERVE_BYTES // state_bytes(lay)))


def max_states(lay: Layout) -> int:
    """The most distinct contact states one run may build: their operators within
    limits.MAX_OPERATOR_BYTES (1,885 on a 31-element mat with a bearing capacity)."""
    return max(64, MAX_OPERATOR_BYTES // state_bytes(lay))


def _too_many_states(lay: Layout) -> str:
    return (f"the run met more than {max_states(lay):,} distinct contact states, whose step operators would exceed "
            f"{MAX_OPERATOR_BYTES / 2**30:g} GiB: the contact chatters; give the foundation more damping, fewer "
            "elements (foundation.elements) or a lower stiffness")


def _reserve(shape: tuple[int, ...], fill: float | None) -> np.ndarray:
    """A new array of `shape`: zeros (fill 0), or left as allocated (None)."""
    return np.empty(shape) if fill is None else np.zeros(shape)


def _doubled(array: np.ndarray, fill: float | None = None) -> np.ndarray:
    """The array with as many rows again after its own, those set to `fill` (None: left unset; 0:
    zeros, whose pages are mapped only as they are written)."""
    return _grown(array, fill, 2)


def _grown(array: np.ndarray, fill: float | None, factor: int) -> np.ndarray:
    """The array with `factor` times its rows, the new ones set to `fill` (as _doubled)."""
    shape = (factor * array.shape[0], *array.shape[1:])
    if fill is None:
        out = np.empty(shape, dtype=array.dtype)
    else:
        out = np.zeros(shape, dtype=array.dtype) if fill == 0.0 else np.full(shape, fill, dtype=array.dtype)
    out[:array.shape[0]] = array
    return out


_NO_INERTIA = ("the mat rotation has neither inertia nor damping in this contact state "
               "(all damping ratios 0 and no element damping): give the mat a rotary inertia I_0 > 0")


_LIFTED_AND_YIELDING = ("a contact element started to lift off and to yield at the same instant (its dashpot "
                        "force balanced its capacity exactly): reduce the time step (analysis.exact.time_step)")


_BOTH_WAYS = ("a story started to yield both ways at the same instant: reduce the time step "
              "(analysis.exact.time_step)")


def add_states(requests: list[tuple[Operators, int, bool]]) -> list[int | AnalysisError]:
    """Build and store the contact states asked for, (operators, pattern, with event rows)
    each, vectorised over the requests that share a layout: one batched assembly
    (patterns.contact_states), one stacked expm and stacked squarings. Each item gets the
    same bits as built alone. Returns the new state index, or the error, per request."""
    out: list[int | AnalysisError] = [AnalysisError(_NO_INERTIA)] * len(requests)
    for members in _groups(requests, out).values():
        built = _built_states(requests, members)
        if not built:
            continue
        if block_operators(requests[built[0][0]][0].layout):
            _block_operators(requests, built, out)  # a yielding mat of many elements
            continue
        fresh, copies = _shared_operators(requests, built)
        if fresh:
            _exponentiated(requests, fresh, out)
        for k, state, key in copies:  # the same A as a state built before: its operators, bit for bit
            operators, pattern, events = requests[k]
            out[k] = operators.store(pattern, state, operators.ops[operators.by_matrix[key]], events)
    return out


def _exponentiated(requests: list[tuple[Operators, int, bool]], built: list[tuple[int, ContactState]],
                   out: list[int | AnalysisError]) -> None:
    """Store the states `built`, their operators from one stacked exponentiation (_level_operators)."""
    ops = _level_operators(requests, built)
    for r, (k, state) in enumerate(built):
        operators, pattern, events = requests[k]
        if state.yielding is not None:
            _hold_settlements(ops[r], operators.layout.settlement_indices[~state.yielding])
        if state.story_sign is not None:
            _elastic_stories(ops[r], state, operators.layout, operators.h)
        out[k] = operators.store(pattern, state, ops[r], events)
        if state.story_sign is not None:
            operators.by_matrix.setdefault(matrix_key(pattern, operators.layout, state), out[k])


def _level_operators(requests: list[tuple[Operators, int, bool]], built: list[tuple[int, ContactState]]
                     ) -> list[np.ndarray]:
    """E_j^T, j = 0..LEVELS, of each state of `built`: in one stacked exponentiation (_stacked_operators), those
    of the states where a story yields by squarings alone (expm.squared_levels: the same accuracy, a
    fifth of the products and no solve; docs/theory.md 15.9)."""
    a_t = np.stack([state.matrix.T for _, state in built])
    h = np.array([requests[k][0].h for k, _ in built])[:, None, None]
    yields = np.array([_story_yields(state) for _, state in built], dtype=bool)
    ops: list[np.ndarray] = [np.empty(0)] * len(built)
    for chosen, levels in ((~yields, _stacked_operators), (yields, _squared_operators)):
        if chosen.any():
            for r, level_ops in zip(np.flatnonzero(chosen), levels(a_t[chosen], h[chosen]), strict=True):
                ops[r] = level_ops
    return ops


def _shared_operators(requests: list[tuple[Operators, int, bool]], built: list[tuple[int, ContactState]]
                      ) -> tuple[list[tuple[int, ContactState]], list[tuple[int, ContactState, tuple]]]:
    """The states of `built` whose operators are to be computed, and (index, state, key) of those whose A
    is that of a state built before or earlier in `built` (yielding stories: story_states.matrix_key), which copy its
    operators once it is stored."""
    fresh, copies, first = [], [], set()
    for k, state in built:
        operators, pattern, _ = requests[k]
        if state.story_sign is None:
            fresh.append((k, state))
            continue
        key = matrix_key(pattern, operators.layout, state)
        if key in operators.by_matrix or (id(operators), key) in first:
            copies.append((k, state, key))
            continue
        first.add((id(operators), key))
        fresh.append((k, state))
    return fresh, copies


def _groups(requests: list[tuple[Operators, int, bool]], out: list[int | AnalysisError]) -> dict[tuple, list[int]]:
    """The requests that can be built, grouped by layout and criterion (indices into requests); the others
    get their error in out: a pattern with an element lifted and yielding, or more states than
    max_states for their run."""
    groups: dict[tuple, list[int]] = {}
    asked: dict[int, int] = {}  # id(operators) -> states asked for in this call
    for k, (operators, pattern, _) in enumerate(requests):
        lay = operators.layout
        if lay.n_settlements and not valid_pattern(pattern, lay.n_elements):
            out[k] = AnalysisError(_LIFTED_AND_YIELDING)
            continue
        if lay.n_plastic and not valid_story_pattern(pattern, soil_rows(lay), lay.n_plastic):
            out[k] = AnalysisError(_BOTH_WAYS)
            continue
        asked[id(operators)] = asked.get(id(operators), 0) + 1
        if len(operators.contact) + asked[id(operators)] > max_states(lay):
            out[k] = AnalysisError(_too_many_states(lay))
            continue
        key = (lay.n_p, tuple(lay.massive), tuple(lay.massless), lay.n_x, lay.n_elements, lay.n_plastic,
               operators.criterion)
        groups.setdefault(key, []).append(k)
    return groups


def _built_states(requests: list[tuple[Operators, int, bool]], members: list[int]) -> list[tuple[int, ContactState]]:
    """(index, state) of the requests `members` (one layout) whose state could be built: all in one batch,
    or, when some item's massless rotation has no damping (ZeroDivisionError), each alone to find it."""
    try:
        return list(zip(members, _states([requests[k] for k in members]), strict=False))
    except ZeroDivisionError:
        if len(members) == 1:
            return []
    built = []
    for k in members:  # find the item(s) at fault; the others go on
        try:
            built.append((k, _states([requests[k]])[0]))
        except ZeroDivisionError:
            continue
    return built


def _block_operators(requests: list[tuple[Operators, int, bool]], built: list[tuple[int, ContactState]],
                     out: list[int | AnalysisError]) -> None:
    """Store states of a yielding mat of many elements, their operators from the exponential of a
    small block each (yielding.step_operators), written straight into Operators.ops; the states of
    one model (the same space and step) in one stacked call."""
    slots = []
    for k, state in built:
        operators, pattern, events = requests[k]
        out[k] = operators.store(pattern, state, None, events)
        slots.append((operators, out[k], state))
    by_model: dict[int, list[tuple[Operators, int, ContactState]]] = {}
    for slot in slots:
        by_model.setdefault(id(slot[0]), []).append(slot)
    for group in by_model.values():  # stored one after another: their slots are one slice of ops
        operators, first = group[0][0], group[0][1]
        step_operators(operators.space, [state for _, _, state in group], operators.h, LEVELS,
                       operators.ops[first:first + len(group)])
        for _, index, state in group:
            if state.story_sign is not None:
                _hold_settlements(operators.ops[index], operators.layout.plastic_indices[state.story_sign == 0])


def _stacked_operators(a_t: np.ndarray, h: np.ndarray) -> np.ndarray:
    """E_j^T = expm(A h / 2^j)^T, j = 0..LEVELS, of a stack of A^T (R, n, n) with steps h (R, 1, 1):
    the finest level by expm, the coarser ones by squaring it, level 0 by its own expm. Transposed
    (the kernel's matvec runs down columns): (E^T)^2 = (E^2)^T."""
    ops = np.empty((a_t.shape[0], LEVELS + 1, *a_t.shape[1:]))
    ops[:, LEVELS] = expm(a_t * (h / 2.0**LEVELS))
    for j in range(LEVELS - 1, 0, -1):
        ops[:, j] = ops[:, j + 1] @ ops[:, j + 1]
    ops[:, 0] = expm(a_t * h)
    return ops


def _story_yields(state: ContactState) -> bool:
    """Whether some story yields in the state."""
    return state.story_sign is not None and bool(state.story_sign.any())


def _squared_operators(a_t: np.ndarray, h: np.ndarray) -> np.ndarray:
    """E_j^T, j = 0..LEVELS, of a stack of A^T (R, n, n) with steps h (R, 1, 1) by expm.squared_levels (states
    where a story yields: docs/theory.md 15.9); (E^T)^2 = (E^2)^T."""
    return squared_levels(a_t * h, LEVELS)


def _hold_settlements(ops: np.ndarray, constant: np.ndarray) -> None:
    """Make the settlements s_i of elements that do not yield exactly constant in the step
    operators (ops: E^T per level, in place): their rows of A are zero, so the rows of E = expm(A h)
    are unit rows, which the computed exponentials hold only to a few units in the last place (a
    drift of 4e-13 of s_i per step, measured)."""
    ops[:, :, constant] = 0.0
    ops[:, constant, constant] = 1.0


def _elastic_stories(ops: np.ndarray, state: ContactState, lay: Layout, h: float) -> None:
    """The step operators (E^T per level, in place) of a state with yielding stories: the plastic drifts
    of the elastic stories held exactly (_hold_settlements), and, where no story yields, the operators
    of the other entries from the exponential of A without the plastic drifts: the matrix and the
    operators of the elastic building, bit for bit (the plastic drifts, zero until a story yields, do
    not change its history: docs/theory.md 15.4)."""
    _hold_settlements(ops, lay.plastic_indices[state.story_sign == 0])
    if np.any(state.story_sign != 0):
        return
    keep = np.setdiff1d(np.arange(lay.n_aug), lay.plastic_indices)
    reduced = state.matrix[np.ix_(keep, keep)].T
    ops[:, keep[:, None], keep[None, :]] = _stacked_operators(reduced[None], np.array([[[h]]]))[0]


def _states(requests: list[tuple[Operators, int, bool]]) -> list[ContactState]:
    """The states asked for (one layout): of yielding stories from their bases (story_states.state_of), else
    assembled together (patterns.contact_states)."""
    if requests[0][0].layout.n_plastic:
        add_bases([(operators, pattern) for operators, pattern, _ in requests])
        return [state_of(operators, pattern) for operators, pattern, _ in requests]
    return _contact_states(requests)


def _contact_states(requests: list[tuple[Operators, int, bool]]) -> list[ContactState]:
    """The states of an elastic building asked for, assembled together (patterns.contact_states)."""
    first = requests[0][0]
    lifted = np.array([operators.lifted(pattern) for operators, pattern, _ in requests], dtype=bool)
    lifted = lifted.reshape(len(requests), first.layout.n_elements)
    yielding = None
    if first.layout.n_settlements:
        yielding = np.array([operators.yielding(pattern) for operators, pattern, _ in requests], dtype=bool)
    return contact_states([operators.space for operators, _, _ in requests], lifted, first.criterion, yielding)
