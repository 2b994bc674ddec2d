"""Energy balance of a simulated history (docs/theory.md, the exact engine's checks):
input work = change of kinetic, strain, foundation elastic and gravity energy + structural
and foundation damping.

Work integrals: 3-point Gauss quadrature on the cubic Hermite interpolants of the signals
(O(h^4), response_kernels.work_integrals); stored energies exact at the first and last
samples. The state-space maps come from the history (History.space).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import response_kernels

if TYPE_CHECKING:
    from .response import Signals
    from .stepping import History


def energy_balance(history: History, sig: Signals) -> dict:
    """Input = kinetic + strain + damping + foundation (+ gravity) energies [J]."""
    space = history.space
    model, lay = space.model, space.layout
    lengths = history.lengths
    lifted = np.ascontiguousarray(history.lifted[:-1])
    k_el, c_el = space.element_stiffness, space.element_damping
    rows = sig.rows
    work_in, damp_struct, damp_found = response_kernels.work_integrals(
        sig.values, sig.slopes, sig.switch, sig.end_values, sig.end_slopes, lengths, lifted,
        rows["Yddot"].start, rows["a"].start, rows["input"].start, rows["Ydot"].start, model.n_modes,
        rows["element_velocity"].start, rows["z"].start, lay.n_elements, space.c_modal, k_el, c_el,
    )

    def stored(index: int) -> tuple[float, float, float, float]:
        x = history.states[index]
        contact = history.contact[history.state_ids[index]]
        kinetic = 0.5 * np.sum(space.masses * (contact.velocity @ x) ** 2)
        strain = 0.5 * np.sum(space.k_modal * sig["Y"][index] ** 2)
        foundation = gravity = 0.0
        if lay.n_elements:
            z = np.where(c_el > 0.0, sig["z"][index], 0.0)
            deformation = np.where(contact.lifted, z, sig["element_displacement"][index])
            foundation = 0.5 * np.sum(k_el * deformation**2)
            gravity = model.total_mass * model.gravity * sig["v"][index, 0]
        return kinetic, strain, foundation, gravity

    first, last = stored(0), stored(-1)
    terms = {"input": float(work_in)}
    for k, name in enumerate(("kinetic", "strain", "foundation_elastic", "gravity")):
        terms[name] = float(last[k] - first[k])
    terms["structural_damping"] = float(damp_struct)
    terms["foundation_damping"] = float(damp_found)
    balance = sum(v for k, v in terms.items() if k != "input")
    # relative to the work done, or (no ground motion) to a billionth of the static foundation
    # energy, so that round-off at rest is not a residual
    scale = max(abs(work_in), damp_struct + damp_found, 1e-9 * space.weight * space.settlement, 1e-300)
    terms["residual"] = float(work_in - balance)
    terms["relative_residual"] = float(abs(work_in - balance) / scale)
    return terms
