"""Options of the engines: the one declaration of each option (deck field, unit, check,
default, choices) and the frozen dataclasses the engines take.

The deck's `[analysis]` and `[analysis.exact]` tables are built from these declarations
(deck/schema.py), and the dataclasses check themselves against the same fields, so an
option is validated by one rule whether it comes from a deck, `--set` or Python code.
Nothing here imports scipy.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from ..deck.fields import Field, check_value
from ..errors import InputError


def option(deck_field: Field) -> Any:
    """A dataclass field whose default and check come from its deck declaration."""
    return dataclasses.field(default=deck_field.default, metadata={"deck": deck_field})


def deck_fields(options_class: type) -> dict[str, Field]:
    """The deck fields declared by an options class, in declaration order."""
    return {f.name: f.metadata["deck"] for f in dataclasses.fields(options_class) if "deck" in f.metadata}


def _validate(options: Any, table: str) -> None:
    for name, declared in deck_fields(type(options)).items():
        value = getattr(options, name)
        if value is None and declared.default is None:
            continue

        def error(expected: str, name: str = name) -> None:
            raise InputError(type(options).__name__, f"{table}.{name}", expected)

        check_value(declared, value, error)


@dataclass(frozen=True)
class SimplifiedOptions:
    """Options of the simplified engine (the open choices of docs/theory.md, simplified procedure).

    procedure: "improved" (default: engines/improved.py, calibrated against the exact engine,
        docs/accuracy.md) or "paper" (Yim & Chopra [21-35] with the corrections of docs/theory.md,
        and the five options below). The two differ only for the uplift support.
    n_modes: modes combined (None = all N).
    combination: "srss" [35] or "cqc" (mode 1 correlated with T1bar, xi1bar when flexible).
    effective_properties: "formula" [21-25] or "eigenvalue" (complex eigenvalue of the bonded
        one-mode system of paper Fig. 2, massless mat).
    uplift_damping: zeta = xi1bar r/b [27] ("xi1bar") or xi_1 r/b ("xi1").
    uplift_x: X0 = (m_t S_a1bar / V_c)^2 = (S_a/g)^2 (h_1*/b)^2 ("spectral") or (V_1/V_c)^2
        ("mass-consistent").
    uplift_x_factor: X = X0 e^(xi1bar pi) ("exponential"), X0 ("none"), or
        X0 e^(2 xi1bar (pi/2 - asin(X0^-1/2))) ("phase": decay over the phase actually
        travelled from the crossing V = V_c to the peak; continuous at V_1 = V_c).
    uplift_formula: "full" [28a] or "slender" [29].
    """

    procedure: str = option(Field(
        "string", "-", "simplified procedure: improved (calibrated against the exact engine, docs/accuracy.md) "
        "or paper (Yim & Chopra Eqs. 21-35 as corrected in docs/theory.md)", "", "improved", ("improved", "paper")))
    n_modes: int | None = None
    combination: str = option(Field("string", "-", "modal combination rule (simplified engine)", "", "srss",
                                    ("srss", "cqc")))
    effective_properties: str = option(Field(
        "string", "-", "T1bar and xi1bar from Eqs. 21-25 (formula) or from the complex eigenvalue of the "
        "bonded one-mode system (eigenvalue)", "", "formula", ("formula", "eigenvalue")))
    uplift_damping: str = option(Field(
        "string", "-", "damping while uplifted: zeta = xi1bar r/b [27] (xi1bar) or xi_1 r/b (xi1, rigid-pivot "
        "derivation)", "", "xi1bar", ("xi1bar", "xi1")))
    uplift_x: str = option(Field(
        "string", "-", "amplitude ratio in X: (S_a/g)^2 (h_1*/b)^2 = (m_t S_a/V_c)^2 (spectral) or "
        "(V_1/V_c)^2 = (m_1* S_a/V_c)^2 (mass-consistent)", "", "spectral", ("spectral", "mass-consistent")))
    uplift_x_factor: str = option(Field(
        "string", "-", "factor on X for the decay from the uplift crossing to the bonded peak: e^(xi1bar pi) "
        "(exponential), 1 (none), or e^(2 xi1bar (pi/2 - asin(1/sqrt(X0)))) (phase)", "", "exponential",
        ("exponential", "none", "phase")))
    uplift_formula: str = option(Field(
        "string", "-", "uplift base shear: full Eq. 28a or slender-structure Eq. 29", "", "full",
        ("full", "slender")))

    def __post_init__(self) -> None:
        _validate(self, "analysis")


@dataclass(frozen=True)
class ExactOptions:
    """Options of the exact (and approximate) engine.

    n_modes: fixed-base modes kept (None = all N).
    criterion: uplift criterion, "reaction" (tensile reaction, default) or "displacement"
        (edge above the unstressed position) [4a, 4b].
    steps_per_period: internal steps per shortest governing period (T_1, the bonded
        vertical period and every mode with at least 1 % effective mass) [-].
    time_step: internal step [s]; None = record dt / ceil(dt steps_per_period / period).
    free_vibration: duration of free vibration appended after the record [s].
    flight: "allow" (free flight under gravity when both edges lift) or "error".
    residual_inertia: with n_modes < N, "neglect" (default: the limit the paper's
        numerically damped integration tends to) or "include" the rotary inertia
        I_b - sum m_n* h_n*^2 of the truncated modes and their share of the excitation.
    residual_check: the perturbed twin of a run that leaves residuals (analysis/residuals.py):
        "auto" (default: in a single analysis and each record of a suite, not in sweeps), "on"
        (sweeps too) or "off".
    histories: keep the time histories in the result (result.histories).
    """

    n_modes: int | None = option(Field(
        "integer", "-", "fixed-base modes kept by the exact/approximate engines (default: analysis.modes, "
        "else all)", "count"))
    criterion: str = option(Field("string", "-", "uplift criterion [4a, 4b]", "", "reaction",
                                  ("reaction", "displacement")))
    steps_per_period: int = option(Field(
        "integer", "-", "internal steps per shortest governing period (T_1, the bonded vertical period, modes "
        "with >= 1 % mass)", "two-or-more", 6))
    time_step: float | None = option(Field(
        "number", "s", "internal time step (default: from steps_per_period and the record step)", "positive"))
    free_vibration: float = option(Field("number", "s", "free vibration appended after the record",
                                         "nonnegative", 0.0))
    flight: str = option(Field("string", "-", "both edges lifted: free flight (allow) or an error", "", "allow",
                               ("allow", "error")))
    residual_inertia: str = option(Field(
        "string", "-", "with fewer modes than stories: neglect (default) or include the rotary inertia of the "
        "truncated modes", "", "neglect", ("neglect", "include")))
    residual_check: str = option(Field(
        "string", "-", "where stories or soil yield, rerun with the record scaled by 1 + 1e-6 and warn where a "
        "residual changes by more than 20 %: auto (single analyses and suites, not sweeps), on, off", "", "auto",
        ("auto", "on", "off")))
    histories: bool = False

    def __post_init__(self) -> None:
        _validate(self, "analysis.exact")
