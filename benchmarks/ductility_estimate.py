"""The R-mu-T estimate of a yielding building's ductility against the exact engine (issue 35,
item 2; docs/theory.md 15.6, docs/accuracy.md). Nothing is calibrated: the relations are the
published ones (engines/ductility_estimate.py) and this measures their spread.

For every case (deck variant x support x record) the elastic demand is taken two ways, from the
exact engine's elastic run (no strengths) and from the simplified engine (the response spectrum
procedure on the record's spectrum); each story's R_j = elastic story shear / story strength gives
its estimated ductility mu_j by the relation at the building's period (T_1 on the rigid support,
the bonded system's T~_1 on the bonded and uplift supports, the simplified engine's T1bar) with
the record's T_c (ductility_estimate.characteristic_period). They are compared with the exact
engine's yielding run:

- story: the largest estimated mu_j over the largest exact story ductility (peak |drift| / yield drift);
- roof: the estimate from R_b = elastic base shear / base-shear strength over the exact roof
  (system) ductility u_r / (u_r,el / R_b) (ductility_estimate.roof_ductility; exact elastic demand only).

Cases where the exact building stays elastic (largest story ductility <= 1) are counted apart.

Decks: inputs/ten_story_elcentro.toml (two elements, h/b = 10) at T_1 = 0.5, 1 and 2 s, at T_1 =
1 s with h/b = 6 (the building of the ASCE 7 decks), and inputs/ten_story_winkler.toml (T_1 = 1 s,
bonded and uplift); strength_coefficient 0.1, 0.2, 0.3, 0.5; hardening_ratio 0, 0.05, 0.1; records:
El Centro 1940 N-S x1 and x2 and the 11 records of records/ten_story_asce7_suite (public domain /
synthetic, all in records/).

    python benchmarks/ductility_estimate.py [--quick] [--rows /tmp/ductility_rows.jsonl]   # ~6 min CPU
    python benchmarks/ductility_estimate.py --from-rows /tmp/ductility_rows.jsonl       # the tables again

The two T_1 = 1 s two-element families are one building on the rigid support (the slenderness
only changes the foundation): their rigid cases are counted twice in the rigid rows.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import json
from pathlib import Path

import numpy as np

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.engines import ductility_estimate as est
from upliftcli.errors import AnalysisError, InputError
from upliftcli.motion.measures import peak_motion

ROOT = Path(__file__).resolve().parents[1]
ELCENTRO = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"
SUITE = sorted((ROOT / "records" / "ten_story_asce7_suite").glob("*.txt"))
EL_CENTRO_RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
#: (name, deck, overrides, supports)
FAMILIES = (
    ("two-element T1=0.5 h/b=10", ELCENTRO, ["building.period=0.5"], ("rigid", "bonded", "uplift")),
    ("two-element T1=1 h/b=10", ELCENTRO, ["building.period=1.0"], ("rigid", "bonded", "uplift")),
    ("two-element T1=2 h/b=10", ELCENTRO, ["building.period=2.0"], ("rigid", "bonded", "uplift")),
    ("two-element T1=1 h/b=6", ELCENTRO, ["building.period=1.0", "foundation.slenderness=6"],
     ("rigid", "bonded", "uplift")),
    ("winkler T1=1", WINKLER, ["analysis.modes=10"], ("bonded", "uplift")),
)
STRENGTHS = (0.1, 0.2, 0.3, 0.5)
HARDENING = (0.0, 0.05, 0.1)
RELATION_NAMES = tuple(est.RELATIONS)


def motions(quick: bool) -> list[tuple[str, list[str]]]:
    """(name, overrides) of every record: El Centro x1 and x2, then the suite's records."""
    elcentro = [f"ground_motion.record={EL_CENTRO_RECORD}", "ground_motion.units=g"]
    out = [(f"El Centro x{factor}", [*elcentro, f"ground_motion.scale={factor}"]) for factor in (1, 2)]
    suite = SUITE[:2] if quick else SUITE
    out += [(path.stem, [f"ground_motion.record={path}", "ground_motion.units=g", "ground_motion.scale=1"])
            for path in suite]
    return out


def elastic_demand(deck, support: str) -> dict:
    """The exact elastic run and the simplified engine's story shears, base shear and roof, with the
    period the relation takes (T_1 rigid, T~_1 otherwise) and the record's T_c."""
    exact = analysis.run_one(deck, "exact", support)
    simple = analysis.run_one(deck, "simplified", support)
    record = deck.ground_motion
    pgv, _ = peak_motion(record.acceleration, record.dt)
    period = deck.system.modes.periods[0] if support == "rigid" else simple.intermediates["T1bar"]
    return {"exact_shear": np.abs(exact.peaks["shear"]), "simple_shear": np.abs(simple.peaks["shear"]),
            "roof": float(exact.peaks["displacement"][-1]), "period": float(period),
            "corner": est.characteristic_period(record.pga, pgv)}


def case_row(demand: dict, result, strengths: np.ndarray) -> dict:
    """The exact peaks of one yielding run and every estimate of them."""
    exact_mu = float(np.max(result.peaks["ductility"]))
    r_base = demand["exact_shear"][0] / strengths[0]
    row = {"exact_story": exact_mu,
           "exact_roof": est.roof_ductility(float(result.peaks["displacement"][-1]), demand["roof"], r_base),
           "R_base": float(r_base)}
    for relation in RELATION_NAMES:
        for source in ("exact", "simple"):
            mus = est.story_ductilities(demand[f"{source}_shear"], strengths, demand["period"], demand["corner"],
                                        relation)
            row[f"{relation}/{source}/story"] = float(np.max(mus))
        row[f"{relation}/exact/roof"] = est.ductility(r_base, demand["period"], demand["corner"], relation)
    return row


def family_rows(name: str, path: Path, overrides: list[str], supports, records) -> list[dict]:
    """Every case of one deck family."""
    rows = []
    for record, given in records:
        for support in supports:
            rows += support_rows(name, path, [*overrides, *given], support, record)
    return rows


def support_rows(name: str, path: Path, overrides: list[str], support: str, record: str) -> list[dict]:
    """The cases of one deck variant, support and record: every strength and hardening."""
    demand = elastic_demand(load_deck(path, overrides), support)
    rows = []
    for coefficient in STRENGTHS:
        for alpha in HARDENING:
            deck = load_deck(path, [*overrides, f"building.strength_coefficient={coefficient}",
                                    f"building.hardening_ratio={alpha}"])
            try:
                result = analysis.run_one(deck, "exact", support)
            except (AnalysisError, InputError) as error:
                print(f"skipped {name} {support} {record} C={coefficient} alpha={alpha}: {error}")
                continue
            row = case_row(demand, result, deck.system.building.story_strength)
            rows.append({"family": name, "support": support, "record": record, "C": coefficient,
                         "alpha": alpha, "T": demand["period"], "Tc": demand["corner"], **row})
    return rows


def spread(values) -> str:
    """n, median, 10th and 90th percentiles, min and max of the ratios."""
    a = np.asarray(values, dtype=float)
    p10, p50, p90 = np.percentile(a, [10, 50, 90])
    return f"| {a.size} | {p50:.2f} | {p10:.2f} | {p90:.2f} | {a.min():.2f} | {a.max():.2f} |"


#: the estimates compared: relation/elastic demand/measure
ESTIMATES = tuple([f"{r}/{s}/story" for r in RELATION_NAMES for s in ("exact", "simple")]
                  + [f"{r}/exact/roof" for r in RELATION_NAMES])


def table_line(rows: list[dict], support: str, key: str) -> str:
    """One line of the table: the spread of estimate / exact of one estimate on one support."""
    relation, source, measure = key.split("/")
    exact = "exact_story" if measure == "story" else "exact_roof"
    ratios = [row[key] / row[exact] for row in rows if row["support"] == support]
    demand = "exact" if source == "exact" else "simplified"
    return f"| {support} | {relation} | {demand} | {measure} {spread(ratios)}"


def table(rows: list[dict]) -> str:
    """The markdown table of the ratios estimate / exact, by support, relation, demand and measure,
    over the cases that yielded."""
    yielded = [row for row in rows if row["exact_story"] > 1.0]
    supports = [s for s in ("rigid", "bonded", "uplift") if any(row["support"] == s for row in yielded)]
    return "\n".join(["| support | relation | elastic demand | measure | cases | median | p10 | p90 | min | max |",
                      "|---|---|---|---|---|---|---|---|---|---|",
                      *(table_line(yielded, s, key) for s in supports for key in ESTIMATES)])


def split_line(rows: list[dict], support: str, name: str, value) -> str:
    """One line of split_table: the spread of Vidic's estimate (exact elastic demand) of the story and
    roof ductility over the cases of one support and one value of the field `name`."""
    mine = [row for row in rows if row["support"] == support and row[name] == value]
    story = spread([row["vidic1994/exact/story"] / row["exact_story"] for row in mine])
    roof = spread([row["vidic1994/exact/roof"] / row["exact_roof"] for row in mine])
    return f"| {support} | {value} | story {story} roof {roof}"


def split_table(rows: list[dict], name: str) -> str:
    """The spread of Vidic's estimate from the exact elastic demand split by the field `name`
    (C: strength coefficient, alpha: hardening ratio), over the cases that yielded."""
    yielded = [row for row in rows if row["exact_story"] > 1.0]
    values = sorted({row[name] for row in yielded})
    head = "| cases | median | p10 | p90 | min | max |"
    return "\n".join([f"| support | {name} | measure {head} measure {head}",
                      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
                      *(split_line(yielded, s, name, v) for s in ("rigid", "bonded", "uplift") for v in values
                        if any(row["support"] == s for row in yielded))])


def elastic_cases(rows: list[dict]) -> str:
    """How many cases stayed elastic in the exact run, and how many of them each estimate calls elastic."""
    elastic = [row for row in rows if row["exact_story"] <= 1.0]
    told = {key: sum(row[key] <= 1.0 for row in elastic) for key in ESTIMATES if key.endswith("/story")}
    return f"{len(elastic)} of {len(rows)} cases stayed elastic; estimated elastic among them: {told}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two suite records, no Winkler deck")
    parser.add_argument("--rows", type=Path, help="also write every case as one JSON line to this file")
    parser.add_argument("--from-rows", type=Path, help="summarize the cases of a --rows file, running nothing")
    args = parser.parse_args()
    rows = [json.loads(line) for line in args.from_rows.read_text().splitlines()] if args.from_rows else run(args)
    print(table(rows))
    for name in ("C", "alpha"):
        print(split_table(rows, name))
    print(elastic_cases(rows))


def run(args) -> list[dict]:
    """Every case (--quick: two families, two suite records), written to --rows if given."""
    rows = []
    families = FAMILIES[:2] if args.quick else FAMILIES
    for name, path, overrides, supports in families:
        rows += family_rows(name, path, overrides, supports, motions(args.quick))
        print(f"{name}: {len(rows)} cases so far", flush=True)
    if args.rows is not None:
        args.rows.write_text("".join(json.dumps(row) + "\n" for row in rows))
    return rows


if __name__ == "__main__":
    main()
