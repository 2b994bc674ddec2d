"""Benchmark: peak memory of a long exact analysis (issue 14: at most 300 MB), in a fresh process.

50 stories, T_1 = 0.05 s, uplift support, El Centro 1940 N-S (records/) tiled 16 times and
windowed to 450 s (22,500 samples, 450,000 internal steps x 110 states: within the exact
engine's limit of 50 million). The post-processing streams (engines/exact/digest.py), so the
peak stays bounded whatever the record's length. Printed: V_b, the run time and the peak
resident memory of the process, and as a baseline the peak of the same process after the
imports and the deck (what the analysis adds is the difference); once as the Python API runs
it, once as the `uplift` command does (process.keep_freed_memory: freed blocks are kept for reuse).

    python benchmarks/bench_memory.py
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TARGET_MB = 300.0

CHILD = r"""
import resource, sys, time
from upliftcli.analysis import run as analysis
from upliftcli.runtime.process import keep_freed_memory
if sys.argv[3] == "command":
    keep_freed_memory()
from upliftcli.deck.load import load_deck
deck = load_deck(sys.argv[1], ["building.stories=50", "building.period=0.05", f'ground_motion.record="{sys.argv[2]}"',
                               'ground_motion.format="text"', 'analysis.engine="exact"', 'analysis.supports="uplift"',
                               "ground_motion.window=[0, 450]"])
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
start = time.perf_counter()
(result,) = analysis.run(deck)
print(result.base_shear, time.perf_counter() - start, before, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
"""


def tiled_record(folder: Path, copies: int = 16) -> Path:
    """The bundled El Centro record repeated `copies` times, as a plain-text record in g."""
    lines = (ROOT / "records" / "elcentro_1940_ns_chopra.txt").read_text().splitlines()
    values = [line.split()[-1] for line in lines if line.strip() and not line.startswith("#")]
    path = folder / "elcentro_x16.txt"
    path.write_text("# dt = 0.02\n# units: g\n" + "\n".join(values * copies) + "\n")
    return path


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        record = tiled_record(Path(folder))
        for mode in ("api", "command"):
            done = subprocess.run([sys.executable, "-c", CHILD, str(ROOT / "inputs" / "ten_story_elcentro.toml"),
                                   str(record), mode], capture_output=True, text=True, check=True)
            base_shear, seconds, before, peak = (float(x) for x in done.stdout.split())
            verdict = "met" if peak <= TARGET_MB else "NOT met"
            print(f"{mode:7s}: 50 stories, T_1 = 0.05 s, uplift, 450 s of El Centro x16: V_b = {base_shear:.6e} N "
                  f"in {seconds:.1f} s")
            print(f"{mode:7s}: peak RSS {peak:.0f} MB (target <= {TARGET_MB:.0f} MB: {verdict}); after imports and "
                  f"deck {before:.0f} MB (the analysis adds {peak - before:.0f} MB, ratio {peak / before:.2f})")


if __name__ == "__main__":
    main()
