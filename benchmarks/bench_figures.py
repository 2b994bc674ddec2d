"""Benchmark: drawing and writing the figures of a run, against an empty figure saved in the
same run (the baseline: what any figure costs, canvas and PNG encoding).

The run is the example deck (ten stories, El Centro 1940 N-S, 31 s) with the exact and
simplified engines and the three supports, histories kept: `uplift analyze --plot` draws
these figures (figures/sets.analysis_figures), plus the paper's spectra figures and a sweep
figure from synthetic rows. Prints, per figure and format, the best and median wall time
[ms] of drawing + writing and its ratio to the empty figure; the figure data alone (the
pure functions) separately. Target: every figure well under a second (here: below 0.5 s).

    python benchmarks/bench_figures.py [--repeats 5] [--formats png,svg]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from timing import timed

from upliftcli.analysis import run as analysis
from upliftcli.cli.plotting import keep_histories
from upliftcli.deck.load import load_deck
from upliftcli.figures import draw as plots
from upliftcli.figures.sets import analysis_figures
from upliftcli.sweep import figures as sweep_figures

DECK = Path(__file__).resolve().parent.parent / "inputs" / "ten_story_elcentro.toml"
TARGET_SECONDS = 0.5


def sweep_rows(engines=("exact", "simplified"), supports=("rigid", "bonded", "uplift"), count=60):
    """Synthetic sweep rows over T_1 (the figures only read them)."""
    rows = []
    for e, engine in enumerate(engines):
        for s, support in enumerate(supports):
            for k in range(count):
                period = 0.05 * 100 ** (k / (count - 1))
                value = 0.1 + 0.05 * e + 0.02 * s + 0.3 / (1 + period)
                rows.append({"engine": engine, "support": support, "building.period": period, "status": "ok",
                             "base_shear_coefficient": value, "base_moment_coefficient": value / 2,
                             "mode1_base_shear_coefficient": value / 1.2, "two_mode_base_shear_coefficient": None,
                             "max_drift_ratio": value / 100, "critical_coefficient": 0.1})
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--formats", default="png", help="comma list of png, svg, pdf")
    args = parser.parse_args()
    formats = [f.strip() for f in args.formats.split(",") if f.strip()]
    deck = keep_histories(load_deck(DECK, ['analysis.engine=["exact", "simplified"]']))
    start = time.perf_counter()
    results = analysis.run(deck)
    print(f"analysis (6 runs, histories kept): {time.perf_counter() - start:.2f} s")
    samples = max(r.histories["time"].size for r in results if r.histories)
    print(f"history samples per run: {samples}")
    data_best, data_median = timed(lambda: analysis_figures(deck, results), args.repeats)
    specs = analysis_figures(deck, results)
    analysis_count = len(specs)
    specs.update({f"paper_{k}": v for k, v in sweep_figures.paper_figures(
        sweep_rows(), ["exact", "simplified"], ["rigid", "bonded", "uplift"], "record El Centro", 0.5).items()})
    print(f"figure data of the run ({analysis_count} figures, pure functions): best {data_best:.1f} ms, "
          f"median {data_median:.1f} ms")
    empty = plots.FigureSpec("", "", [plots.Panel("", "")], columns=1, panel_size=(4.0, 3.0))
    with tempfile.TemporaryDirectory() as folder:
        plots.plot_figure(empty, Path(folder) / "warm.png")  # imports matplotlib
        for extension in formats:
            base, _ = timed(lambda e=extension: plots.plot_figure(empty, Path(folder) / f"empty.{e}"), args.repeats)
            print(f"\n{extension}: empty figure (baseline) {base:.1f} ms")
            print(f"{'figure':<34} {'best [ms]':>10} {'median [ms]':>12} {'/ empty':>8}  within target")
            worst = 0.0
            for name, spec in specs.items():
                path = Path(folder) / f"{name}.{extension}"
                best, median = timed(lambda s=spec, p=path: plots.plot_figure(s, p), args.repeats)
                worst = max(worst, median)
                ok = "yes" if median < 1e3 * TARGET_SECONDS else "NO"
                print(f"{name:<34} {best:>10.1f} {median:>12.1f} {median / base:>8.1f}  {ok}")
            print(f"slowest figure: {worst:.0f} ms = {worst / base:.1f} x the empty figure "
                  f"(target < {1e3 * TARGET_SECONDS:.0f} ms)")


if __name__ == "__main__":
    main()
