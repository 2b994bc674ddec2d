"""The [design] table of a deck (ASCE 7-22's design values of the structure: model/design.py, where the
fields are declared): a Design, or None for a deck without the table (every result then unchanged).
Its fields combine here: risk_category is needed; R and C_d come together (the linear procedure needs
both; a chapter 16 deck, which uses neither, may give none); I_e, when given, is that of Table 1.5-2 for
the risk category (11.5.1); the first row of Table 12.12-1 holds four stories or less."""

from __future__ import annotations

from ..model.design import LOW_RISE_STORIES, Design, importance_factor

#: the fields a [design] table must give, and those that come together (the linear procedure's)
REQUIRED = ("risk_category",)
TOGETHER = ("R", "Cd")


def design_from_fields(fields: dict, stories: int | None, error) -> Design | None:
    """The Design of the [design] fields (checked one by one by the schema), None without them; stories:
    the building's (None: not built, the row of Table 12.12-1 unchecked). Every mistake one
    error(field, expected)."""
    if not fields:
        return None
    if "risk_category" not in fields:
        raise error("design.risk_category", "a value in a [design] table (it sets I_e and the allowable drift)")
    _check_together(fields, error)
    risk = fields["risk_category"]
    _check_importance(fields, risk, error)
    _check_structure(fields, stories, error)
    return Design(R=_optional(fields.get("R")), Cd=_optional(fields.get("Cd")), Ie=importance_factor(risk),
                  risk_category=risk, structure=fields.get("structure", "all-other"),
                  Omega0=_optional(fields.get("Omega0")))


def _optional(value) -> float | None:
    """A number as a float, None as it is."""
    return None if value is None else float(value)


def _check_together(fields: dict, error) -> None:
    """design.R and design.Cd both or neither (the linear procedure needs both: 12.9.1.2)."""
    given = [name for name in TOGETHER if name in fields]
    if len(given) == 1:
        other = TOGETHER[1 - TOGETHER.index(given[0])]
        raise error(f"design.{other}", f"a value with design.{given[0]} (the linear procedure of ASCE 7-22 12.9.1.2 "
                    "needs R and C_d; a chapter 16 deck may give neither)")


def _check_importance(fields: dict, risk: str, error) -> None:
    """design.Ie, when given, that of the risk category (ASCE 7-22 11.5.1: assigned by Table 1.5-2)."""
    if "Ie" in fields and fields["Ie"] != importance_factor(risk):
        raise error("design.Ie", f"{importance_factor(risk)!r}, the importance factor of risk category {risk} "
                    f"(ASCE 7-22 11.5.1, Table 1.5-2), got {fields['Ie']:g} (or leave it out)")


def _check_structure(fields: dict, stories: int | None, error) -> None:
    """The first row of Table 12.12-1 only for four stories or less above the base."""
    if fields.get("structure") == "low-rise-drift-tolerant" and (stories or 0) > LOW_RISE_STORIES:
        raise error("design.structure", f"a row of ASCE 7-22 Table 12.12-1 that fits the building: "
                    f"low-rise-drift-tolerant holds {LOW_RISE_STORIES} stories or less, the building has {stories}")
