"""OpenSeesPy against the exact engine on stories that yield (issue 35, docs/theory.md section 15): a
shear building of zeroLength Steel01 story springs (Fy = the story strength V_yj, E0 = the story
stiffness k_j, b = the hardening ratio alpha: bilinear kinematic hardening, as the exact engine's
story) on a fixed base and on the uplifting foundation of benchmarks/opensees_model.py (Kelvin units
under compression-only ENT penalty contacts), at a halving sequence of fixed steps (Newmark, average
acceleration) under El Centro 1940 N-S.

The model (opensees_model.mat_and_floors and .foundation, with these stories):

- story j: a node rigidly linked to floor j - 1 (rigidLink beam: it moves with that floor and turns
  with the mat) at the height of floor j, and between it and floor j a zeroLength Steel01 spring in
  the horizontal direction: its deformation is x_j - x_(j-1) - h_j theta, the drift d_j relative to
  the rotated mat of docs/theory.md 15.1 (x: floor displacements relative to the ground, h_j the
  story's height); the story shear is its force;
- structural damping: a zeroLength dashpot (Viscous, c_j = beta k_j) beside each spring, so that
  C = beta K on the elastic stiffness: the exact engine's modal damping xi_n = beta w_n / 2
  (opensees_yielding.example_system: xi_n = 0.05 w_n / w_1), which does not change as stories
  yield (the exact engine damps the elastic modes).

Compared, each over the exact engine's value (the exact engine: peaks between samples, events
located inside the step; OpenSees: values at its steps): the peak drift, story shear and ductility
of each story (the largest difference over the stories), the residual drift at the end of the record
and a free vibration (over the peak drift: a residual is small and fragile), the hysteretic energy
int V dp (OpenSees: trapezoids over its steps, p = d - V/k), the base shear, the roof displacement,
and on the uplifting foundation the peak and residual mat rotation. The change from one step to the
next is the fixed step's own convergence.

    python benchmarks/opensees_stories.py                  # 10 stories, 0.15 W, El Centro x 2, rigid and uplift
    python benchmarks/opensees_stories.py --stories 2 --steps 0.002,0.001
    python benchmarks/opensees_stories.py --supports uplift --coefficient 0.1 --hardening 0

Needs openseespy (benchmarks/opensees_model.py). Nothing is cached.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import opensees_model as om
from opensees_yielding import example_system

from upliftcli.deck.strengths import coefficient_strengths
from upliftcli.engines.exact import engine as exact
from upliftcli.engines.options import ExactOptions
from upliftcli.model.building import modal_analysis, shear_building
from upliftcli.model.foundations import two_element_from_ratios
from upliftcli.model.system import System
from upliftcli.motion.records import read_record

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
#: the compared quantities, each a relative difference (see the module's docstring)
COMPARED = ("drift", "shear", "ductility", "residual_drift", "hysteretic_energy", "base_shear", "roof",
            "rotation", "residual_rotation")
#: tags of the story springs, their dashpots and the nodes below them
SPRING, DASHPOT, BELOW = 3000, 3100, 50


def yielding_system(period: float, coefficient: float, hardening: float) -> System:
    """The paper's ten-story example (opensees_yielding.example_system: two elements, stiffness-
    proportional damping) with the story strengths of the base-shear coefficient `coefficient` x W
    distributed over the height as ASCE 7-22 12.8.3 (the deck's strength_coefficient) and the
    hardening ratio alpha."""
    system = example_system(period)
    building = system.building
    strength = coefficient_strengths(building, coefficient, system.gravity)
    return replace(system, building=replace(building, story_strength=strength, hardening_ratio=hardening))


def two_story_system(coefficient: float, hardening: float) -> System:
    """Two stories (m 3.5e5 and 2.5e5 kg, k 1.4e8 and 0.9e8 N/m) on two elements (w_v/w_1 = 8,
    xi_v = 0.4, h_1*/b = 6: the mat lifts under El Centro) with xi_n = 0.05 w_n/w_1 and the strengths of
    `coefficient` x W distributed as ASCE 7-22 12.8.3."""
    masses, heights, stiffness = [3.5e5, 2.5e5], [3.5, 3.5], [1.4e8, 0.9e8]
    modes = modal_analysis(shear_building(masses, heights, stiffness, 0.05))
    building = shear_building(masses, heights, stiffness, om.stiffness_proportional_damping(modes.omega, 0.05))
    two = two_element_from_ratios(building.masses.sum(), modes.omega[0], 8.0, 0.4)
    system = System(building, two, modes.effective_height[0] / 6.0)
    strength = coefficient_strengths(building, coefficient, system.gravity)
    return replace(system, building=replace(building, story_strength=strength, hardening_ratio=hardening))


def build(ops, system: System, support: str, penalty: float = om.PENALTY) -> dict:
    """The model in the (wiped) OpenSees domain: mat, floors, the Steel01 stories and their dashpots,
    and the foundation (none on "rigid"); returns the tags (opensees_model.mat_and_floors)."""
    tags = om.mat_and_floors(ops, system, support)
    building = system.building
    beta = om.damping_beta(system)
    below = tags["mat"]
    for j, (floor, height) in enumerate(zip(tags["floors"], building.heights, strict=True)):
        ops.node(BELOW + j, 0.0, float(height))
        ops.rigidLink("beam", below, BELOW + j)
        k_j, strength = float(building.story_stiffness[j]), float(building.story_strength[j])
        if np.isfinite(strength):
            ops.uniaxialMaterial("Steel01", SPRING + j, strength, k_j, float(building.hardening_ratio))
        else:
            ops.uniaxialMaterial("Elastic", SPRING + j, k_j)
        ops.uniaxialMaterial("Viscous", DASHPOT + j, beta * k_j, 1.0)
        ops.element("zeroLength", SPRING + j, BELOW + j, floor, "-mat", SPRING + j, "-dir", 1)
        ops.element("zeroLength", DASHPOT + j, BELOW + j, floor, "-mat", DASHPOT + j, "-dir", 1)
        below = floor
    om.foundation(ops, system, support, penalty, tags)
    return tags


def _sample(ops, tags: dict, heights: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """theta (the project's sign), the drifts relative to the rotated mat and the story shears now."""
    theta = -ops.nodeDisp(tags["mat"], 3)
    x = np.array([ops.nodeDisp(tag, 1) for tag in tags["floors"]])
    u = x - heights * theta
    shear = [ops.eleResponse(SPRING + j, "force")[3] for j in range(heights.size)]
    return theta, np.diff(u, prepend=0.0), np.array(shear)


def run(system: System, acceleration: np.ndarray, record_dt: float, dt: float, support: str,
        penalty: float = om.PENALTY) -> dict[str, np.ndarray]:
    """Histories at every step dt [s]: time, theta [rad], the drifts d_j [m] and the story shears V_j [N]
    (n, N); acceleration [m/s^2] at record_dt [s] (append zeros for a free vibration)."""
    import openseespy.opensees as ops

    ops.logFile("/dev/null", "-noEcho")
    tags = build(ops, system, support, penalty)
    om.start_transient(ops, system, tags, acceleration, record_dt, ("Newmark", 0.5, 0.25))
    heights = system.building.heights
    count = round((acceleration.size - 1) * record_dt / dt)
    out = {"time": np.empty(count + 1), "theta": np.empty(count + 1), "drift": np.empty((count + 1, heights.size)),
           "shear": np.empty((count + 1, heights.size))}
    for step in range(count + 1):
        if step:
            om.advance(ops, dt)
        out["time"][step] = ops.getTime()
        out["theta"][step], out["drift"][step], out["shear"][step] = _sample(ops, tags, heights)
    ops.wipe()
    return out


def hysteretic_energy(drift: np.ndarray, shear: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
    """int V dp of each story [J] by trapezoids over the samples, p = d - V/k the plastic drift."""
    plastic = drift - shear / stiffness
    return np.sum(0.5 * (shear[1:] + shear[:-1]) * np.diff(plastic, axis=0), axis=0)


def opensees_peaks(histories: dict[str, np.ndarray], system: System) -> dict[str, np.ndarray | float]:
    """The compared quantities of the OpenSees histories (SI; per story: arrays)."""
    building = system.building
    drift, shear = histories["drift"], histories["shear"]
    peak_drift = np.max(np.abs(drift), axis=0)
    return {"drift": peak_drift, "shear": np.max(np.abs(shear), axis=0),
            "ductility": peak_drift / building.yield_drift, "residual_drift": np.abs(drift[-1]),
            "hysteretic_energy": hysteretic_energy(drift, shear, building.story_stiffness),
            "base_shear": float(np.max(np.abs(shear[:, 0]))),
            "roof": float(np.max(np.abs(np.cumsum(drift, axis=1)[:, -1]))),
            "rotation": float(np.max(np.abs(histories["theta"]))), "residual_rotation": abs(histories["theta"][-1])}


def exact_peaks(system: System, record, support: str, free_vibration: float,
                steps_per_period: int = 24) -> dict[str, np.ndarray | float]:
    """The same quantities from the exact engine (engines/exact), its peaks between samples, and whether
    the mat lifted and how many stories yielded."""
    result = exact.analyze(system, record, support, ExactOptions(free_vibration=free_vibration,
                                                                  steps_per_period=steps_per_period))
    peaks, building = result.peaks, system.building
    rocking = support != "rigid"
    return {"drift": peaks["drift"], "shear": peaks["shear"], "ductility": peaks["ductility"],
            "residual_drift": peaks["residual_drift_ratio"] * building.story_heights,
            "hysteretic_energy": peaks["hysteretic_energy"], "base_shear": float(result.base_shear),
            "roof": float(peaks["displacement"][-1]),
            "rotation": float(peaks["rotation"][0]) if rocking else 0.0,
            "residual_rotation": float(peaks["residual_rotation"][0]) if rocking else 0.0,
            "uplift": bool(result.uplift), "yielded_stories": int(peaks["yielded_stories"][0])}


def differences(opensees: dict, reference: dict) -> dict[str, float]:
    """The largest relative difference of each compared quantity: per story over the story's own
    value (the residual drift over the peak drift, the hysteretic energy over the largest story's;
    the residual rotation over the peak rotation; 0 where the reference is 0: the fixed base)."""
    scale = {"residual_drift": reference["drift"], "hysteretic_energy": np.max(reference["hysteretic_energy"]),
             "residual_rotation": reference["rotation"]}
    out = {}
    for name in COMPARED:
        ref = np.asarray(reference[name], dtype=float)
        denominator = np.asarray(scale.get(name, ref), dtype=float)
        gap = np.abs(np.asarray(opensees[name], dtype=float) - ref)
        out[name] = float(np.max(np.divide(gap, denominator, out=np.zeros_like(gap), where=denominator > 0)))
    return out


def compare(system: System, record, support: str, steps: list[float], free_vibration: float,
            penalty: float = om.PENALTY) -> list[dict]:
    """One row per step dt: the differences from the exact engine, the step's change from the previous
    step (the largest over the compared quantities) and OpenSees' seconds."""
    reference = exact_peaks(system, record, support, free_vibration)
    acceleration = np.concatenate((record.acceleration, np.zeros(round(free_vibration / record.dt))))
    rows, previous = [], None
    for dt in steps:
        start = time.perf_counter()
        peaks = opensees_peaks(run(system, acceleration, record.dt, dt, support, penalty), system)
        row = {"support": support, "dt": dt, "seconds": round(time.perf_counter() - start, 2),
               "uplift": reference["uplift"], "yielded_stories": reference["yielded_stories"],
               "max_ductility": float(np.max(reference["ductility"])), **differences(peaks, reference)}
        if previous is not None:
            row["step_change"] = max(differences(peaks, previous).values())
        rows.append(row)
        previous = peaks
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--stories", type=int, default=10, choices=(2, 10), help="the ten-story example or two")
    parser.add_argument("--period", type=float, default=1.0, help="T_1 of the ten-story example [s]")
    parser.add_argument("--coefficient", type=float, default=0.15, help="base-shear strength over the weight")
    parser.add_argument("--hardening", type=float, default=0.05, help="alpha = Steel01's b")
    parser.add_argument("--supports", default="rigid,uplift", help="rigid, bonded, uplift (comma-separated)")
    parser.add_argument("--steps", default="0.002,0.001,0.0005,0.00025", help="fixed steps dt [s]")
    parser.add_argument("--scale", type=float, default=2.0, help="factor on the record")
    parser.add_argument("--duration", type=float, default=None, help="first seconds of the record [s]")
    parser.add_argument("--penalty", type=float, default=om.PENALTY, help="contact stiffness / element stiffness")
    parser.add_argument("--free-vibration", type=float, default=5.0, help="after the record [s]")
    args = parser.parse_args()
    record = read_record(RECORD, units="g")
    length = round(args.duration / record.dt) + 1 if args.duration else None
    record = replace(record, acceleration=args.scale * record.acceleration[:length])
    if args.stories == 10:
        system = yielding_system(args.period, args.coefficient, args.hardening)
    else:
        system = two_story_system(args.coefficient, args.hardening)
    steps = [float(s) for s in args.steps.split(",")]
    for support in args.supports.split(","):
        for row in compare(system, record, support, steps, args.free_vibration, args.penalty):
            print(json.dumps({k: (float(f"{v:.3g}") if isinstance(v, float) else v) for k, v in row.items()}),
                  flush=True)


if __name__ == "__main__":
    main()
