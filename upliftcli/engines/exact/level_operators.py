"""The step operators of one contact state at every bisection level, E_j^T = expm(A h / 2^j)^T,
j = 0..LEVELS (level 0 steps, the finer ones bisect a crossing: docs/theory.md sections 4 and 15.9),
stored transposed as the stepping loop reads them. Two constructions:

- every state of a building whose stories yield: the Taylor polynomial of the finest level and squarings, in C
  (_levels.c) or its numpy twin (levels_numpy.py), written straight into the run's operator array
  (state_levels); where no story yields, the entries other than the plastic drifts then get the elastic
  building's operators (elastic_stories: such a run must stay the elastic one bit for bit);
- the states of an elastic building, and those elastic building's operators: the [13/13] Pade exponentials of
  the finest and of the coarsest level of a stack of states, squarings between (stacked_operators).
"""

from __future__ import annotations

from types import ModuleType

import numpy as np

from ...runtime import backend
from .expm import expm
from .statespace import ContactState, Layout

#: levels of bisection operators: crossings are bracketed to h / 2^LEVELS, then interpolated
LEVELS = 12


def loops() -> ModuleType:
    """The module that computes a yielding state's operators and rows now: _levels.c or levels_numpy.py, as
    upliftcli.runtime.backend chooses (asked once per run's operators: operators.Operators.levels)."""
    return backend.loops(f"{__package__}._levels", f"{__package__}.levels_numpy")


def state_levels(matrix: np.ndarray, h: float, ops: np.ndarray) -> None:
    """ops[j] = expm(A h / 2^j)^T, j = 0..L, of A = matrix (n, n), written whole into ops (L + 1, n, n; a
    state's slot of Operators.ops): _levels.c or levels_numpy.py, as upliftcli.runtime.backend chooses. The
    zero rows of A (the plastic drifts of elastic stories, the settlements of elements that do not yield)
    are unit rows of the operators exactly."""
    loops().state_levels(matrix, float(h), ops)


def story_rows(bits: int, table: np.ndarray, picks: np.ndarray, rows: np.ndarray, events: np.ndarray,
               rates: np.ndarray, matrix_t: np.ndarray, fields: np.ndarray, zero_rows: int, soil_rows: int) -> None:
    """The rows of one state of yielding stories taken from its base's table, written into rows, events (a
    state's slot of Operators.events) and matrix_t (of Operators.matrices), its stories' fields into fields and
    the rates of its stories' event rows into rates (of Operators.event_rates; levels_numpy.story_rows):
    _levels.c or levels_numpy.py, as upliftcli.runtime.backend chooses."""
    loops().story_rows(bits, table, picks, rows, events, rates, matrix_t, fields, zero_rows, soil_rows)


def stacked_operators(a_t: np.ndarray, h: np.ndarray) -> np.ndarray:
    """E_j^T = expm(A h / 2^j)^T, j = 0..LEVELS, of a stack of A^T (R, n, n) with steps h (R, 1, 1):
    the finest level by expm, the coarser ones by squaring it, level 0 by its own expm. Transposed
    (the kernel's matvec runs down columns): (E^T)^2 = (E^2)^T."""
    ops = np.empty((a_t.shape[0], LEVELS + 1, *a_t.shape[1:]))
    ops[:, LEVELS] = expm(a_t * (h / 2.0**LEVELS))
    for j in range(LEVELS - 1, 0, -1):
        ops[:, j] = ops[:, j + 1] @ ops[:, j + 1]
    ops[:, 0] = expm(a_t * h)
    return ops


def hold_settlements(ops: np.ndarray, constant: np.ndarray) -> None:
    """Make the settlements s_i of elements that do not yield exactly constant in the step
    operators (ops: E^T per level, in place): their rows of A are zero, so the rows of E = expm(A h)
    are unit rows, which the computed exponentials hold only to a few units in the last place (a
    drift of 4e-13 of s_i per step, measured)."""
    ops[:, :, constant] = 0.0
    ops[:, constant, constant] = 1.0


def elastic_stories(ops: np.ndarray, state: ContactState, lay: Layout, h: float, block: np.ndarray | None = None
                    ) -> None:
    """The step operators (E^T per level, in place: state_levels') of a state with yielding stories where none
    yields: the plastic drifts held exactly (hold_settlements), and the operators of the other entries from the
    exponential of A without the plastic drifts: the matrix and the operators of the elastic building, bit for
    bit (the plastic drifts, zero until a story yields, do not change its history: docs/theory.md 15.4; their
    columns, state_levels', multiply zeros there); block: those operators where computed already
    (elastic_blocks), else computed here."""
    hold_settlements(ops, lay.plastic_indices[state.story_sign == 0])
    if np.any(state.story_sign != 0):
        return
    keep = _kept(lay)
    if block is None:
        block = elastic_blocks([state], lay, [h])[0]
    ops[:, keep[:, None], keep[None, :]] = block


def elastic_operators(slots: list[tuple[np.ndarray, ContactState, float]], lay: Layout) -> None:
    """elastic_stories of each slot (its operators E^T per level, in place: state_levels', its state, its step h)
    whose state has no story yielding, their blocks from one stacked exponentiation (elastic_blocks)."""
    calm = [slot for slot in slots if not slot[1].story_sign.any()]
    blocks = elastic_blocks([state for _, state, _ in calm], lay, [h for _, _, h in calm])
    for (ops, state, h), block in zip(calm, blocks, strict=True):
        elastic_stories(ops, state, lay, h, block)


def elastic_blocks(states: list[ContactState], lay: Layout, h: list[float]) -> list[np.ndarray | None]:
    """The operators (LEVELS + 1, n, n) of A without the plastic drifts of each state with yielding stories where
    none yields (their steps h), in one stacked exponentiation: each the same bits as alone (stacked_operators
    exponentiates and squares each matrix of the stack by itself); None for a state of an elastic building."""
    wanted = [i for i, state in enumerate(states) if state.story_sign is not None]
    out: list[np.ndarray | None] = [None] * len(states)
    if wanted:
        blocks = _reduced_operators([states[i].matrix for i in wanted], _kept(lay), [h[i] for i in wanted])
        for i, block in zip(wanted, blocks, strict=True):
            out[i] = block
    return out


def _reduced_operators(matrices: list[np.ndarray], keep: np.ndarray, h: list[float]) -> np.ndarray:
    """stacked_operators of the matrices restricted to the entries `keep`, with steps h."""
    reduced = np.stack([matrix[np.ix_(keep, keep)].T for matrix in matrices])
    return stacked_operators(reduced, np.array(h)[:, None, None])


def _kept(lay: Layout) -> np.ndarray:
    """The indices of the entries other than the plastic drifts."""
    return np.delete(np.arange(lay.n_aug), lay.plastic_indices)  # not setdiff1d: it imports numpy.ma (8 ms)
