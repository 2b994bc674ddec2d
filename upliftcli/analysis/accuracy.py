"""The simplified engine checked against the exact engine on the same deck.

When the deck has a record, every simplified result is compared with the exact engine's result
of the same support, run with all the building's modes (a truncation of the deck, `analysis.modes`
or `analysis.exact.n_modes`, is not inherited: the check says which modes it used), for every
value of engines/quantities.COMPARED (V_b, M_b, the largest drift ratio, the roof displacement,
the largest floor acceleration and, with uplift, the edge uplift and the mat rotation). A value
whose exact counterpart is another quantity is left out with the reason (Check.left_out,
engines/quantities.Compared.left_out): the edge uplift when the soil yielded, where the exact
engine's gap is measured from the settled level.

    checks = check_accuracy(deck, results)          # one Check per simplified result, beside them
    check = compare(simplified, exact, band=(0.8, 1.25), reference="exact engine, all 10 modes")
    check.ratios                                    # {name: simplified / exact}
    check.warnings()                                # a line per ratio outside the band, and the
                                                    # exact run's own warnings (flight ...)
    check.largest_error()                           # (error, Comparison) for [criteria] simplified_error
    check.to_dict()                                 # the JSON `accuracy` object

A ratio outside the band (default DEFAULT_BAND, the deck's `analysis.check_band`; for the edge
uplift and the mat rotation, whose estimate scatters more, DEFAULT_MOTION_BAND,
`analysis.check_band_motion`) is a warning naming the value, the ratio and the exact value;
`[criteria] simplified_error = e` fails a run (exit code 3) when a ratio leaves [1/(1 + e), 1 + e]
(deck/criteria.py). Results are not changed: a Check is a separate object carried beside the results
(output.py, cli/render.py, report/). A suite deck has its own comparison (the simplified engine
on the target spectrum beside the suite statistic, engines/suite_result.py); compare() serves
any pair of results of one support (a suite's statistic among them): a deck with a design
spectrum is checked on a spectrum-compatible suite (analysis/suite_check.py), a Check with the suite and
the ratio's two factors.
docs/accuracy.md gives the measured spread of every ratio.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from ..deck.load import Deck
from ..engines.result import AnalysisResult
from ..errors import AnalysisError, InputError
from ..motion.records import Record
from .comparison import (  # noqa: F401  (the accuracy check's names, re-exported)
    DEFAULT_BAND,
    DEFAULT_MOTION_BAND,
    MOTION,
    Check,
    Comparison,
    compare,
    deck_bands,
)


def all_modes(deck: Deck) -> Deck:
    """The deck with the exact engine keeping every mode (the check does not inherit a truncation)
    and no histories."""
    exact = replace(deck.analysis.exact, n_modes=None, histories=False)
    return replace(deck, analysis=replace(deck.analysis, exact=exact))


def check_accuracy(deck: Deck, results: Sequence[AnalysisResult]) -> list[Check]:
    """One Check per simplified result of a deck with a record (none otherwise): the exact engine
    of the same support with all modes, reused from `results` when it ran with all of them, else run
    here (about 10-100 ms each). The results are not changed."""
    if not isinstance(deck.ground_motion, Record):
        return []
    n_total = deck.system.building.n_stories
    label = f"exact engine, all {n_total} modes"
    band, motion_band = deck_bands(deck)
    exact: dict[str, AnalysisResult | Exception] = {
        r.support: r for r in results if r.engine == "exact" and r.periods.size == n_total}
    return [_check_one(deck, result, exact, label, band, motion_band) for result in results
            if result.engine == "simplified"]


def _check_one(deck: Deck, result: AnalysisResult, exact: dict[str, AnalysisResult | Exception], label: str,
               band: tuple[float, float], motion_band: tuple[float, float]) -> Check:
    """The Check of one simplified result against the exact result of its support (exact: by
    support, run here and kept when missing), or a Check with the error that stopped it."""
    if result.support not in exact:
        exact[result.support] = _run_exact(deck, result.support)
    reference = exact[result.support]
    if isinstance(reference, Exception):
        return Check(result.support, label, band, error=str(reference), motion_band=motion_band)
    return compare(result, reference, band, label, motion_band)


def _run_exact(deck: Deck, support: str) -> AnalysisResult | Exception:
    """The exact engine's result on the deck with all modes (all_modes), or the error that stopped it."""
    from .run import run_one  # analysis imports nothing of this module

    try:
        return run_one(all_modes(deck), "exact", support, single=False)  # a reference: no residual check
    except (AnalysisError, InputError) as error:
        return error
