"""Terminal tables (cli/render.py, cli/fitting.py): readable at 80 and 100 columns (no cell cut, no line too
long, every number whole), $COLUMNS honoured without a terminal, tables too wide split in
parts that keep the label columns, and the modal table showing what the engine used."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from rich import box as rich_box
from rich.markup import escape
from rich.table import Table
from rich.text import Text
from typer.testing import CliRunner

from upliftcli.analysis import run as analysis
from upliftcli.cli import app, fitting, render
from upliftcli.deck.load import load_deck
from upliftcli.units import STANDARD_GRAVITY

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
runner = CliRunner()


def invoke(*args, columns: int):
    return runner.invoke(app, [str(a) for a in args], env={"CI": "true", "COLUMNS": str(columns)})


@pytest.mark.parametrize("columns", [80, 100])
@pytest.mark.parametrize("args", [
    ("analyze", EXAMPLE),
    ("analyze", EXAMPLE, "--engine", "exact", "--set", "ground_motion.window=[0, 8]"),
    ("analyze", ROOT / "inputs" / "ten_story_asce7.toml"),
    ("modes", EXAMPLE),
    ("record", "info", ROOT / "records" / "elcentro_1940_ns_chopra.txt", "--damping", "0.02,0.05,0.1"),
], ids=["simplified", "exact", "design-spectrum", "modes", "record-info"])
def test_tables_fit_the_width_and_cut_nothing(args, columns):
    result = invoke(*args, columns=columns)
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert max(len(line) for line in lines) <= columns
    assert "…" not in result.stdout


def test_every_number_of_the_summary_is_whole_at_80_columns():
    deck = load_deck(EXAMPLE)
    results = analysis.run(deck)
    text = invoke("analyze", EXAMPLE, "--no-check", columns=80).stdout
    for r in results:
        for value in (f"{1e-3 * r.base_shear:.1f}", f"{1e-3 * r.base_moment:.1f}", f"{r.base_shear_coefficient:.4f}"):
            assert value in text
    assert f"V_c = {1e-3 * results[0].critical_base_shear:.1f} kN" in " ".join(text.split())


def test_columns_sets_the_width_without_a_terminal(monkeypatch):
    monkeypatch.setenv("COLUMNS", "137")
    assert render.console().width == 137
    monkeypatch.setenv("COLUMNS", "wide")
    assert render.console().width == fitting.PIPE_WIDTH
    monkeypatch.delenv("COLUMNS")
    assert render.console().width == fitting.PIPE_WIDTH


def test_a_table_too_wide_is_split_keeping_its_label_columns():
    table = Table(title="wide")
    table.add_column("case", justify="left")
    for k in range(12):
        table.add_column(f"quantity {k} [kN m]", justify="right")
    for row in range(3):
        table.add_row(f"case {row}", *[f"{1e6 * (row + 1) + k:.1f}" for k in range(12)])
    parts = fitting.fit_table(table, 60)
    assert len(parts) > 1
    assert all(fitting.minimum_width(part) <= 60 for part in parts)
    assert all(part.columns[0].header == "case" and list(part.columns[0].cells) == ["case 0", "case 1", "case 2"]
               for part in parts)
    cells = [cell for part in parts for column in part.columns[1:] for cell in column.cells]
    assert sorted(cells) == sorted(f"{1e6 * (row + 1) + k:.1f}" for row in range(3) for k in range(12))
    assert [part.title for part in parts] == [f"wide ({k + 1}/{len(parts)})" for k in range(len(parts))]
    assert fitting.fit_table(table, 1000) == [table]


@pytest.mark.parametrize("box", [rich_box.HEAVY_HEAD, rich_box.SIMPLE, None])
@pytest.mark.parametrize("width", [40, 55, 70, 90])
def test_each_part_takes_as_many_columns_as_fit(box, width):
    """fit_table adds up column widths measured once (_frame_width): every part fits, measured
    as a whole, and would not with the next column."""
    table = Table(title="wide", box=box)
    table.add_column("case", justify="left")
    for k in range(9):
        table.add_column(f"quantity {k} {'x' * k} [kN m]", justify="right")
    table.add_row("case 0", *[f"{10.0**k:.1f}" for k in range(9)])
    parts = fitting.fit_table(table, width)
    assert len(parts) > 1
    start = 1  # the parts take the number columns in order, each after the label column
    for part in parts:
        count = len(part.columns) - 1
        assert fitting.minimum_width(part) <= width
        if start + count < len(table.columns):
            grown = fitting._part(table, [0, *range(start, start + count + 1)], compact=True)
            assert fitting.minimum_width(grown) > width
        start += count
    assert start == len(table.columns)


def test_the_quick_width_bound_is_never_below_what_rich_measures():
    table = Table(title="t")
    table.add_column("a [kN]", justify="right")
    table.add_column(escape("[b] and text"), justify="left", min_width=20)
    table.add_column(Text("stacked\nheading"), justify="right")
    table.add_row("1.0", escape("[bold]not markup[/bold]"), Text("12345"))
    table.add_row("[bold]2.0[/bold]", "x\ny", "")
    for box in (rich_box.HEAVY_HEAD, rich_box.SIMPLE, None):
        table.box = box
        assert fitting._widest(table) >= fitting._measure(table).maximum
    table.add_row("1", Table(), "2")
    assert fitting._widest(table) == float("inf")


def test_the_quick_width_is_what_rich_measures_where_it_says_so():
    """Start-up (issue 34): a table of texts (markup rendered as rich renders it) is not measured by
    rich (it draws every cell twice) to learn that it is too wide; where a text holds what
    printable() escapes or a tab, rich measures it."""
    table = Table(title="t")
    table.add_column(escape("disp. [mm]"), justify="right")
    table.add_column("meaning", justify="left", min_width=12)
    table.add_column(Text("stacked\nheading"), justify="right")
    table.add_row("1.0", "a long text " * 5, Text("12345"))
    table.add_row(escape("[bold]not markup[/bold]"), "x\ny", "")
    for box in (rich_box.HEAVY_HEAD, rich_box.SIMPLE, None):
        table.box = box
        assert fitting._measured_exactly(table)
        assert fitting._widest(table) == fitting._measure(table).maximum
        assert fitting._fits(table, 200) and not fitting._fits(table, 60)
    for compact in (False, True):  # each column alone, as fit_table measures it
        for index in range(len(table.columns)):
            part = fitting._part(table, [index], compact=compact)
            assert fitting._measured_exactly(part)
            assert fitting._quick_measure(part) == fitting._measure(part)
    table.add_row("  ", "", Text(""))
    assert fitting._quick_measure(table) == fitting._measure(table)
    table.add_row("[bold]2.0[/bold]", "a reference [16a]", Text("x"))  # markup: a tag, and brackets that are none
    assert fitting._measured_exactly(table)
    assert fitting._quick_measure(table) == fitting._measure(table)
    table.add_row("tab\there", "", "")
    assert not fitting._measured_exactly(table)
    assert fitting._widest(table) >= fitting._measure(table).maximum


def table_rows(text: str) -> list[list[str]]:
    return [[cell.strip() for cell in line.strip("│").split("│")] for line in text.splitlines() if line.startswith("│")]


def test_modal_table_shows_the_mode_1_the_engine_used():
    """Mode 1 of a flexible support: T1bar = T_1 sqrt(1 + w_1^2 m_1* h_1*^2 / K_theta) [21], with
    K_theta = 2 k_f b^2 [22] from the deck's values here, and the deck spectrum's S_a there."""
    deck = load_deck(ROOT / "inputs" / "ten_story_asce7.toml")
    system = deck.system
    modes = system.modes
    k_theta = system.foundation.rocking_stiffness(system.half_width)
    assert k_theta == pytest.approx(2 * system.foundation.stiffness * system.half_width**2)
    t1 = float(modes.periods[0])
    t1bar = t1 * math.sqrt(1 + modes.omega[0] ** 2 * modes.effective_mass[0] * modes.effective_height[0] ** 2 / k_theta)
    out = fitting.FittedConsole(width=100, highlight=False, force_terminal=False)
    for support in ("rigid", "bonded"):
        (result,) = analysis.run(deck, "simplified", support)
        with out.capture() as captured:
            out.print(render.modal_table(result))
        rows = table_rows(captured.get())
        if support == "rigid":
            assert rows[0][:2] == ["1", f"{t1:.4f}"]
            continue
        xi1bar = result.intermediates["xi1bar"]
        sa = float(deck.spectrum.sa(np.array([t1bar]), xi1bar)[0])
        assert rows[0][:3] == ["1*", f"{t1bar:.4f}", f"{sa / STANDARD_GRAVITY:.4f}"]  # S_a [g]
        assert rows[1][:2] == ["2", f"{modes.periods[1]:.4f}"]
        assert re.search(r"fixed-base T_1 = " + f"{t1:.4f}", " ".join(captured.get().split()))


@pytest.mark.parametrize("columns", [80, 100])
def test_sweep_summary_fits_and_repeats_the_group_columns(tmp_path, columns):
    result = invoke("sweep", EXAMPLE, "--vary", "foundation.k_f=1e8:1e10:3:log", "--vary", "building.period=0.5,1.5",
                    "--support", "bonded,uplift", "--out", tmp_path, "--workers", "1", columns=columns)
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert max(len(line) for line in lines) <= columns and "…" not in result.stdout
    rows = [line for line in lines if line.startswith("│ simplified")]
    assert all("0.5" in row or "1.5" in row for row in rows)  # each part names the group's period


def test_titles_are_printed_as_written(tmp_path):
    """No emoji codes replaced, no markup read: a deck's title reaches the terminal as written."""
    text = EXAMPLE.read_text().replace("../records/", f"{ROOT / 'records'}/")
    deck = tmp_path / "titled.toml"
    deck.write_text(re.sub(r'(?m)^title = .*$', 'title = "Block B :warning: [m] 10:30:00"', text))
    result = invoke("analyze", deck, "--no-check", columns=120)
    assert result.exit_code == 0, result.output
    assert "Block B :warning: [m] 10:30:00" in result.output


def test_the_uplift_ratio_states_the_criterion_of_each_foundation():
    """V1_bonded/V_c is stated with the criterion per foundation type: a Winkler mat loses contact
    at its kern, above 1/3 (the improved procedure's verdict: 'uplift yes' at 0.68), two edge
    elements above 1. The meaning printed beside it says so."""
    from upliftcli.engines.quantities import INTERMEDIATES

    meaning = INTERMEDIATES["V1_bonded/V_c"][1]
    assert "1 for two edge elements" in meaning and "1/3 for a Winkler mat" in meaning
    for deck_name, support in (("ten_story_winkler.toml", "uplift"), ("ten_story_elcentro.toml", "uplift")):
        deck = load_deck(Path(__file__).resolve().parents[1] / "inputs" / deck_name)
        (result,) = analysis.run(deck, "simplified", support)
        ratio = result.intermediates["V1_bonded/V_c"]
        assert result.uplift == (ratio > deck.system.foundation.contact_loss_moment_ratio)
        out = fitting.FittedConsole(width=200, highlight=False, force_terminal=False)
        with out.capture() as captured:
            out.print(render.intermediates_table(result))
        assert "Winkler mat (its kern" in " ".join(captured.get().split())
    winkler = load_deck(Path(__file__).resolve().parents[1] / "inputs" / "ten_story_winkler.toml")
    (result,) = analysis.run(winkler, "simplified", "uplift")
    assert 1 / 3 < result.intermediates["V1_bonded/V_c"] < 1 and result.uplift  # the case the issue saw


def test_the_table_modules_import_in_one_direction():
    """No import circle among the terminal-table modules (issue 34): an AST walk of their imports,
    those inside functions too (cli/tables.py and cli/fitting.py are what they share)."""
    import ast

    modules = ("render", "render_suite", "render_rocking", "render_batch", "sweep_render", "histories", "plotting",
               "stdout", "fitting", "tables")
    folder = ROOT / "upliftcli" / "cli"
    imports = {}
    for name in modules:
        tree = ast.parse((folder / f"{name}.py").read_text())
        found = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                found |= {node.module} if node.module else {alias.name for alias in node.names}
        imports[name] = found & set(modules)
    done: set[str] = set()

    def visit(name, path):
        assert name not in path, f"import circle: {' -> '.join([*path, name])}"
        if name not in done:
            for other in imports[name]:
                visit(other, [*path, name])
            done.add(name)

    for name in modules:
        visit(name, [])
