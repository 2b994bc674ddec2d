"""Compiled stepping loop: the matrix-vector product and the interior-excursion test."""

from __future__ import annotations

import numpy as np

from upliftcli.engines.exact import stepping_kernels as kernel


def test_matvec_takes_the_transposed_matrix():
    rng = np.random.default_rng(1)
    matrix, x = rng.normal(size=(7, 7)), rng.normal(size=7)
    out = np.empty(7)
    kernel.matvec(np.ascontiguousarray(matrix.T), x, out)
    np.testing.assert_allclose(out, matrix @ x)


def test_excursion_flags_a_positive_bump_between_negative_ends():
    """g(t) = -(t - 0.5)^2 + 0.01 on [0, 1]: negative at both ends, positive in between."""
    events = np.array([[1.0, 0.0]])   # g = x[0]
    rates = np.array([[0.0, 1.0]])    # g' = x[1]
    start = np.array([-0.24, 1.0])    # g(0) = -0.24, g'(0) = 1
    end = np.array([-0.24, -1.0])     # g(1) = -0.24, g'(1) = -1
    assert kernel.excursion(events, rates, start, end, 1.0)
    lower = np.array([-0.26, 1.0]), np.array([-0.26, -1.0])  # peak -0.01: no excursion
    assert not kernel.excursion(events, rates, *lower, 1.0)
    assert not kernel.excursion(events, rates, np.array([-0.2, -1.0]), np.array([-0.3, 0.5]), 1.0)


# ----------------------------------------------------------------------------- numpy twin of integrate

def _integrate_twin(space, ground, slopes, h, criterion="reaction", probes=8):
    """The stepping loop written plainly: each step by expm(A h); a crossing of an event function
    (probed at `probes` points inside the step) located by brentq on the exact flow; the
    elements at zero switch (a lifting one's top starts at the edge); the step goes on from
    there in the new state. Returns the transition times and the state at the end."""
    from scipy.linalg import expm
    from scipy.optimize import brentq

    from upliftcli.engines.exact.statespace import contact_states

    lay = space.layout
    built = {}

    def state_of(pattern):
        if pattern not in built:
            lifted = np.array([[(pattern >> i) & 1 for i in range(lay.n_elements)]], dtype=bool)
            built[pattern] = contact_states([space], lifted, criterion)[0]
        return built[pattern]

    x, pattern, transitions = space.rest.copy(), 0, []
    for step in range(ground.size - 1):
        x[lay.index_acceleration], x[lay.index_slope] = ground[step], slopes[step]
        t = 0.0
        while t < h:
            state = state_of(pattern)

            def flow(tau, x=x, state=state):
                return expm(state.matrix * tau) @ x

            def g(tau, state=state, flow=flow):
                return (state.events @ flow(tau)).max()

            grid = np.linspace(0.0, h - t, probes + 1)[1:]
            positive = [tau for tau in grid if g(tau) > kernel.EVENT_TOLERANCE]
            if not positive:
                x = flow(h - t)
                break
            hi = positive[0]
            lo = max([tau for tau in grid if tau < hi], default=0.0)
            tau = brentq(lambda s: g(s) - kernel.EVENT_TOLERANCE, lo, hi, xtol=1e-15, rtol=1e-15)
            x, after = flow(tau), flow(min(tau + (h - t) / 4096, h - t))
            for i in range(lay.n_elements):
                if state.events[i] @ x >= -1e-9 and state.events[i] @ after > kernel.EVENT_TOLERANCE:
                    pattern ^= 1 << i
                    if (pattern >> i) & 1:
                        x[lay.z_indices[i]] = space.displacement_rows[i] @ x if space.element_damping[i] > 0 else 0.0
            t += tau
            transitions.append(step * h + t)
    x[lay.index_acceleration] = ground[-1]
    return np.array(transitions), x


def test_integrate_equals_its_numpy_twin_through_lift_offs_and_recontacts():
    from paper_example import paper_system

    from upliftcli.engines.exact.statespace import modal_model, state_space
    from upliftcli.engines.exact.stepping import ground_grid, simulate
    from upliftcli.motion.records import bundled_records_dir, read_record

    record = read_record(bundled_records_dir() / "elcentro_1940_ns_chopra.txt")
    acceleration = 2.0 * record.acceleration[:101]  # 2 s, twice El Centro: several lift-offs
    system = paper_system(0.5)
    space = state_space(modal_model(system, "uplift", 10))
    substeps = 2
    ((_, history),) = list(simulate([space], [substeps], acceleration, record.dt, "reaction", uplift=True,
                                    allow_flight=True))
    changes = np.nonzero(np.diff(history.state_ids))[0] + 1
    ground, slopes = ground_grid(acceleration, substeps, record.dt)
    transitions, end = _integrate_twin(space, ground, slopes, record.dt / substeps)
    assert transitions.size == changes.size >= 4
    np.testing.assert_allclose(history.times[changes], transitions, atol=1e-9)
    np.testing.assert_allclose(history.states[-1], end, rtol=1e-7, atol=1e-9 * np.abs(end).max())
