"""Seeded generators of the inputs tests/test_fuzz_paths.py runs: design spectra of every type
(inline and from table files), record-suite entries, record-command options and output folders
whose files may collide with the outputs. Every case is a plain value (reproducible from the
seed and its index); `item1` marks a case holding a deck value whose type or magnitude only the
one field checker of issue 29 item 1 refuses."""

from __future__ import annotations

import json
import math
import random
from dataclasses import dataclass, field

#: the deck-value problems of issue 29 item 1 (a wrong type, a magnitude outside 1e-30..1e30)
ITEM1_VALUES = (True, False, "1.0", "5%", "x", [1.0], [[1.0]], {"a": 1}, 1e300, -1e300, 1e-300, 1e31, 1e-31,
                math.nan, math.inf, -math.inf, "DATE")
DATE = "1979-05-27"  # a TOML date (written bare)


@dataclass
class Case:
    """A generated input: what it is (kind), its data and whether a value of item 1 is in it."""

    kind: str
    data: dict
    item1: bool = False
    files: dict = field(default_factory=dict)  # file name -> text, written into the case's folder


def toml(value) -> str:
    """A TOML value (inline tables, arrays, nan/inf, a bare date for "DATE")."""
    if value == "DATE":
        return DATE
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)  # JSON's escapes are TOML's
    if isinstance(value, list):
        return "[" + ", ".join(toml(v) for v in value) + "]"
    return "{" + ", ".join(f"{k} = {toml(v)}" for k, v in value.items()) + "}"


class Draw:
    """Values for one case; records whether an item-1 value was drawn."""

    def __init__(self, rng: random.Random, item1_rate: float = 0.15):
        self.rng, self.item1_rate, self.item1 = rng, item1_rate, False

    def number(self, low=0.01, high=3.0):
        """A number of the right type within the magnitude limits (plausible or at an edge), or
        now and then an item-1 value."""
        rng = self.rng
        if rng.random() < self.item1_rate:
            self.item1 = True
            return rng.choice(ITEM1_VALUES)
        return rng.choice([rng.uniform(low, high), rng.uniform(low, high), rng.uniform(low, high), 0.0, -1.0,
                           1e-30, 1e30, 2.5, 8.0, 10.0, 100.0, rng.randint(0, 30), -rng.uniform(0, 2)])

    def text(self, choices):
        if self.rng.random() < self.item1_rate:
            self.item1 = True
            return self.rng.choice([1, 2.5, True, [choices[0]], {"a": 1}, "DATE"])
        return self.rng.choice([*choices, "", "x", choices[0].upper()])

    def numbers(self, count, low, high, increasing=True):
        values = sorted(self.rng.uniform(low, high) for _ in range(count)) if increasing else \
            [self.rng.uniform(low, high) for _ in range(count)]
        if self.rng.random() < 0.3 and values:
            values[self.rng.randrange(len(values))] = self.number(low, high)
        return values


TYPES = ("asce7", "asce7-multiperiod", "ec8", "table", "table-file")


def table_file(draw: Draw, rows: int) -> str:
    """A spectrum table file: '#' comment, an optional header, rows of period [s] and S_a [g]."""
    rng = draw.rng
    periods = sorted(rng.uniform(0.0, 8.0) for _ in range(rows))
    lines = ["# period [s], S_a [g]"] + (["period,sa"] if rng.random() < 0.5 else [])
    for t in periods:
        sa = rng.uniform(0.05, 1.5)
        if rng.random() < 0.04:
            lines.append(rng.choice(["abc", "0.5", "nan,0.3", "0.5;0.3", ""]))
            continue
        if rng.random() < 0.04:
            draw.item1 = True  # a number out of the limits, read from the file (item 1: tables from files)
            sa = rng.choice([1e300, 1e-300, 1e31])
        lines.append(f"{t:.4f}{rng.choice([',', ' ', ', '])}{sa:.4g}")
    return "\n".join(lines) + "\n"


def spectrum_case(rng: random.Random) -> Case:
    """A design_spectrum table of a random type with keys drawn from clean and item-1 pools; now
    and then a key missing, an unknown key or a wrong 'type'."""
    draw = Draw(rng)
    kind = rng.choice(TYPES)
    files = {}
    if kind == "asce7":
        spectrum = {"type": "asce7", "sds": draw.number(), "sd1": draw.number(), "tl": draw.number(1, 16)}
    elif kind == "asce7-multiperiod":
        spectrum = {"type": "asce7-multiperiod", "sa": draw.numbers(rng.choice([22, 22, 22, 21, 0]), 0.05, 1.5,
                                                                    increasing=False)}
        for key in ("sds", "sd1"):
            if rng.random() < 0.3:
                spectrum[key] = draw.number()
        if rng.random() < 0.2:
            spectrum["units"] = draw.text(["g", "m/s2"])
    elif kind == "ec8":
        spectrum = {"type": "ec8", "ag": draw.number(), "ground_type": draw.text(["A", "B", "C", "D", "E"])}
        if rng.random() < 0.4:
            spectrum["spectrum_type"] = rng.choice([1, 2, 3, 0])
            if rng.random() < draw.item1_rate:
                draw.item1, spectrum["spectrum_type"] = True, rng.choice(ITEM1_VALUES)
        if rng.random() < 0.4:
            spectrum["importance"] = draw.number(0.5, 1.6)
    else:
        spectrum = {"type": "table", "damping": rng.choice([0.05, 0.02, 0.1, 0.0, 1.0]) if rng.random() < 0.7
                    else draw.number(0.0, 0.3)}
        if kind == "table-file":
            spectrum["file"] = rng.choice(["spectrum.csv"] * 6 + ["missing.csv", ".", "fifo.csv"])
            files["spectrum.csv"] = table_file(draw, rng.choice([0, 1, 2, 5, 12]))
        if rng.random() < 0.3:
            spectrum["units"] = draw.text(["g", "m/s2", "cm/s2"])
        if rng.random() < 0.2:
            spectrum["damping_correction"] = draw.text(["asce", "ec8"])
        if kind == "table-file" and not (isinstance(spectrum["damping"], float) and 0.0 < spectrum["damping"] < 1.0
                                         and spectrum.get("units", "g") in ("g", "m/s2", "cm/s2")):
            draw.item1 = True  # item 1: a deck key of a spectrum read from a file is blamed on the file
        else:
            count = rng.choice([0, 1, 2, 5, 12])
            spectrum["periods"] = draw.numbers(count, 0.0, 8.0, increasing=rng.random() < 0.9)
            spectrum["sa"] = draw.numbers(rng.choice([count, count, count + 1]), 0.05, 1.5, increasing=False)
    if rng.random() < 0.2:
        spectrum["name"] = draw.text(["Site A", "table"])
    if rng.random() < 0.06:
        spectrum.pop(rng.choice(sorted(spectrum)))
    if rng.random() < 0.04:
        spectrum["sdss"] = 1.0
    return Case("spectrum", {"spectrum": spectrum}, draw.item1, files)


def record_text(rng: random.Random, samples: int, dt: float = 0.02) -> str:
    """A plain-text record in g: a decaying sine with noise."""
    values = [0.3 * math.sin(0.9 * i) * math.exp(-0.004 * i) + 0.02 * rng.uniform(-1, 1) for i in range(samples)]
    return f"# dt = {dt}\n# units: g\n" + "\n".join(f"{v:.5f}" for v in values) + "\n"


def suite_case(rng: random.Random) -> Case:
    """A [ground_motion] suite of 1-3 entries (paths or tables with file, dt, units, format, scale)
    with a scaling and a narrow period range (the case stays cheap)."""
    draw = Draw(rng)
    entries = []
    for _ in range(rng.choice([1, 2, 2, 3])):
        name = rng.choice(["r1.txt", "r2.txt", "r1.txt", "missing.txt", "zero.txt", "folder"])
        if rng.random() < 0.3:
            entries.append(name)
            continue
        entry = {"file": name if rng.random() > draw.item1_rate else draw.number()}
        if rng.random() < 0.3:
            entry["dt"] = rng.choice([0.02, 0.02, 0.01]) if rng.random() < 0.8 else draw.number(0.001, 0.05)
        if rng.random() < 0.3:
            entry["units"] = rng.choice(["g", "m/s2", "cm/s2"]) if rng.random() < 0.8 else draw.text(["furlong"])
        if rng.random() < 0.2:
            entry["format"] = draw.text(["text", "csv", "at2"])
        if rng.random() < 0.3:
            entry["scale"] = rng.choice([1.0, 2.0, -1.0, 0.5]) if rng.random() < 0.8 else draw.number()
        if rng.random() < 0.05:
            entry["weight"] = 1.0
        dt, scale = entry.get("dt", 0.02), entry.get("scale", 1.0)
        if not (isinstance(dt, float) and 0.0 < dt <= 10.0 and isinstance(scale, float) and scale != 0.0
                and entry.get("units", "g") in ("g", "m/s2", "cm/s2")):
            draw.item1 = True  # item 1: a suite entry's value is blamed on the record file, not the deck field
        entries.append(entry)
    low = rng.choice([0.5, 0.5, 0.3, 1e-6, 2.0])
    data = {"suite": entries, "scaling": rng.choice(["amplitude"] * 4 + ["none"] * 2 + ["factor"]),
            "period_range": [low, low * rng.choice([1.5, 2.0, 1.5, 2.0, 0.5])]}
    files = {"r1.txt": record_text(rng, 600), "r2.txt": record_text(rng, 650),
             "zero.txt": "# dt = 0.02\n# units: g\n" + "0.0\n" * 600}
    return Case("suite", data, draw.item1, files)


RECORD_OPTIONS = {
    "--dt": ["0.02", "0.01", "0", "-1", "1e-300", "nan", "inf", "x", "20"],
    "--record-units": ["g", "m/s2", "cm/s2", "furlong", ""],
    "--units": ["si", "us", "g", "furlong", ""],  # display units; an acceleration unit: the old --record-units
    "--scale": ["1", "2", "0", "-1", "nan", "1e300", "x"],
    "--window": ["0:5", "1:3", "5:1", "0:0", "x", "0:1e300", "100:200"],
    "--damping": ["0.05", "0.02,0.05", "5%", "0", "1", "-0.1", "x", ""],
    "--periods": ["0.1,1", "0.05:5:20", "0:1:5", "1:0.1:5", "0.1:5:10000000", "1e-9", "x", "0.1:5:1"],
    "--input-format": ["text", "csv", "at2", "shared", "xml"],
}
RECORD_FILES = ("rec.txt", "rec.txt", "rec.txt", "short.txt", "empty.txt", "binary.txt", "fifo.txt", "missing.txt",
                "folder")


def record_command_case(rng: random.Random) -> Case:
    """`record info` or `record spectrum` on one of several files with 0-3 options drawn."""
    command = rng.choice(["info", "spectrum"])
    options = {}
    for option in rng.sample(sorted(RECORD_OPTIONS), rng.choice([0, 1, 2, 3])):
        if command == "info" and option == "--periods":
            continue
        options[option] = rng.choice(RECORD_OPTIONS[option])
    files = {"rec.txt": record_text(rng, 300), "short.txt": "# dt = 0.02\n# units: g\n0.1\n",
             "empty.txt": "", "binary.txt": "0.1\n\x00\n"}
    return Case("record", {"command": command, "file": rng.choice(RECORD_FILES), "options": options}, False, files)


GENERATE_OPTIONS = {
    "--count": ["1", "11", "0", "-3", "1000000", "400"],
    "--seed": ["1", "0", "-1", str(2**63), "x"],
    "--dt": ["0.01", "0.005", "1e-6", "1e-30", "0", "-0.01", "nan", "0.2"],
    "--stationary": ["10", "0", "-1", "9999", "nan", "inf", "1e300"],
    "--set": ["ground_motion.period_range=[0.2, 2]", "ground_motion.period_range=[1e-6, 2e-6]",
              "ground_motion.period_range=[0.2, 12]", "building.period=0.3"],
}


def generate_case(rng: random.Random) -> Case:
    """`record generate` with options drawn; its --out folder holds a manifest.json already, so
    that a valid command is refused before it generates (and the manifest must stay)."""
    options = {option: rng.choice(values) for option, values in GENERATE_OPTIONS.items() if rng.random() < 0.6}
    options.setdefault("--seed", "1")
    return Case("generate", {"options": options})


#: commands that write files, with the names they write into the folder d (deck d/deck.toml)
OUTPUTS = {
    "modes": ["deck.modes.png"],
    "analyze-out": ["deck.json", "deck.csv", "deck.elements.csv", "deck.deck.toml"],
    "analyze-plot": ["deck.profiles.png", "deck.modes.png", "deck.spectrum.png"],
    "report": ["report.html"],
    "spectrum": ["spectrum.csv"],
}


def output_case(rng: random.Random) -> Case:
    """A folder d with the deck and its record under a name that may be an output's, files of an
    earlier run among the outputs, a command writing into d and --overwrite or not."""
    command = rng.choice(sorted(OUTPUTS))
    names = OUTPUTS[command]
    record = rng.choice(["rec.txt", "rec.txt", *names])
    existing = [name for name in names if name != record and rng.random() < 0.5]
    return Case("output", {"command": command, "record": record, "existing": existing,
                           "overwrite": rng.random() < 0.4})


def cases(kind: str, count: int, seed: int) -> list[Case]:
    """`count` cases of a kind, reproducible from the seed."""
    make = {"spectrum": spectrum_case, "suite": suite_case, "record": record_command_case,
            "generate": generate_case, "output": output_case}[kind]
    return [make(random.Random(f"{seed}-{kind}-{k}")) for k in range(count)]
