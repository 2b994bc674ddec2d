"""Compiled stepping loop: the matrix-vector product and the interior-excursion test."""

from __future__ import annotations

import numpy as np
import pytest

from upliftcli.engines.exact import stepping_kernels as kernel


def test_matvec_takes_the_transposed_matrix():
    rng = np.random.default_rng(1)
    matrix, x = rng.normal(size=(7, 7)), rng.normal(size=7)
    out = np.empty(7)
    kernel.matvec(np.ascontiguousarray(matrix.T), x, out)
    np.testing.assert_allclose(out, matrix @ x)


def test_matvec_sums_each_output_in_the_order_of_its_terms_at_every_width():
    """The compiled product keeps up to 51 outputs in registers, a copy per width (transitions.h,
    register_product): every output is the sum over q = 0, 1, ... from +0 of its products, those of zero
    inputs left out, bit for bit, at every width and wider (strided_product)."""
    from upliftcli.engines.exact import _stepping  # the compiled loop itself, whichever backend runs

    rng = np.random.default_rng(7)
    for n in range(1, 56):
        matrix_t = rng.normal(size=(n, n))
        x = rng.normal(size=n)
        x[rng.random(n) < 0.3] = 0.0  # zero inputs, alone and in pairs
        out = np.empty(n)
        _stepping.matvec(matrix_t, x, out)
        expected = []
        for r in range(n):
            total = 0.0
            for q in range(n):
                if x[q] != 0.0:
                    total += float(matrix_t[q, r]) * float(x[q])
            expected.append(total)
        assert out.tobytes() == np.array(expected).tobytes(), n


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

    from upliftcli.engines.exact.patterns import contact_states

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

    from upliftcli.engines.exact.modal import modal_model
    from upliftcli.engines.exact.statespace import state_space
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


# ----------------------------------------------------------------------------- argument checks of the C loop

def test_integrate_refuses_every_wrong_argument_with_an_exception():
    """The compiled loop checks every array shape, index and limit it follows before it runs: a
    wrong caller gets a Python exception, never a write out of bounds."""
    from backends import compiled_or_skip
    from paper_example import paper_system

    from upliftcli.engines.exact.modal import modal_model
    from upliftcli.engines.exact.operators import add_states
    from upliftcli.engines.exact.statespace import state_space
    from upliftcli.engines.exact.stepping import Run

    compiled_or_skip()
    from upliftcli.engines.exact import _stepping

    space = state_space(modal_model(paper_system(0.5), "uplift", 3))
    ground = 0.01 * np.sin(np.arange(201) * 0.05)  # small: no lift-off
    run = Run(space, ground, np.diff(ground, append=0.0) / 0.005, 0.005)
    (index,) = add_states([run.first_request()])
    ops = run.operators

    def arguments(**change):
        states = dict(zip(kernel.States._fields, (ops.ops, ops.slots, ops.events, ops.event_rates, ops.matrices,
                                                 ops.patterns, len(ops.contact)), strict=True))
        elements, grid = run.elements._asdict(), run.grid._asdict()
        samples = dict(x=run.x.copy(), out_x=run.out_x, out_t=run.out_t, out_state=run.out_s)
        scalars = dict(state=index, step=0, offset=0.0, n_out=0)
        for name, value in change.items():
            for group in (states, elements, grid, samples, scalars):
                if name in group:
                    group[name] = value
        return (tuple(states.values()), tuple(elements.values()), tuple(grid.values()), tuple(samples.values()),
                *scalars.values())

    status, *_ = _stepping.integrate(*arguments())
    assert status == kernel.DONE
    n_aug, n_e = space.layout.n_aug, space.layout.n_elements
    wrong = {
        "z_index": np.array([0, n_aug], dtype=np.int64),  # an element's top outside the state
        "lift_rows": np.zeros((n_e, n_aug - 1)),
        "damped": np.ones(n_e + 1, dtype=bool),
        "count": ops.ops.shape[0] + 1,  # more states than operators
        "slots": np.full(ops.slots.size, ops.ops.shape[0]),  # a state's operators outside ops
        "patterns": np.zeros(0, dtype=np.int64),
        "levels": 3,  # fewer bisection levels than the refinement uses
        "index_acceleration": n_aug,
        "index_slope": -1,
        "slopes": np.zeros(10),
        "h": 0.0,
        "state": 5,
        "step": 201,
        "offset": float("nan"),
        "n_out": run.out_t.size + 1,
        "out_x": np.zeros((3, n_aug)),
        "out_state": np.zeros(3, dtype=np.int64),
        "x": np.zeros(n_aug + 1),
        "ground": np.zeros((2, 3)),  # 2-D
        "ops": ops.ops[:, :, :-1, :-1],
    }
    for name, value in wrong.items():
        with pytest.raises((ValueError, TypeError)):
            _stepping.integrate(*arguments(**{name: value}))
    with pytest.raises(TypeError, match="states must be a tuple of 7 items"):
        _stepping.integrate(arguments()[0][:6], *arguments()[1:])
    with pytest.raises(TypeError, match="takes 8 arguments"):
        _stepping.integrate(*arguments()[:7])
