"""The project's model built in OpenSeesPy, an independent engine for the rocking analyses (issue 28):
a shear building with lumped floor masses on a rigid mat that rests on the foundation's contact
elements, integrated at a fixed step under a record (docs/theory.md sections 1-4 and 14).

Built from a model.system.System (a shear building: story stiffnesses; two-element or Winkler
foundation; a massless mat as in the paper, or one with m_0 and I_0):

- floors: nodes at (0, h_j) with the horizontal mass m_j and the vertical mass m_j; their vertical
  displacement and rotation are tied to the mat node's (equalDOF), so the floors move with the
  rigid mat (v, theta) and horizontally on their own; the mat's horizontal displacement is fixed
  (no slip), the ground motion acts through it (UniformExcitation: displacements relative to the
  ground, as the project's);
- stories: elastic beam-columns with E I = k_j L^3 / 12 between consecutive floors: with both end
  rotations equal to the mat's, their shear is k_j (relative drift - L theta), the project's story
  spring acting on the deformation u relative to the rotated mat;
- structural damping: stiffness-proportional on the story elements alone (region -rayleigh 0 beta 0 0),
  which is the project's modal damping when xi_n = beta w_n / 2 for every fixed-base mode (the deck
  then gives `building.damping` as that array: stiffness_proportional_damping);
- each contact element i at x_i: a rigid link from the mat node to an edge node; a Kelvin unit
  (spring k_i in parallel with the dashpot c_i) from a fixed ground node to a massless element-top
  node z_i; and a compression-only contact (an elastic-no-tension penalty spring, stiffness
  `penalty` x k_i) from the top to the edge. The contact opens when its force would pull, that is
  when the Kelvin unit's force k z + c z' turns tensile: the project's reaction criterion [4a]; a
  lifted top relaxes by k z + c z' = 0 as the project's does. With a capacity Q_i the spring is
  elastic-perfectly-plastic in compression (ElasticPP yielding at -Q_i, not in tension), the dashpot
  in parallel: the capacity bounds the spring force (docs/theory.md 14.1);
- gravity applied first by a static analysis (all elements in contact), then the record.

Needs `pip install openseespy` (its Linux wheel links the system BLAS: on Debian, the packages
libblas3 and liblapack3).
"""

from __future__ import annotations

import numpy as np

#: stiffness of the contact penalty spring over the element's stiffness
PENALTY = 1.0e4
#: penalty factor of the rigid ties (equalDOF, rigidLink)
PENALTY_TIES = 1.0e17
#: Newton iterations stop when the displacement increment's norm is below this [m] (round-off with
#: the penalty ties is about 1e-12 m)
TOLERANCE = 1.0e-10


def stiffness_proportional_damping(omega: np.ndarray, xi_1: float) -> np.ndarray:
    """xi_n = xi_1 w_n / w_1 [-]: the modal damping of C = beta K with beta = 2 xi_1 / w_1."""
    omega = np.asarray(omega, dtype=float)
    return xi_1 * omega / omega[0]


def damping_beta(system) -> float:
    """beta [s] with C = beta K, checked against the building's modal damping."""
    modes = system.modes
    beta = 2.0 * modes.damping[0] / modes.omega[0]
    if not np.allclose(modes.damping, beta * modes.omega / 2.0, rtol=1e-9, atol=1e-12):
        raise ValueError("the OpenSees model needs stiffness-proportional damping, xi_n = xi_1 w_n/w_1 for every "
                         "mode (stiffness_proportional_damping)")
    return float(beta)


def build(ops, system, support: str = "uplift", penalty: float = PENALTY) -> dict:
    """Build the model in the (wiped) OpenSees domain `ops`; returns the node tags and the data
    the recorders need. support: "uplift" (compression-only contacts) or "bonded" (they pull)."""
    building = system.building
    if building.story_stiffness is None:
        raise ValueError("the OpenSees model is a shear building: give story stiffnesses")
    tags = mat_and_floors(ops, system, support)
    transform, big_area = 1, 1.0  # axial deformation is prevented by the equalDOF ties
    ops.geomTransf("Linear", transform)
    below = tags["mat"]
    for j, (tag, k_j, length) in enumerate(zip(tags["floors"], building.story_stiffness, building.story_heights,
                                                strict=True)):
        inertia = float(k_j) * float(length) ** 3 / 12.0
        ops.element("elasticBeamColumn", 1000 + j, below, tag, big_area, 1.0, inertia, transform)
        below = tag
    stories = [1000 + j for j in range(len(tags["floors"]))]
    ops.region(1, "-ele", *stories, "-rayleigh", 0.0, damping_beta(system), 0.0, 0.0)
    foundation(ops, system, support, penalty, tags)
    return tags


def mat_and_floors(ops, system, support: str) -> dict:
    """The model's frame (2-D, 3 dof a node) and its nodes: the mat (horizontal displacement fixed;
    every dof fixed on the "rigid" support) with its mass and rotary inertia, and the floors (mass m_j
    horizontally and vertically) whose vertical displacement and rotation are the mat's (equalDOF)."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    mat = 1
    ops.node(mat, 0.0, 0.0)
    ops.fix(mat, 1, int(support == "rigid"), int(support == "rigid"))
    ops.mass(mat, 0.0, system.mat_mass, system.mat_rotary_inertia)
    floors = []
    for j, (height, mass) in enumerate(zip(system.building.heights, system.building.masses, strict=True)):
        tag = 10 + j
        ops.node(tag, 0.0, float(height))
        ops.mass(tag, float(mass), float(mass), 0.0)
        ops.equalDOF(mat, tag, 2, 3)
        floors.append(tag)
    positions = system.foundation.contact_elements(system.half_width).positions
    return {"mat": mat, "floors": floors, "positions": positions.copy()}


def foundation(ops, system, support: str, penalty: float, tags: dict) -> None:
    """The foundation's contact elements under the mat (none on the "rigid" support): a Kelvin unit
    from a fixed ground node to the element's top, and a contact from the top to the mat's edge node
    (rigidly linked to the mat), compression-only on the "uplift" support (ENT), elastic on "bonded"."""
    if support == "rigid":
        return
    elements = system.foundation.contact_elements(system.half_width)
    for i, (x, k, c) in enumerate(zip(elements.positions, elements.stiffness, elements.damping, strict=True)):
        ground, top, edge = 100 + 3 * i, 101 + 3 * i, 102 + 3 * i
        for tag in (ground, top, edge):
            ops.node(tag, float(x), 0.0)
        ops.fix(ground, 1, 1, 1)
        ops.fix(top, 1, 0, 1)
        ops.rigidLink("beam", tags["mat"], edge)
        spring, dashpot, kelvin, contact = 10 + 4 * i, 11 + 4 * i, 12 + 4 * i, 13 + 4 * i
        capacity = None if elements.capacity is None else float(elements.capacity[i])
        if capacity is None:
            ops.uniaxialMaterial("Elastic", spring, float(k))
        else:
            ops.uniaxialMaterial("ElasticPP", spring, float(k), 1e10, -capacity / float(k))
        if c > 0.0:
            ops.uniaxialMaterial("Viscous", dashpot, float(c), 1.0)
            ops.uniaxialMaterial("Parallel", kelvin, spring, dashpot)
        else:
            kelvin = spring
        if support == "uplift":
            ops.uniaxialMaterial("ENT", contact, penalty * float(k))
        else:
            ops.uniaxialMaterial("Elastic", contact, penalty * float(k))
        ops.element("zeroLength", 2000 + 2 * i, ground, top, "-mat", kelvin, "-dir", 2)
        ops.element("zeroLength", 2001 + 2 * i, top, edge, "-mat", contact, "-dir", 2)


def solver(ops, test: tuple) -> None:
    # penalty ties: a Transformation handler made anew for the transient analysis starts the tied
    # nodes from zero displacement, not from the static state (the mat then falls)
    ops.constraints("Penalty", PENALTY_TIES, PENALTY_TIES)
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test(*test, 50, 0)
    ops.algorithm("Newton")


def gravity(ops, system, tags: dict) -> None:
    """The weight applied in one static step (all contacts closed: linear)."""
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    g = system.gravity
    ops.load(tags["mat"], 0.0, -system.mat_mass * g, 0.0)
    for tag, mass in zip(tags["floors"], system.building.masses, strict=True):
        ops.load(tag, 0.0, -float(mass) * g, 0.0)
    # one linear step: its unbalance after the first solve is round-off (the displacement increment
    # of a stiffer contact penalty may stay above TOLERANCE), so the test is on the force
    solver(ops, ("NormUnbalance", 1e-6 * system.weight))
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees: the static analysis under gravity did not converge")
    ops.loadConst("-time", 0.0)


def advance(ops, dt: float, depth: int = 0) -> None:
    """One step of dt [s]; on failure the step is split (down to dt / 2^6), then given up."""
    if ops.analyze(1, dt) == 0:
        return
    if depth == 6:
        raise RuntimeError(f"OpenSees: no convergence at t = {ops.getTime():.6f} s")
    advance(ops, dt / 2.0, depth + 1)
    advance(ops, dt / 2.0, depth + 1)


def start_transient(ops, system, tags: dict, acceleration: np.ndarray, record_dt: float, integrator: tuple) -> None:
    """Gravity (a static step), then the record as a uniform excitation of the horizontal dof and the
    transient analysis set up with `integrator` (Newmark's parameters: the step's own tolerance)."""
    gravity(ops, system, tags)
    ops.timeSeries("Path", 2, "-dt", float(record_dt), "-values", *np.asarray(acceleration, dtype=float).tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.wipeAnalysis()
    solver(ops, ("NormDispIncr", TOLERANCE))
    ops.integrator(*integrator)
    ops.analysis("Transient")


def run(system, acceleration: np.ndarray, record_dt: float, dt: float, support: str = "uplift",
        penalty: float = PENALTY, integrator: tuple = ("Newmark", 0.5, 0.25)) -> dict[str, np.ndarray]:
    """Histories at every step dt [s] (SI; the project's signs: theta > 0 lifts the left edge):
    time, theta, v, left/right edge displacement (at the outermost elements: v - x_i theta),
    base shear V_b = k_1 u_1, base moment
    M_b = sum_j h_j (K u)_j, roof displacement relative to the mat u_N, each element's reaction on
    the mat R_i = -F_i [N] (> 0 in compression, docs/theory.md [3a]). acceleration [m/s^2] sampled
    at record_dt [s]."""
    import openseespy.opensees as ops

    ops.logFile("/dev/null", "-noEcho")  # OpenSees prints every split step: the histories say enough
    tags = build(ops, system, support, penalty)
    start_transient(ops, system, tags, acceleration, record_dt, integrator)
    building = system.building
    heights, stiffness = building.heights, building.stiffness
    count = round((acceleration.size - 1) * record_dt / dt)
    n_e = tags["positions"].size
    out = {name: np.empty(count + 1) for name in ("time", "theta", "v", "base_shear", "base_moment", "roof")}
    out["reaction"] = np.empty((count + 1, n_e))
    for step in range(count + 1):
        if step:
            advance(ops, dt)
        theta = -ops.nodeDisp(tags["mat"], 3)
        x = np.array([ops.nodeDisp(tag, 1) for tag in tags["floors"]])
        u = x - heights * theta
        out["time"][step] = ops.getTime()
        out["theta"][step] = theta
        out["v"][step] = ops.nodeDisp(tags["mat"], 2)
        out["base_shear"][step] = building.story_stiffness[0] * u[0]
        out["base_moment"][step] = heights @ (stiffness @ u)
        out["roof"][step] = u[-1]
        # the contact's resisting force at its lower node (the top): -F_i, the upward reaction on the mat
        out["reaction"][step] = [ops.eleResponse(2001 + 2 * i, "force")[1] for i in range(n_e)]
    out.update(edge_displacements(out, tags["positions"]))
    ops.wipe()
    return out


def edge_displacements(histories: dict[str, np.ndarray], positions: np.ndarray) -> dict[str, np.ndarray]:
    """v - x_i theta [m] at the outermost elements (the mat edges for two elements), as the exact
    engine's histories give the "edge" displacements."""
    return {"left_edge_displacement": histories["v"] - positions[0] * histories["theta"],
            "right_edge_displacement": histories["v"] - positions[-1] * histories["theta"]}


def peaks(histories: dict[str, np.ndarray]) -> dict[str, float]:
    """The peaks compared: |V_b|, |M_b|, |theta|, |u_N| and the largest rise of each edge above
    its rest position (uplift), in SI units."""
    out = {name: float(np.max(np.abs(histories[name]))) for name in ("base_shear", "base_moment", "theta", "roof")}
    for side in ("left", "right"):
        series = histories[f"{side}_edge_displacement"]
        out[f"{side}_rise"] = float(np.max(series - series[0]))
    return out


def relative_history_difference(time: np.ndarray, values: np.ndarray, reference_time: np.ndarray,
                                reference: np.ndarray) -> float:
    """max |values - reference| / max |reference| with the reference interpolated linearly to `time`."""
    interpolated = np.interp(time, reference_time, reference)
    return float(np.max(np.abs(values - interpolated)) / max(np.max(np.abs(reference)), 1e-300))


def push(system, thetas: np.ndarray, penalty: float = PENALTY) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A slow (static) push of the mat through the rotations `thetas` [rad] (a path from 0: a
    monotonic push or cycles, the project's sign: theta > 0 lifts the left edge), after gravity:
    the mat's rotation imposed (a penalty single-point constraint scaled by the load factor; the
    displacement-control integrator did not converge with the penalty ties), its vertical motion
    free, the floors following the mat (no horizontal load: the stories stay undeformed). Returns
    (theta [rad], M = sum x_i R_i [N m], the moment of the element reactions about the centre, and
    the reactions R_i [N] (n, n_e)) at every point of the path: the moment-rotation backbone of
    docs/theory.md 14.4 (model/rocking_capacity.py)."""
    import openseespy.opensees as ops

    ops.logFile("/dev/null", "-noEcho")
    tags = build(ops, system, "uplift", penalty)
    gravity(ops, system, tags)
    ops.timeSeries("Linear", 3)
    ops.pattern("Plain", 3, 3)
    ops.sp(tags["mat"], 3, -1.0)  # the mat's rotation = -load factor (OpenSees' sign)
    ops.wipeAnalysis()
    # a static step: the unbalanced force, as for gravity (the displacement increment of the stiff
    # penalty contacts stays at round-off)
    solver(ops, ("NormUnbalance", 1e-6 * system.weight))
    n_e = tags["positions"].size
    out_theta, out_moment, out_reaction = [], [], []
    factor = 0.0
    for target in np.asarray(thetas, dtype=float):
        ops.integrator("LoadControl", float(target) - factor)
        ops.analysis("Static")
        if ops.analyze(1) != 0:
            raise RuntimeError(f"OpenSees: the push did not converge at theta = {target:.6g} rad")
        factor = float(target)
        reaction = np.array([ops.eleResponse(2001 + 2 * i, "force")[1] for i in range(n_e)])
        out_theta.append(-ops.nodeDisp(tags["mat"], 3))
        out_moment.append(float(tags["positions"] @ reaction))
        out_reaction.append(reaction)
    ops.wipe()
    return np.array(out_theta), np.array(out_moment), np.array(out_reaction)
