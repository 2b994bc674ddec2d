"""Energy balance of a simulated history (docs/theory.md, the exact engine's checks):
input work = change of kinetic, strain, foundation elastic and gravity energy + structural
and foundation damping (+ the plastic work of yielding soil, docs/theory.md 14.5).

Work integrals: the exact integrals (the Gram matrix and moments of the basis) of the quintic Hermite
interpolants of the signals through their values, exact slopes and exact curvatures (X'' = A^2 X, read
off response.signals) at both ends of every interval (O(h^6), the compiled loop _energy.c or its twin
energy_numpy.py); stored energies exact at the first and last samples. The state-space maps come from
the history (History.space).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ...runtime import backend
from .stories import stored_strain

if TYPE_CHECKING:
    from .response import Signals
    from .statespace import StateSpace
    from .stepping import History


def _loops():
    """The module that runs the work integrals: _energy (C) or energy_numpy (upliftcli.runtime.backend)."""
    return backend.loops(f"{__package__}._energy", f"{__package__}.energy_numpy")


def work(history: History, sig: Signals) -> tuple[float, float, float]:
    """Input work, structural damping and foundation damping energy [J] over the history's
    intervals (additive: a run stepped in chunks sums them)."""
    space = history.space
    rows, curved = sig.rows, sig.curvatures
    work_in, damp_struct, damp_found = _loops().work_integrals(
        sig.values, sig.slopes, sig.end_values, sig.end_slopes, sig.switch, sig.state_index, sig.slope_rows,
        history.lengths, np.ascontiguousarray(history.lifted[:-1]), rows["a"].start, rows["input"].start,
        rows["Ydot"].start, space.model.n_modes, rows["element_velocity"].start, rows["z"].start,
        space.layout.n_elements, curved["Ydot"].start, curved["input"].start, curved["element_velocity"].start,
        space.c_modal, space.element_stiffness, space.element_damping,
    )
    return float(work_in), float(damp_struct), float(damp_found)


def stored(history: History, sig: Signals, index: int) -> tuple[float, ...]:
    """Kinetic, strain, foundation elastic and gravity energy [J] at one sample; with a bearing
    capacity also -sum_i Q_i s_i [J], whose change is the plastic work W_p (docs/theory.md 14.5:
    the foundation elastic energy then uses the springs' deformations v_i - s_i, z_i - s_i)."""
    space = history.space
    model = space.model
    x = history.states[index]
    contact = history.contact[history.state_ids[index]]
    kinetic = 0.5 * np.sum(space.masses * (contact.velocity @ x) ** 2)
    strain = 0.5 * np.sum(space.k_modal * sig["Y"][index] ** 2)
    if space.layout.n_plastic:  # the yielding stories' springs act on d_j - p_j (docs/theory.md 15.3)
        strain += stored_strain(space.model.stories, space.drift_rows @ x, x[space.layout.plastic_indices])
    foundation = gravity = 0.0
    if space.layout.n_elements:
        k_el, c_el = space.element_stiffness, space.element_damping
        z = np.where(c_el > 0.0, sig["z"][index], 0.0)
        deformation = np.where(contact.lifted, z, sig["element_displacement"][index])
        foundation = 0.5 * np.sum(k_el * deformation**2)
        gravity = model.total_mass * model.gravity * sig["v"][index, 0]
    if space.layout.n_settlements:
        plastic = -float(np.sum(space.element_capacity * x[space.layout.settlement_indices]))
        return float(kinetic), float(strain), float(foundation), float(gravity), plastic
    return float(kinetic), float(strain), float(foundation), float(gravity)


def balance(space: StateSpace, works: tuple[float, float, float], first: tuple, last: tuple,
            hysteretic: float | None = None) -> dict:
    """The energy terms [J] of a run from its work integrals and its stored energies at the
    first and the last sample (and the hysteretic energy of yielding stories, docs/theory.md 15.3);
    residual and relative residual."""
    work_in, damp_struct, damp_found = works
    terms = {"input": work_in}
    for k, name in enumerate(("kinetic", "strain", "foundation_elastic", "gravity", "plastic_work")[:len(first)]):
        terms[name] = float(last[k] - first[k])
    terms["structural_damping"] = damp_struct
    terms["foundation_damping"] = damp_found
    if hysteretic is not None:
        terms["hysteretic"] = float(hysteretic)
    total = sum(v for k, v in terms.items() if k != "input")
    # relative to the work done, or (no ground motion) to a billionth of the static foundation
    # energy, so that round-off at rest is not a residual
    scale = max(abs(work_in), damp_struct + damp_found, 1e-9 * space.weight * space.settlement, 1e-300)
    terms["residual"] = float(work_in - total)
    terms["relative_residual"] = float(abs(work_in - total) / scale)
    return terms


def energy_balance(history: History, sig: Signals) -> dict:
    """Input = kinetic + strain + damping + foundation (+ gravity) energies [J] of one history."""
    return balance(history.space, work(history, sig), stored(history, sig, 0), stored(history, sig, -1))
