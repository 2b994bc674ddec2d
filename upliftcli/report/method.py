"""The method summary of a report: the model and each engine run, with the paper's equation
numbers (Yim & Chopra; docs/theory.md gives them with the corrections of the OCR text)."""

from __future__ import annotations

from collections.abc import Sequence

from .document import Section, Text

MODEL = (
    "Model (docs/theory.md sections 1-5): an N-story shear building (lumped floor masses, story "
    "stiffnesses, classical modal damping) on a rigid mat of half-width b resting on a flexible foundation "
    "(two spring-dampers at the mat edges, a Winkler bed or a half-space). The mat may lift off: an element "
    "leaves contact when its reaction would turn tensile [4a] (or its edge rises above the unstressed "
    "position [4b]). In modal form the building, the mat rotation theta and its vertical displacement v obey "
    "the N + 2 equations [11a-11c]; floor displacements [12], lateral forces [13], base shear V_b [14a] and "
    "base moment M_b [14b] follow. The mat starts to lift at the critical base moment M_c = m_t g b [16b], "
    "i.e. the critical base shear V_c = m_t g b / h_1* [16a]. Three support conditions are compared: rigid, "
    "bonded (the mat may not lift) and uplift."
)
ENGINES = {
    "simplified": (
        "Simplified procedure (docs/theory.md section 7): the fundamental mode alone feels the foundation. "
        "Bonded effective period T1bar [21] with the rocking stiffness K_theta [22] and effective damping "
        "xi1bar [23] with the foundation damping xi_f [24] and the rocking damping C_theta [25]; mode-1 base "
        "shear without uplift V_1 = m_1* S_a(T1bar, xi1bar) [26]; if V_1 > V_c the mat lifts off: damping "
        "while uplifted [27] and the mode-1 base shear with uplift [28a, 28b] (or the slender-structure limit "
        "[29]). Higher modes fixed-base, V_n = m_n* S_a(T_n, xi_n) [31]; floor forces [32], displacements "
        "[33] and drifts [34] per mode, combined by SRSS [35] (or CQC)."),
    "approximate": (
        "Approximate response history (paper Figs. 6 and 8; docs/theory.md section 11.7): the fundamental mode "
        "coupled with the foundation through the one-mode equations [17a-17c] with I_b ~ m_1* h_1*^2 and "
        "L_0 ~ m_1* h_1* [20], uplift permitted; the higher modes fixed-base; modal responses combined "
        "instant by instant."),
    "exact": (
        "Exact response history (docs/theory.md section 11): the N + 2 nonlinear equations [11a-11c] integrated "
        "state by state with exact step operators; every lift-off and recontact located inside the step; peaks "
        "found between samples; the energy balance (input work = dissipated + stored energy) checked on every "
        "run (section 11.6)."),
}


IMPROVED = (
    "Uplift support, improved procedure (analysis.procedure = \"improved\", the default; docs/accuracy.md): "
    "the paper's procedure with the mass-consistent X in [28a] (V_1/V_c instead of (S_a/g)(h_1*/b)), mode 1 "
    "read from S_a averaged over the band of periods a lifting system sweeps, with a short-period gain for "
    "the impacts, the higher modes raised by the uplift severity through the h_n* theta'' term of [11a], a "
    "combination that correlates them with mode 1, no caps; the mat rotation and edge uplift from the "
    "rocking displacement of the equivalent system of Fig. 2, and the floor accelerations of the impacts at "
    "recontact; coefficients calibrated against the exact engine on the FEMA P695 far-field records and "
    "validated on the near-field ones. With analysis.procedure = \"paper\" the procedure is Yim and Chopra's "
    "[21-35] as above.")


def method_section(engines: Sequence[str], procedure: str = "paper") -> Section:
    """The model and the engines that were run, citing the paper's equations; procedure: the
    simplified engine's (analysis.procedure)."""
    paragraphs = [MODEL, *_engine_paragraphs(engines, procedure)]
    paragraphs.append("Reference: Yim and Chopra, \"Simplified earthquake analysis of multistory structures with "
                      "foundation uplift\", Journal of Structural Engineering (ASCE). Equation numbers in brackets are "
                      "the paper's.")
    return Section("method", "Method", [Text(paragraphs)])


def _engine_paragraphs(engines: Sequence[str], procedure: str) -> list[str]:
    """A paragraph per engine run (in the order run); the improved procedure after the simplified engine's."""
    paragraphs = [ENGINES[name] for name in dict.fromkeys(engines) if name in ENGINES]
    if "simplified" in engines and procedure == "improved":
        paragraphs.insert(paragraphs.index(ENGINES["simplified"]) + 1, IMPROVED)
    return paragraphs
