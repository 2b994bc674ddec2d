"""Text is made safe for the terminal in one place (errors.printable): a deck's title, its
[project] fields, a record's header, a file name in a warning or an error line never reach the
terminal as control characters; they are shown as visible escapes ('\\x1b[2J')."""

from __future__ import annotations

import ast
import os
from pathlib import Path

from cli_helpers import invoke

from upliftcli.errors import InputError, one_line, printable

ROOT = Path(__file__).resolve().parent.parent
CLEAR = "\x1b[2J\x1b[H"  # clears the screen and moves the cursor home
#: characters a terminal acts on: ESC, BEL, CR, backspace, a C1 CSI, DEL, a right-to-left override
HOSTILE = ("\x1b", "\x07", "\r", "\x08", "\x9b", "\x7f", "\u202e")
RECORD = "# dt = 0.02\n# units: g\n" + "\n".join(f"{0.1 * (-1) ** i * (i % 7) / 7:.4f}" for i in range(80)) + "\n"


def deck(folder: Path, title: str = "t", mass: str = "2.0e5", project: str = "", name: str = "deck.toml") -> Path:
    (folder / "rec.txt").write_text(RECORD)
    path = folder / name
    path.write_text(f'title = "{title}"\n{project}\n[building]\nstories = 3\nfloor_mass = {mass}\nstory_height = 3.0\n'
                    "period = 0.4\n[foundation]\nslenderness = 3.0\nfrequency_ratio = 8\ndamping_ratio = 0.1\n"
                    '[ground_motion]\nrecord = "rec.txt"\n[analysis]\nsupports = ["rigid", "uplift"]\n')
    return path


def assert_safe(text: str) -> None:
    found = [ch for ch in HOSTILE if ch in text]
    assert not found, (found, text[:400])


def test_printable_shows_control_characters_as_escapes():
    assert printable(f"a{CLEAR}b") == "a\\x1b[2J\\x1b[Hb"
    assert printable("ok \u00e9 \u4e2d") == "ok \u00e9 \u4e2d"  # printable text as it is
    assert printable("x\u202ey\x9bz\x7f") == "x\\u202ey\\x9bz\\x7f"
    assert printable("one\ntwo\tthree") == "one\\ntwo\\tthree"
    assert printable("one\ntwo\tthree\r", lines=True) == "one\ntwo\tthree\\r"
    assert one_line("a\nb\x1b") == "a\\nb\\x1b"


def test_analyze_shows_an_escape_in_the_title_and_project_fields(tmp_path):
    project = ('[project]\nproject = "p\\u001b[2J"\njob_number = "j\\u0007"\nengineer = "e\\u009b31m"\n'
               'checker = "c\\r"\nrevision = "r\\u202e"\n')
    result = invoke("analyze", deck(tmp_path, title="\\u001b[2J\\u001b[H x", project=project))
    assert result.exit_code == 0, result.output
    assert_safe(result.stdout + result.stderr)
    assert "\\x1b[2J\\x1b[H x" in result.stdout  # the title, visibly


def test_analyze_modes_shows_an_escape_in_the_title(tmp_path):
    result = invoke("modes", deck(tmp_path, title="\\u001b]0;owned\\u0007"))
    assert result.exit_code == 0, result.output
    assert_safe(result.stdout + result.stderr)
    assert "\\x1b]0;owned\\x07" in result.stdout


def test_a_warning_naming_a_file_with_an_escape_is_safe(tmp_path):
    result = invoke("analyze", deck(tmp_path, mass="300", name=f"d{CLEAR}.toml"))  # implausible: a warning
    assert result.exit_code == 0, result.output
    warning = [line for line in result.stderr.splitlines() if line.startswith("warning:")]
    assert warning and "floor_mass" in warning[0] and "\\x1b[2J" in warning[0], result.stderr
    assert_safe(result.stdout + result.stderr)


def test_an_error_line_with_an_escape_is_one_safe_line(tmp_path):
    path = deck(tmp_path, name=f"e{CLEAR}.toml")
    path.write_text(path.read_text() + '"\\u001b[2J" = 1\n')  # an unknown key with an escape in its name
    result = invoke("analyze", path)
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: ") and result.stderr.count("\n") == 1, result.stderr
    assert "\\x1b[2J" in result.stderr
    assert_safe(result.stdout + result.stderr)
    assert_safe(str(InputError(f"d{CLEAR}", "title", "a string")))


def test_a_record_header_with_an_escape_is_shown_safe(tmp_path):
    path = tmp_path / "r.txt"
    path.write_text(f"# El Centro{CLEAR}\x07\n" + RECORD)
    result = invoke("record", "info", path)
    assert result.exit_code == 0, result.output
    assert "El Centro\\x1b[2J" in result.stdout
    assert_safe(result.stdout + result.stderr)


def test_a_python_warning_is_shown_safe(capsys):
    """matplotlib warns 'Glyph 27 (\\x1b) missing' for a title's ESC: the command shows Python's
    warnings through the one place too (cli.main sets warnings.showwarning)."""
    from upliftcli.cli.stdout import show_warning

    show_warning(UserWarning(f"Glyph 27 ({CLEAR}) missing"), UserWarning, "draw.py", 95)
    err = capsys.readouterr().err
    assert "Glyph 27 (\\x1b[2J\\x1b[H) missing" in err
    assert_safe(err)


def test_the_command_shows_a_library_warning_about_the_title_safe(tmp_path):
    import subprocess
    import sys

    path = deck(tmp_path, title="\\u001b[2J plotted")
    done = subprocess.run([sys.executable, "-c", "from upliftcli.cli import main; main()", "modes", str(path),
                           "--plot", str(tmp_path / "figures")], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 0, done.stderr
    assert_safe(done.stdout + done.stderr)  # matplotlib (3.11) warns 'Glyph 27 (\x1b) missing', shown safe


def test_every_echo_of_the_commands_goes_through_the_one_place():
    """cli/stdout.echo makes text safe (errors.printable) and the rich consoles their texts
    (cli/fitting.SafeConsole): no command module calls typer.echo or print itself."""
    found = []
    for path in sorted((ROOT / "upliftcli" / "cli").glob("*.py")):
        if path.name == "stdout.py":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call):
                name = ast.unparse(node.func)
                if name in ("typer.echo", "click.echo", "sys.stderr.write", "sys.stdout.write") or (
                        name == "print" and not (node.args and ast.unparse(node.args[0]).startswith("printable("))):
                    found.append(f"{path.name}:{node.lineno}: {name}")
    assert not found, found
