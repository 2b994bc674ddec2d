"""The exact step operators of the contact states a run meets, built on demand (docs/theory.md
sections 4 and 14.3): per state E_j = expm(A h / 2^j), j = 0..LEVELS (level 0 steps, the finer
ones bisect a crossing), its event rows and their rates, kept in arrays that the stepping loop
(stepping_kernels.integrate) reads. add_states builds the states several runs ask for in one
vectorised batch; the operators of states where a story yields are written into those arrays one
state at a time, in C (level_operators.state_levels).
"""

from __future__ import annotations

import numpy as np

from ...errors import AnalysisError
from ...runtime.limits import MAX_OPERATOR_BYTES
from .kept import doubled, reserve
from .level_operators import LEVELS, elastic_operators, hold_settlements, stacked_operators, state_levels
from .patterns import contact_states
from .statespace import ContactState, Layout, StateSpace
from .stories import story_bits, valid_story_pattern
from .story_requests import add_quick, event_rates
from .story_states import StoryBase, add_bases, matrix_key, soil_rows, state_of
from .yielding import pattern_bits, step_operators, valid_pattern

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
        lay = self.layout  # the states of runs of one group are built together (_groups), at most most_states
        self.group = (lay.n_p, tuple(lay.massive), tuple(lay.massless), lay.n_x, lay.n_elements, lay.n_plastic,
                      criterion)
        self.most_states = max_states(lay)
        # the states of yielding stories and of a yielding mat of many elements write their operators (block
        # operators: _block_operators), event rows and rates whole: those arrays are left as allocated (np.empty:
        # the memory an earlier run freed, runtime/process.keep_freed_memory; on such a mat its operators' array,
        # kept.reused; neither zeroed nor faulted in again; states not yet stored are never read); the others'
        # start as zeros, mapped only as states are stored
        block = block_operators(self.layout)
        self.fill = None if self.layout.n_plastic or block else 0.0
        self.quick = bool(self.layout.n_plastic) and not block  # a state may be built by story_requests.py
        self.ops = reserve((self.capacity, LEVELS + 1, n_aug, n_aug), self.fill, block)
        self.events = reserve((self.capacity, n_e, n_aug), self.fill)
        self.event_rates = reserve((self.capacity, n_e, n_aug), self.fill)
        self.matrices = np.empty((self.capacity, n_aug, n_aug))
        self.patterns = np.full(self.capacity, -1, dtype=np.int64)
        self.slots = np.empty(self.capacity, dtype=np.int64)  # per state: the slot of ops of its operators (slot)
        # yielding stories, per state: its A and event rows, its stories' fields, its key of A where its operators are
        # its own (-1 where shared: record), as story_requests.py and the compiled loop (stepping_kernels.Builds) write
        self.rows, self.fields = np.empty((self.capacity, n_aug + n_e, n_aug)), np.empty((self.capacity, lay.n_plastic),
                                                                                        dtype=np.int64)
        self.keys = np.empty((self.capacity, 2), dtype=np.int64)
        self.contact: list[ContactState] = []
        # yielding stories (story_states.py): the base of each foundation pattern, and the state whose
        # operators a state with the same A shares (slots), by (foundation pattern, where the stories yield)
        self.bases: dict[int, StoryBase] = {}
        self.by_matrix: dict[tuple[int, int], int] = {}

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
        """Keep a built state: ops[j] = expm(A^T h / 2^j) for j = 0..LEVELS (None: the caller writes them into
        self.ops[index] or shares another's, share; until then zeros, or nothing defined: self.fill)."""
        index = self.slot()
        if ops is not None:
            self.ops[index] = ops
        if events:
            rows = state.events
            if not self.uplift:  # a bonded run with yielding stories: its elements never switch
                rows = rows.copy()
                rows[:soil_rows(self.layout)] = 0.0
            self.events[index] = rows
            event_rates(rows, state.matrix, self.event_rates[index], soil_rows(self.layout))
        elif self.fill is None:  # no event rows: zero, as in arrays that start as zeros
            self.events[index] = self.event_rates[index] = 0.0
        self.matrices[index] = state.matrix.T
        return self.keep(index, pattern, state)

    def slot(self) -> int:
        """The index of the next state to store (its operators in its slot of ops, unless shared), with room."""
        index = len(self.contact)
        if index == self.capacity:
            self._grow()
        self.slots[index], self.keys[index] = index, -1
        return index

    def record(self, key: tuple[int, int], index: int) -> None:
        """State `index` is the first of its key of A (story_states.matrix_key): the states of that A share its
        operators (by_matrix, and keys for the compiled loop)."""
        if key not in self.by_matrix:
            self.by_matrix[key], self.keys[index] = index, key

    def share(self, index: int, source: int) -> None:
        """State `index` steps with the operators of `source` (the same A): its own slot of ops stays unused."""
        self.slots[index] = self.slots[source]

    def keep(self, index: int, pattern: int, state: ContactState) -> int:
        """Keep the state whose operators, event rows, rates and A^T are in slot `index` (slot()); its index."""
        self.patterns[index] = pattern
        self.contact.append(state)
        return index

    def _grow(self) -> None:
        """More room for states: doubled (kept.doubled: zeros, mapped only as stored, or not filled: self.fill; the
        matrices, never read before, not filled)."""
        self.capacity *= 2
        self.ops, self.matrices = doubled(self.ops, self.fill), doubled(self.matrices)
        self.events, self.event_rates = doubled(self.events, self.fill), doubled(self.event_rates, self.fill)
        self.patterns, self.slots = doubled(self.patterns, -1), doubled(self.slots)
        self.rows, self.fields, self.keys = doubled(self.rows), doubled(self.fields), doubled(self.keys)


def block_operators(lay: Layout) -> bool:
    """Whether the step operators come from a small block of each state (a bearing capacity on more than
    BLOCK_ELEMENTS elements: _block_operators)."""
    return bool(lay.n_settlements) and lay.n_elements > BLOCK_ELEMENTS


#: the most memory reserved up front for the operators of one run [bytes] (virtual: untouched
#: pages cost nothing); beyond it the arrays double as states are added
RESERVE_BYTES = 2**30


#: the most memory reserved up front for the operators of a run with yielding stories [bytes]: below the
#: allocator's threshold for a mapping of its own (runtime/process.MMAP_THRESHOLD, 32 MiB), whose pages would
#: be faulted in again by every run
STORY_RESERVE_BYTES = 30 * 2**20
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
    """Memory of the step operators of one contact state [bytes] (LEVELS + 1 of n_aug^2: 450 kB on 20 elements)."""
    return (LEVELS + 1) * lay.n_aug**2 * 8


def reserved_states(lay: Layout) -> int:
    """How many contact states a run's operator arrays hold before they first grow: 4, or on a yielding
    mat of many elements twice expected_states (2 n_e^2), so that the 450 kB per state of such a run
    are not copied at every doubling (a fifth of its run time, measured); with yielding stories (on no such
    mat) twice expected_states, at most STORY_RESERVE_BYTES: their arrays are not filled (Operators.fill), so
    a run that never yields touches the pages of its few states only, and one that does seldom copies (the
    README example: 151 states, 122 bonded, in 209 to 271; its period swept over 0.4-0.8 s at most 175, and
    the twin of a residual check adds its own; growing fourfold from 4 copied 84 states, 9.5 MB)."""
    if lay.n_plastic and not block_operators(lay):
        return max(4, min(2 * expected_states(lay), STORY_RESERVE_BYTES // state_bytes(lay)))
    expected = lay.n_elements**2 if block_operators(lay) else 0
    if not expected:
        return 4
    return max(4, min(2 * expected, RESERVE_BYTES // state_bytes(lay)))


def max_states(lay: Layout) -> int:
    """The most distinct contact states one run may build: within limits.MAX_OPERATOR_BYTES (1,885 on 31 elements)."""
    return max(64, MAX_OPERATOR_BYTES // state_bytes(lay))


def _too_many_states(lay: Layout) -> str:
    return (f"the run met more than {max_states(lay):,} distinct contact states, whose step operators would exceed "
            f"{MAX_OPERATOR_BYTES / 2**30:g} GiB: the contact chatters; give the foundation more damping, fewer "
            "elements (foundation.elements) or a lower stiffness")


_NO_INERTIA = ("the mat rotation has neither inertia nor damping in this contact state "
               "(all damping ratios 0 and no element damping): give the mat a rotary inertia I_0 > 0")
_LIFTED_AND_YIELDING = ("a contact element started to lift off and to yield at the same instant (its dashpot "
                        "force balanced its capacity exactly): reduce the time step (analysis.exact.time_step)")
_BOTH_WAYS = ("a story started to yield both ways at the same instant: reduce the time step "
              "(analysis.exact.time_step)")


def add_states(requests: list[tuple[Operators, int, bool]]) -> list[int | AnalysisError]:
    """Build and store the contact states asked for, (operators, pattern, with event rows)
    each, vectorised over the requests that share a layout: one batched assembly
    (patterns.contact_states), one stacked expm and stacked squarings (the operators of states
    where a story yields: level_operators.state_levels, each written in place). Each item gets the
    same bits as built alone (the one request of each yielding-story run: story_requests.py, without this
    batch machinery). Returns the new state index, or the error, per request."""
    quick = add_quick(requests)
    if quick is not None:
        return quick
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
        for k, state, key in copies:  # the same A as a state built before: its operators, no copy
            operators, pattern, events = requests[k]
            out[k] = operators.store(pattern, state, None, events)
            operators.share(out[k], operators.by_matrix[key])
    return out


def _exponentiated(requests: list[tuple[Operators, int, bool]], built: list[tuple[int, ContactState, tuple | None]],
                   out: list[int | AnalysisError]) -> None:
    """Store the states `built` ((index, state, key of A: _shared_operators; one layout)): those of yielding stories
    with their operators written in place (level_operators.state_levels: the Taylor polynomial and squarings, in
    C), where no story yields those of the entries other than the plastic drifts then the elastic building's
    (level_operators.elastic_operators); those of an elastic building from one stacked exponentiation (_stacked);
    in the order of `built`."""
    if built[0][2] is None:  # an elastic building (every key None)
        _stacked(requests, built, out)
        return
    for k, state, key in built:
        out[k] = _stored(requests[k], state, key, None)
    elastic_operators([(requests[k][0].ops[out[k]], state, requests[k][0].h) for k, state, _ in built],
                      requests[built[0][0]][0].layout)


def _stacked(requests: list[tuple[Operators, int, bool]], built: list[tuple[int, ContactState, None]],
             out: list[int | AnalysisError]) -> None:
    """Store the states `built` of an elastic building with their operators from one stacked exponentiation
    (_level_operators), the settlements of elements that do not yield held (_held)."""
    stacked = _level_operators(requests, [(k, state) for k, state, _ in built])
    for (k, state, key), ops in zip(built, stacked, strict=True):
        out[k] = _stored(requests[k], state, key, _held(ops, state, requests[k][0]))


def _stored(request: tuple[Operators, int, bool], state: ContactState, key: tuple | None, ops: np.ndarray | None
            ) -> int:
    """Store a state with the operators `ops` (of the stacked exponentiation, its constant entries held: _held),
    or (None) with those level_operators.state_levels writes into its slot; its index (kept under its key of A
    where it has one)."""
    operators, pattern, events = request
    index = operators.store(pattern, state, ops, events)
    if ops is None:
        state_levels(state.matrix, operators.h, operators.ops[index])
    if key is not None:
        operators.record(key, index)
    return index


def _held(ops: np.ndarray, state: ContactState, operators: Operators) -> np.ndarray:
    """The stacked exponentiation's operators of a state of an elastic building with the settlements of elements
    that do not yield held exactly (constant entries)."""
    if state.yielding is not None:
        hold_settlements(ops, operators.layout.settlement_indices[~state.yielding])
    return ops


def _level_operators(requests: list[tuple[Operators, int, bool]], built: list[tuple[int, ContactState]]
                     ) -> np.ndarray:
    """E_j^T, j = 0..LEVELS, of each state of `built` (of an elastic building) in one stacked exponentiation
    (level_operators.stacked_operators)."""
    if not built:
        return np.empty((0, LEVELS + 1, 0, 0))
    a_t = np.stack([state.matrix.T for _, state in built])
    return stacked_operators(a_t, np.array([requests[k][0].h for k, _ in built])[:, None, None])


def _shared_operators(requests: list[tuple[Operators, int, bool]], built: list[tuple[int, ContactState]]
                      ) -> tuple[list[tuple[int, ContactState, tuple | None]], list[tuple[int, ContactState, tuple]]]:
    """(index, state, key) of the states of `built` whose operators are to be computed, and of those whose A
    is that of a state built before or earlier in `built`, which share its operators once it is stored; the key
    of A (yielding stories: story_states.matrix_key, else None)."""
    fresh, copies, first = [], [], set()
    for k, state in built:
        operators, pattern, _ = requests[k]
        if state.story_sign is None:
            fresh.append((k, state, None))
            continue
        key = matrix_key(pattern, operators.layout)
        if key in operators.by_matrix or (id(operators), key) in first:
            copies.append((k, state, key))
            continue
        first.add((id(operators), key))
        fresh.append((k, state, key))
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
        if len(operators.contact) + asked[id(operators)] > operators.most_states:
            out[k] = AnalysisError(_too_many_states(lay))
            continue
        groups.setdefault(operators.group, []).append(k)
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
                hold_settlements(operators.ops[index], operators.layout.plastic_indices[state.story_sign == 0])


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
