"""The one table of response quantities: name, where it lives, SI unit, meaning, how it is
shown, which engines give it and its column in sweep rows.

Everything that reports a result reads this table: the JSON, CSV and history writers
(output.py), the terminal tables (cli/render.py), sweep rows and figures (sweep/), and the
deck's `[criteria]` (deck/schema.py, deck/criteria.py). An engine produces a
quantity by putting its peaks under the quantity's name in AnalysisResult.peaks (and, for
the history engines, the instants under AnalysisResult.times).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..display import file_unit, unit_suffix
from ..display import heading as display_heading

#: where a quantity's values live: one per floor (1..N), per story (story j joins floor j-1
#: and floor j) or per foundation contact element (left to right)
FLOOR, STORY, ELEMENT = "floor", "story", "element"
ALL_ENGINES = ("simplified", "approximate", "exact")
HISTORY_ENGINES = ("approximate", "exact")


@dataclass(frozen=True)
class Quantity:
    """A response quantity.

    name: key in results, files and [criteria]; where: FLOOR, STORY or ELEMENT; unit: SI unit;
    meaning: what it is, in words (its peak is reported); display: its display kind ("mm", "%",
    "N", "N m", "g": display.py), which sets its unit in every human output; engines: the
    engines that give it; column: sweep-row column of its largest value (with its unit), or ""
    if the sweep rows do not carry it; criterion: whether [criteria] may limit its largest value;
    count: its values are counts, written as integers (typed).
    """

    name: str
    where: str
    unit: str
    meaning: str
    display: str
    engines: tuple[str, ...] = ALL_ENGINES
    column: str = ""
    criterion: bool = True
    count: bool = False

    def typed(self, value: float) -> float | int:
        """A value as the files write it: a count's whole value as an int (20, not 20.0); any
        other value, and a count's fractional statistic (a suite's mean), as it is."""
        return int(value) if self.count and float(value).is_integer() else value

    def heading(self, system: str = "si") -> str:
        """Column heading with the display unit ('shear [kN]'; display.py)."""
        return display_heading(self.name.replace("_", " "), self.display, system)


QUANTITIES: dict[str, Quantity] = {q.name: q for q in (
    Quantity("displacement", FLOOR, "m", "floor displacement relative to the mat", "mm",
             column="max_displacement_m"),
    Quantity("drift", STORY, "m", "story drift u_j - u_(j-1)", "mm"),
    Quantity("drift_ratio", STORY, "-", "story drift ratio (drift / story height)", "%",
             column="max_drift_ratio"),
    Quantity("shear", STORY, "N", "story shear (story 1: the base shear V_b [14a])", "N",
             criterion=False),
    Quantity("moment", STORY, "N m", "overturning moment at the bottom of the story (story 1: M_b [14b])",
             "N m", criterion=False),
    Quantity("floor_acceleration", FLOOR, "m/s^2", "absolute floor acceleration (relative acceleration plus "
             "ground acceleration)", "g", column="max_floor_acceleration_m_s2"),
    Quantity("reaction", ELEMENT, "N", "largest compression of the foundation element (upward reaction on the "
             "mat)", "N", column="max_reaction_N"),
    Quantity("impact", ELEMENT, "N", "largest element compression at a recontact (the impact of the mat)",
             "N", engines=HISTORY_ENGINES, column="max_impact_N", criterion=False),
)}


#: where a rocking quantity lives: one value for the mat, or three: the left edge (x = -b),
#: the centre and the right edge (x = +b)
MAT, MAT_POINTS = "mat", "mat-points"

#: The response of a rocking foundation with a bearing capacity (docs/theory.md section 14.7),
#: declared for the exact engine (engines = ("exact",)), which fills them in by name in
#: AnalysisResult.peaks when it models yielding (issue 28). Kept out of QUANTITIES so that the
#: outputs of an elastic foundation stay what they are: the outputs add them where a result
#: carries them. Settlements are positive downwards, from the mat's rest position under gravity.
#: criterion: [criteria] may limit them (deck_schema; values from ASCE 41-17 section 8.4, given
#: by the user: docs/deck.md).
ROCKING: dict[str, Quantity] = {q.name: q for q in (
    Quantity("rotation", MAT, "rad", "mat rotation |theta| (ASCE 41-17 section 8.4: the rotation of a rocking "
             "shallow foundation)", "mrad", engines=("exact",), column="rotation_rad"),
    Quantity("residual_rotation", MAT, "rad", "mat rotation |theta| at the end of the analysis (the record and "
             "analysis.exact.free_vibration)", "mrad", engines=("exact",), column="residual_rotation_rad"),
    Quantity("settlement", MAT_POINTS, "m", "settlement (downward displacement from the rest position under "
             "gravity) of the left edge, the centre and the right edge of the mat", "mm",
             engines=("exact",), column="max_settlement_m"),
    Quantity("residual_settlement", MAT_POINTS, "m", "settlement of the left edge, the centre and the right edge "
             "at the end of the analysis", "mm", engines=("exact",), column="max_residual_settlement_m"),
    Quantity("plastic_settlement", ELEMENT, "m", "plastic settlement -s_i of the contact element at the end "
             "(> 0: the element yielded)", "mm", engines=("exact",), column="max_plastic_settlement_m",
             criterion=False),
    Quantity("yielded_elements", MAT, "-", "number of contact elements that yielded", "-",
             engines=("exact",), column="yielded_elements", criterion=False, count=True),
    Quantity("plastic_work", MAT, "J", "energy dissipated by the yielding soil, sum Q_y,i |s_i| (docs/theory.md "
             "14.5)", "J", engines=("exact",), column="plastic_work_J", criterion=False),
)}


#: where a yielding-building quantity of the whole result lives: one value for the building
BUILDING = "building"

#: The response of stories that yield (docs/theory.md section 15.5), given by the exact engine when the
#: building has story strengths ([building] story_strengths or strength_coefficient), by name in
#: AnalysisResult.peaks. Kept out of QUANTITIES so that the outputs of an elastic building stay what they
#: are: the outputs add them where a result carries them (as ROCKING). The peak drift ratio is
#: QUANTITIES' drift_ratio.
YIELDING: dict[str, Quantity] = {q.name: q for q in (
    Quantity("ductility", STORY, "-", "story ductility: peak |drift| over the yield drift V_y/k (0 for a story "
             "without a strength)", "-", engines=("exact",), column="max_ductility"),
    Quantity("residual_drift_ratio", STORY, "-", "story drift ratio |drift| / story height at the end of the "
             "analysis (the record and analysis.exact.free_vibration)", "%", engines=("exact",),
             column="max_residual_drift_ratio"),
    Quantity("hysteretic_energy", STORY, "J", "energy the story dissipates by yielding, int V dp (docs/theory.md "
             "15.3)", "J", engines=("exact",), column="hysteretic_energy_J", criterion=False),
    Quantity("story_yielded", STORY, "-", "whether the story yielded (1) or not (0)", "-", engines=("exact",),
             criterion=False, count=True),
    Quantity("yielded_stories", BUILDING, "-", "number of stories that yielded (0: the building stayed elastic)",
             "-", engines=("exact",), column="yielded_stories", criterion=False, count=True),
    Quantity("base_shear_strength", BUILDING, "N", "base-shear strength: the strength V_y1 of the first story",
             "N", engines=("exact",), column="base_shear_strength_N", criterion=False),
)}


#: ASCE 7-22's linear procedures (docs/theory.md 16, engines/design.py): the simplified engine's on a deck with
#: [design], in AnalysisResult.peaks; kept out of QUANTITIES (as YIELDING): a deck without it is unchanged.
DESIGN: dict[str, Quantity] = {q.name: q for q in (
    Quantity("design_shear", STORY, "N", "design story shear: elastic x Ie/R (12.9.1.2)", "N", ("simplified",),
             criterion=False),
    Quantity("design_drift_ratio", STORY, "-", "design story drift ratio Delta/h_sx = C_d/R x the elastic one (ASCE "
             "7-22 12.8.6, 12.9.1.2)", "%", ("simplified",), "max_design_drift_ratio", False),
    Quantity("design_base_shear", BUILDING, "N", "design base shear: elastic x Ie/R (ASCE 7-22 12.9.1.2)", "N",
             ("simplified",), "design_base_shear_N", False),
    Quantity("allowable_drift_ratio", BUILDING, "-", "allowable story drift ratio Delta_a/h_sx (ASCE 7-22 Table "
             "12.12-1)", "%", ("simplified",), "allowable_drift_ratio", False),
)}

#: the places of a MAT_POINTS quantity, left to right: (key in files, label in human outputs)
MAT_PLACES = (("left_edge", "left edge (x = -b)"), ("centre", "centre"), ("right_edge", "right edge (x = +b)"))


def rocking_entries(result) -> list[tuple[Quantity, str, str, float, float | None]]:
    """The rocking quantities a result carries that live on the mat (quantities.ROCKING, MAT and
    MAT_POINTS), one entry per value: (quantity, place key, place label, value [SI; a count as
    Quantity.typed], instant [s] or None), in ROCKING's order; [] for a result without them (the
    elements' plastic settlement is in the foundation tables: element_quantities)."""
    entries = []
    for q in ROCKING.values():
        if q.where == ELEMENT or q.name not in result.peaks:
            continue
        places = MAT_PLACES if q.where == MAT_POINTS else (("mat", "mat"),)
        times = result.times.get(q.name)
        for k, (key, label) in enumerate(places):
            entries.append((q, key, label, q.typed(float(result.peaks[q.name][k])),
                            None if times is None else float(times[k])))
    return entries


def rocking_value(result, name: str) -> float:
    """The value of a rocking quantity that [criteria] limits and sweep rows carry: a settlement's
    largest downward value (>= 0: a mat that rose has not settled), else the largest |value| (a
    count as Quantity.typed)."""
    if ROCKING[name].unit == "m":
        return max(float(result.peaks[name].max()), 0.0)
    return ROCKING[name].typed(result.value(name))


def element_quantities() -> list[Quantity]:
    """The per-element quantities of the foundation tables: QUANTITIES', then ROCKING's (plastic settlement)."""
    return [*quantities(ELEMENT), *(q for q in ROCKING.values() if q.where == ELEMENT)]


@dataclass(frozen=True)
class Scalar:
    """A single-valued result: name, SI unit, meaning (the value is a property of AnalysisResult)."""

    name: str
    unit: str
    meaning: str
    column: str


SCALARS: dict[str, Scalar] = {s.name: s for s in (
    Scalar("base_shear", "N", "peak base shear V_b [14a]", "base_shear_N"),
    Scalar("base_shear_coefficient", "-", "base shear coefficient V_b/(m_t g)", "base_shear_coefficient"),
    Scalar("base_moment", "N m", "peak base overturning moment M_b [14b]", "base_moment_Nm"),
    Scalar("base_moment_coefficient", "-", "base moment coefficient M_b/(m_t g h_1*)",
           "base_moment_coefficient"),
)}


def _largest(result, *names: str) -> float | None:
    """The largest of the intermediates `names` a result has (None when it has none)."""
    values = [float(result.intermediates[n]) for n in names if isinstance(result.intermediates.get(n), (int, float))]
    return max(values) if values else None


@dataclass(frozen=True)
class Compared:
    """A value compared between two engines (the accuracy check of the simplified engine against
    the exact one, a suite's statistic against the simplified engine, sweep --check, the report,
    the accuracy study): name (one name everywhere: JSON keys, check_<name> sweep columns), SI
    unit, symbol (short label), meaning, value: the value of an AnalysisResult (None when the
    result does not give it: the uplift of a bonded result), the supports it applies to, its
    display kind (display.py), which sets its unit in every human output, and left_out: why a
    result's value is not the quantity the other engine gives (None when it is), which leaves the
    value out of every comparison (compared_values gives None, the accuracy check states the reason)."""

    name: str
    unit: str
    symbol: str
    meaning: str
    value: Callable[[Any], float | None]
    supports: tuple[str, ...] = ("rigid", "bonded", "uplift")
    display: str = "coefficient"
    left_out: Callable[[Any], str | None] = lambda result: None

    def heading(self, system: str = "si") -> str:
        """'V_b [kN]', 'largest drift ratio [%]', 'edge uplift [mm]': a table heading in the display units."""
        return display_heading(("largest " if self.name in QUANTITIES else "") + self.symbol, self.display, system)


def _settled_gap(result) -> str | None:
    """Why the edge uplift of a result on soil that yielded is not compared: the exact engine's
    max_uplift is then the gap above the settled level of the element (docs/theory.md 14.3), ratios
    2-68 to the simplified estimate of a gap above the rest level (docs/accuracy.md)."""
    if getattr(result, "yielded", None):
        return ("the soil yielded: the exact engine's edge uplift is then the gap above the settled level "
                "(docs/theory.md 14.3), not the lift above the rest position that the simplified procedure estimates")
    return None


#: the compared values, in the order of every table that shows them
COMPARED: dict[str, Compared] = {c.name: c for c in (
    Compared("base_shear", "N", "V_b", "base shear V_b", lambda r: r.base_shear, display="N"),
    Compared("base_moment", "N m", "M_b", "base overturning moment M_b", lambda r: r.base_moment, display="N m"),
    Compared("drift_ratio", "-", "drift ratio", "largest story drift ratio", lambda r: r.value("drift_ratio"),
             display="%"),
    Compared("roof_displacement", "m", "roof displacement", "roof displacement relative to the mat",
             lambda r: float(abs(r.peaks["displacement"][-1])), display="mm"),
    Compared("floor_acceleration", "m/s^2", "floor acceleration", "largest absolute floor acceleration",
             lambda r: r.value("floor_acceleration"), display="g"),
    Compared("max_uplift", "m", "edge uplift", "largest gap under an edge of the mat (uplift)",
             lambda r: _largest(r, "max_uplift", "max_uplift_left", "max_uplift_right"), ("uplift",), "mm",
             _settled_gap),
    Compared("max_rotation", "rad", "mat rotation", "largest mat rotation |theta| (uplift)",
             lambda r: _largest(r, "max_rotation"), ("uplift",), "mrad"),
)}


def compared_values(result) -> dict[str, float | None]:
    """Every COMPARED value of a result that applies to its support (None: not given, or left out:
    Compared.left_out)."""
    return {c.name: None if c.left_out(result) else c.value(result) for c in COMPARED.values()
            if result.support in c.supports}


def unit_of(name: str) -> str:
    """The SI unit of a response, rocking, yielding-story or design quantity or a scalar (KeyError: none)."""
    return (QUANTITIES.get(name) or ROCKING.get(name) or YIELDING.get(name) or DESIGN.get(name) or SCALARS[name]).unit


def display_kind(name: str) -> str:
    """The display kind (display.py) of a response quantity, a rocking quantity, a compared value
    (COMPARED) or a scalar: a quantity's or a compared value's own; 'max_drift_ratio': that of
    the quantity it takes; else by the SI unit (a ratio '-' as a coefficient)."""
    if name in COMPARED:
        return COMPARED[name].display
    for candidate in (name, name.removeprefix("max_"), name.rsplit("_", 1)[-1]):
        if found := QUANTITIES.get(candidate) or ROCKING.get(candidate) or DESIGN.get(candidate):
            return found.display
    unit = unit_of(name)
    return "coefficient" if unit == "-" else unit


def quantities(*where: str) -> list[Quantity]:
    return [q for q in QUANTITIES.values() if q.where in where]  # those per floor, story or element, in table order


#: intermediate values an engineer checks by hand, name -> (unit, meaning): those of the
#: simplified engine, then those of the response-history engines
INTERMEDIATES: dict[str, tuple[str, str]] = {
    "T_n": ("s", "fixed-base periods of the modes used"),
    "Sa_n": ("m/s^2", "S_a(T_n, xi_n) of each mode, fixed base"),
    "V_n": ("N", "modal base shear used in the combination [26, 28, 31]"),
    "V_1+2": ("N", "modes 1 and 2 combined by the combination rule [35]"),
    "m_n*/m_t": ("-", "effective modal mass ratios"),
    "h_n*": ("m", "effective modal heights"),
    "K_theta": ("N m/rad", "rocking stiffness of the foundation [22] at omega_impedance"),
    "C_theta": ("N m s/rad", "rocking damping of the foundation [25] at omega_impedance"),
    "omega_impedance": ("rad/s", "frequency at which K_theta, C_theta are evaluated (flexible-base w1bar)"),
    "k_element": ("N/m", "equivalent edge element k = K_theta / (2 b^2)"),
    "c_element": ("N s/m", "equivalent edge element c = C_theta / (2 b^2)"),
    "T1": ("s", "fixed-base fundamental period"),
    "T1bar": ("s", "effective period of the bonded system [21]"),
    "T1bar/T1": ("-", "period lengthening"),
    "xi1": ("-", "fixed-base damping of mode 1"),
    "xi_f": ("-", "foundation damping [24]"),
    "xi1bar": ("-", "effective damping of the bonded system [23]"),
    "xi1bar/xi1": ("-", "xi1bar / fixed-base xi_1; below 1 Eq. 23 lowers the damping (the foundation adds less "
                   "than the (T_1/T1bar)^3 discount takes), which design codes' SSI procedures do not (NIST GCR "
                   "12-917-21 4.1); the paper's value is used"),
    "Sa1bar": ("m/s^2", "S_a(T1bar, xi1bar)"),
    "V_c": ("N", "critical base shear m_t g b / h_1* [16a]"),
    "M_c": ("N m", "critical base moment m_t g b [16b]"),
    "M_tip": ("N m", "elastic tipping moment m_t g b [16b], given with a bearing capacity (M_c, V_c are then the "
              "capacity's: docs/theory.md 14.4)"),
    "Q_y": ("N", "bearing capacity of each contact element (docs/theory.md section 14)"),
    "FS_v": ("-", "factor of safety against vertical bearing failure q_c/q under the weight (ASCE 41-17 8.4)"),
    "V1_bonded": ("N", "mode-1 base shear without uplift m_1* S_a(T1bar, xi1bar) [26]"),
    "V1_bonded/V_c": ("-", "contact is lost at an edge of the mat (uplift; the bonded mat pulls) when this exceeds "
                      "the foundation's contact-loss ratio: 1 for two edge elements or a half-space (the mat tips), "
                      "1/3 for a Winkler mat (its kern: the improved procedure; the paper's procedure takes 1)"),
    "r": ("m", "sqrt(h_1*^2 + b^2)"),
    "zeta": ("-", "damping while uplifted [27]"),
    "X0": ("-", "X before the decay factor"),
    "X_factor": ("-", "decay factor on X"),
    "X": ("-", "X of Eq. 28"),
    "phi": ("rad", "phase angle [28b]"),
    "V1_uplift": ("N", "mode-1 base shear with uplift [28a] or [29]"),
    "capacity": ("-", "improved procedure: M_c,eff/M_c of a mat lifting progressively (Winkler: from the kern)"),
    "T_u": ("s", "improved procedure: upper end of the band [T1bar, T_u] over which S_a is averaged for X"),
    "x_u": ("-", "improved procedure: m_1* S_a / V_c, S_a the geometric mean over [T1bar, T_u] (the amplitude "
            "ratio in X)"),
    "modal_factors": ("-", "improved procedure: factors on the modal base shears raised by uplift (mode 1: 1)"),
    "rho_1n": ("-", "improved procedure: correlation of mode 1 with the higher modes in the combination"),
    "max_uplift": ("m", "improved procedure: largest gap under an edge of the mat (rocking displacement of the "
                   "equivalent system, docs/accuracy.md)"),
    "impact_acceleration": ("m/s^2", "improved procedure: largest floor acceleration of the impacts at recontact "
                            "(combined with the modal one by SRSS)"),
    "n_modes": ("-", "fixed-base modes in the model"),
    "time_step": ("s", "internal step h (exact step operator; crossings located inside it)"),
    "steps_per_period": ("-", "internal steps per governing period after the step was refined (energy balance)"),
    "criterion": ("-", "uplift criterion [4a] reaction or [4b] displacement"),
    "rotation_inertia": ("kg m^2", "inertia of the mat rotation (0: first-order rocking constraint)"),
    "samples": ("-", "history samples: every step plus every contact transition"),
    "transitions": ("-", "contact transitions (lift-off and recontact of elements; with a bearing "
                    "capacity also onset of yield and elastic unloading)"),
    "base_shear_time": ("s", "time of the peak base shear"),
    "base_moment_time": ("s", "time of the peak base moment"),
    "uplift_time": ("s", "total time with at least one element lifted"),
    "episodes": ("-", "uplift episodes (contact lost after full contact)"),
    "max_rotation": ("rad", "largest mat rotation |theta| (improved procedure: its estimate)"),
    "max_uplift_left": ("m", "largest gap under the left edge"),
    "max_uplift_right": ("m", "largest gap under the right edge"),
    "min_reaction": ("N", "smallest reaction of an element in contact (< 0: tension)"),
    "energy_residual": ("-", "energy balance residual / input energy"),
}

#: unit -> suffix of a column name ("max_drift_ratio", "shear_N", "floor_acceleration_m_s2"): the one
#: style of every CSV file's columns (results, sweeps, histories, record spectra), quantity_unit
_SUFFIXES = {"-": "", "m": "_m", "N": "_N", "N m": "_Nm", "m/s^2": "_m_s2", "m/s": "_m_s", "s": "_s", "rad": "_rad",
             "g": "_g", "J": "_J"}


def column_name(name: str, unit: str) -> str:
    """A file column name that carries its unit: ('shear', 'N') -> 'shear_N', ('drift_3', 'm') ->
    'drift_3_m'; a value without a physical unit (a ratio, a bitmask) keeps its name."""
    return name + _SUFFIXES.get(unit, "")


def file_column(name: str, unit: str, kind: str = "", system: str = "si") -> tuple[str, float]:
    """(column name, factor from SI) of a file's column in a unit system: SI as column_name; under
    --units us the unit of display.file_unit ('shear_kip', 'drift_3_in', 'elevation_ft')."""
    shown = file_unit(unit, kind, system)
    if shown.label == unit:
        return column_name(name, unit), 1.0
    return name + unit_suffix(shown.label), shown.factor


def file_kind(name: str) -> str:
    """The display kind of a result file's key (a quantity's or a compared value's own; '' for any
    other: its SI unit's)."""
    found = QUANTITIES.get(name) or ROCKING.get(name) or YIELDING.get(name) or DESIGN.get(name) or COMPARED.get(name)
    return found.display if found else ""


#: response histories written by --histories (besides one column per floor, story or element
#: of the quantities in HISTORY_QUANTITIES): name -> unit
HISTORY_SIGNALS: dict[str, str] = {
    "time": "s", "ground_acceleration": "m/s^2", "base_shear": "N", "base_moment": "N m",
    "roof_displacement": "m", "theta": "rad", "v": "m", "left_edge_displacement": "m",
    "right_edge_displacement": "m", "contact_state": "bitmask: bit i set = element i lifted",
    "left_edge_settlement": "m", "centre_settlement": "m", "right_edge_settlement": "m",
}
#: the meaning of the settlement histories (the flexible supports): down +, from the rest position
#: under gravity, as quantities.ROCKING's settlement; with a bearing capacity also one column
#: plastic_settlement_<element> per element, its -s_i >= 0 (ROCKING's plastic_settlement)
#: quantities written as histories, one column "<name>_<floor, story or element number>" (with yielding
#: stories also shear_<story>: the story shears of their hysteresis, docs/theory.md 15.5)
HISTORY_QUANTITIES = ("drift", "floor_acceleration", "reaction")
