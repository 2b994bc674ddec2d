"""`uplift analyze --plot DIR`, `uplift modes --plot DIR` and `uplift record spectrum --plot`
end to end through typer's test runner."""

import json
from pathlib import Path

import pytest
from cli_helpers import invoke

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
SMALL = ["--set", "building.stories=4", "--set", "ground_motion.window=[0, 6]"]
PNG = b"\x89PNG\r\n\x1a\n"




def test_analyze_plot_writes_every_figure_and_keeps_json_free_of_histories(tmp_path):
    result = invoke("analyze", EXAMPLE, *SMALL, "-e", "exact", "-e", "simplified", "--support", "uplift",
                    "--plot", tmp_path / "figs", "--format", "json")
    assert result.exit_code == 0, result.output
    names = sorted(p.name for p in (tmp_path / "figs").iterdir())
    assert names == [f"ten_story_elcentro.{n}.png" for n in ("energy_exact", "histories_exact", "modes",
                                                              "moment_rotation_exact", "profiles", "spectrum")]
    assert all((tmp_path / "figs" / n).read_bytes().startswith(PNG) for n in names)
    document = json.loads(result.stdout)
    assert all("histories" not in r["details"] for r in document["results"])  # kept for the figures only
    assert "wrote" in result.stderr and "profiles.png" in result.stderr


def test_analyze_plot_formats_and_the_simplified_engine_alone(tmp_path):
    result = invoke("analyze", EXAMPLE, *SMALL, "--plot", tmp_path, "--plot-format", "svg,png")
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        f"ten_story_elcentro.{n}.{e}" for n in ("modes", "profiles", "spectrum") for e in ("png", "svg"))
    assert "peak story drift ratio" in (tmp_path / "ten_story_elcentro.profiles.svg").read_text()


def test_analyze_plot_with_histories_writes_both(tmp_path):
    result = invoke("analyze", EXAMPLE, *SMALL, "-e", "exact", "--support", "uplift", "--plot", tmp_path,
                    "--histories", tmp_path / "h.csv")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "h.csv").read_text().splitlines()[2].startswith("time_s,")  # after the provenance lines
    assert (tmp_path / "ten_story_elcentro.histories_exact.png").exists()


def test_plot_input_errors(tmp_path):
    (tmp_path / "file").write_text("x")
    for args, words in (
        (("analyze", EXAMPLE, "--plot", tmp_path / "file"), "--plot"),
        (("analyze", EXAMPLE, "--plot", tmp_path, "--plot-format", "jpg"), "--plot-format"),
        (("analyze", EXAMPLE, EXAMPLE, "--plot", tmp_path), "a single deck"),
        (("modes", EXAMPLE, "--plot", tmp_path, "--plot-format", "gif"), "--plot-format"),
    ):
        result = invoke(*args)
        assert result.exit_code == 2, result.output
        assert words in result.stderr and "Traceback" not in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]  # nothing written


def test_modes_plot(tmp_path):
    result = invoke("modes", EXAMPLE, "--plot", tmp_path)
    assert result.exit_code == 0, result.output
    assert (tmp_path / "ten_story_elcentro.modes.png").read_bytes().startswith(PNG)


def test_record_spectrum_plot_has_three_panels(tmp_path):
    result = invoke("record", "spectrum", RECORD, "--record-units", "g", "--periods", "0.1:3:12", "--plot",
                    tmp_path / "s.svg", "--out", tmp_path / "s.csv")
    assert result.exit_code == 0, result.output
    svg = (tmp_path / "s.svg").read_text()
    assert all(words in svg for words in ("S_d [mm]", "S_v [mm/s]", "S_a [g]", "Response spectra"))
    # --units us: the figure in in and in/s, and the CSV too (unit-tagged headers): the same spectrum converted
    result = invoke("record", "spectrum", RECORD, "--units", "us", "--periods", "0.1:3:12", "--plot",
                    tmp_path / "us.svg", "--out", tmp_path / "us.csv")
    assert result.exit_code == 0, result.output
    svg = (tmp_path / "us.svg").read_text()
    assert all(words in svg for words in ("S_d [in]", "S_v [in/s]", "S_a [g]")) and "[mm]" not in svg
    rows = [[line.split(",") for line in (tmp_path / name).read_text().splitlines() if not line.startswith("#")]
            for name in ("us.csv", "s.csv")]
    assert rows[0][0] == ["damping_ratio", "period_s", "sd_in", "psv_in_s", "psa_in_s2", "psa_g", "abs_acc_in_s2"]
    assert rows[1][0] == ["damping_ratio", "period_s", "sd_m", "psv_m_s", "psa_m_s2", "psa_g", "abs_acc_m_s2"]
    assert len(rows[0]) == len(rows[1]) == 13
    inch = 0.0254  # m, exact
    for us, si in zip(rows[0][1:], rows[1][1:], strict=True):
        us, si = [float(x) for x in us], [float(x) for x in si]
        assert us[:2] == si[:2] and us[5] == si[5]  # damping, period, S_a in g
        assert [u * inch for u in (us[2], us[3], us[4], us[6])] == pytest.approx([si[2], si[3], si[4], si[6]],
                                                                                 rel=1e-9)


def test_figures_never_replace_an_input_and_an_existing_figure_needs_overwrite(tmp_path):
    """A record named deck.modes.png in the --plot folder was replaced by the figure; figures of an
    earlier run are replaced only with --overwrite (checked before the run, nothing written)."""
    folder = tmp_path / "d"
    folder.mkdir()
    record = folder / "deck.modes.png"
    record.write_bytes(RECORD.read_bytes())
    (folder / "deck.toml").write_text(EXAMPLE.read_text().replace("../records/elcentro_1940_ns_chopra.txt",
                                                                  "deck.modes.png"))
    for extra in ([], ["--overwrite"]):
        result = invoke("analyze", folder / "deck.toml", *SMALL, "--no-check", "--plot", folder, *extra)
        assert result.exit_code == 2 and record.read_bytes() == RECORD.read_bytes()
        assert result.stderr.startswith(f"error: --plot: {record}: a path that does not replace an input of the run")
    assert sorted(p.name for p in folder.iterdir()) == ["deck.modes.png", "deck.toml"]
    figures = tmp_path / "figs"
    assert invoke("modes", EXAMPLE, "--plot", figures).exit_code == 0
    first = (figures / "ten_story_elcentro.modes.png").read_bytes()
    result = invoke("analyze", EXAMPLE, *SMALL, "--no-check", "--plot", figures)
    assert result.exit_code == 2 and (figures / "ten_story_elcentro.modes.png").read_bytes() == first
    assert result.stderr == (f"error: --plot: {figures / 'ten_story_elcentro.modes.png'}: a new file (it exists; "
                             "pass --overwrite to replace it)\n")
    assert sorted(p.name for p in figures.iterdir()) == ["ten_story_elcentro.modes.png"]
    assert invoke("modes", EXAMPLE, "--plot", figures).exit_code == 2
    assert invoke("analyze", EXAMPLE, *SMALL, "--no-check", "--plot", figures, "--overwrite").exit_code == 0
    assert len(list(figures.iterdir())) == 3


def test_a_full_disk_under_analyze_plot_leaves_no_figure_behind(tmp_path, monkeypatch):
    """Issue 38: a full disk at the second figure of `analyze --plot` left the first one behind.
    The figures of one command are written all or none (figures/draw.plot_figures, atomic.write_set)."""
    import errno

    from upliftcli.runtime import atomic

    original, calls = atomic._finish, []

    def full_disk(tmp, target):
        calls.append(target.name)
        if len(calls) == 2:
            raise OSError(errno.ENOSPC, "No space left on device")
        original(tmp, target)

    monkeypatch.setattr(atomic, "_finish", full_disk)
    figures = tmp_path / "figs"
    result = invoke("analyze", EXAMPLE, *SMALL, "--plot", figures)
    assert result.exit_code == 2, result.output
    assert len(calls) == 2 and calls[0].endswith(".png") and calls[0] != calls[1]
    lines = result.stderr.strip().splitlines()
    assert lines[-1] == f"error: --plot: {figures}: a writable directory (No space left on device)"
    assert "wrote" not in result.stderr and not figures.exists()  # the folder it made is gone too
    (figures).mkdir()
    (figures / "notes.txt").write_text("kept")
    calls.clear()
    assert invoke("analyze", EXAMPLE, *SMALL, "--plot", figures).exit_code == 2
    assert sorted(p.name for p in figures.iterdir()) == ["notes.txt"]  # no figure, no temporary file
