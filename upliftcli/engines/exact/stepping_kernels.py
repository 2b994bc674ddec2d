"""The stepping loop of the exact engine: compiled (C: _stepping.c, built at install) or its
numpy twin (stepping_numpy.py), as upliftcli.runtime.backend chooses.

For each contact state s the caller supplies the exact step operators
ops[slots[s], j] = expm(A_s h / 2^j)^T, j = 0..L, of the augmented autonomous system (see
statespace.py), the event rows G_s, their rates G_s A_s and A_s^T (operators and
matrices are passed transposed: see matvec). A step of length h is one
matrix-vector product. When an event function turns positive at the end of a chunk,
the crossing is bracketed by bisection with the finer operators (one product per
halving, exact at every level) down to h / 2^L, then placed by linear interpolation
inside that last sliver; the state switches there and the rest of the step is
integrated in the new state, itself checked for events. Nothing is rounded to a step
boundary (docs/theory.md section 4).

Status codes returned: DONE, NEED_STATE (a contact pattern without operators was
reached that the loop does not build itself (Builds): the caller builds them and calls
again), FULL (the sample buffer is full), FLIGHT (both edges lifted and flight is
refused), NONFINITE, CHATTER (more than MAX_EVENTS_PER_STEP transitions inside one
step). On NEED_STATE, x and offset are at the event (transition applied): the caller adds
the state, stores the event sample and calls again with the new state. A state the loop
builds itself is entered the same way (the sample where it starts, then on as a new call
would go, a full buffer returned FULL).
"""

from __future__ import annotations

from collections import namedtuple

from ...runtime import backend

DONE, NEED_STATE, FULL, FLIGHT, NONFINITE, CHATTER = 0, 1, 2, 3, 4, 5
#: samples kept free at the start of every step; more events than this inside one step is chatter
MAX_EVENTS_PER_STEP = 256
#: an event function above this is positive (a crossing)
EVENT_TOLERANCE = 1e-12
#: a chunk whose event functions may make a brief positive excursion is halved down to h / 2^this
REFINE_LEVELS = 5
# (the same constants are #defined in _stepping.c and events.h)

#: the contact states built so far: step operators ops[slots[s], j] = expm(A_s h / 2^j)^T (states of
#: the same A share a slot: operators.Operators.share), event rows G_s, their rates G_s A_s, A_s^T, the
#: contact pattern of each and how many there are
States = namedtuple("States", "ops slots events event_rates matrices patterns count")
#: the elements, per event row r (one per element; two with a bearing capacity, yielding.py):
#: the state index set when a crossing of row r turns bit r of the pattern on, the row it is set
#: from (X[z_index[r]] := lift_rows[r] . X where damped[r], else 0: the top z_i of a lifting
#: element, the settlement s_i at the onset of yield), the pattern with every element lifted,
#: and whether flight is allowed
Elements = namedtuple("Elements", "z_index lift_rows damped all_lifted allow_flight")
#: the ground acceleration at every internal step [m/s^2], its slope in each step [m/s^3], the
#: step h [s], the bisection levels L and where a_g and its slope sit in the augmented state
Grid = namedtuple("Grid", "ground slopes h levels index_acceleration index_slope")
#: the state x (updated in place) and the sample buffers (times, states, state ids)
Samples = namedtuple("Samples", "x out_x out_t out_state")
#: what the compiled loop builds the states of yielding stories with, itself (story_requests.loop_builds; the
#: twin builds none): per state its rows (A, then its event rows), its stories' fields and its key of A where
#: its operators are its own (Operators.rows, .fields, .keys); count (1,): the states there are, set by the loop
#: as it builds one; bases: (foundation pattern, StoryBase.table, StoryBase.picks) of each base, at most
#: MAX_BASES; the step h [s], the most states the run may hold, the foundation's event rows (all zero: a rigid
#: or bonded run), the elements and whether they have a bearing capacity
Builds = namedtuple("Builds", "rows fields keys count bases h most_states n_soil n_elements settles")
#: the bases a call of the loop builds states of at most (builds.h)
MAX_BASES = 8


def _loops():
    """The module that runs the loop: _stepping (C) or stepping_numpy (upliftcli.runtime.backend)."""
    return backend.loops(f"{__package__}._stepping", f"{__package__}.stepping_numpy")


def integrator():
    """The integrate function of the loop that runs now (_loops), for a caller that calls it once per contact
    state of a run (stepping.Run: a yielding run returns for each new state, hundreds of times; asking the
    backend at each call cost 2 us of the 9 us a call spends in Python, measured)."""
    return _loops().integrate


def integrate(states: States, elements: Elements, grid: Grid, samples: Samples, state: int, step: int,
              offset: float, n_out: int, builds: Builds | None = None) -> tuple[int, int, float, int, int, int]:
    """Advance from (step, offset) to the end of the ground-motion grid.

    Returns (status, step, offset, state, n_out, pattern) and updates samples.x and the
    sample buffers in place; pattern is the pending contact pattern for NEED_STATE. With builds,
    the compiled loop builds the states of yielding stories it can (builds.h) into the states'
    arrays and says how many there are in builds.count (the caller makes their ContactState:
    story_requests.adopt).
    """
    return _loops().integrate(states, elements, grid, samples, state, step, offset, n_out, builds)


def matvec(matrix_t, x, out) -> None:
    """out = M x from the transposed matrix M^T (how the loop multiplies: along contiguous columns)."""
    _loops().matvec(matrix_t, x, out)


def excursion(events, rates, x, y, length: float) -> bool:
    """True if some event function, not positive at either end of a chunk (states x, y,
    length [s]), has a positive interior maximum on its cubic Hermite interpolant (values
    G x, G y and exact rates G A x, G A y): a brief excursion the chunk ends would miss."""
    return _loops().excursion(events, rates, x, y, float(length))
