"""`uplift examples DIR`: the bundled example decks and records written into DIR (the files are
upliftcli.runtime.examples'; this module checks DIR and writes them)."""

from __future__ import annotations

from pathlib import Path

import typer

from ..errors import InputError
from . import stdout
from .options import given_path, not_writable

#: the argument's name in messages
OPTION = "DIR"


def examples(
    folder: Path = typer.Argument(..., metavar=OPTION, parser=given_path,
                                  help="The folder to write into (created if missing)."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace example files that exist in DIR already."),
) -> None:
    """Write the example decks (DIR/inputs/*.toml) and the ground-motion records they read
    (DIR/records/, with records/README.md on the provenance and licence of each), as in the
    repository: `uplift analyze DIR/inputs/ten_story_elcentro.toml` runs the paper's example.

    Nothing is written when a file of DIR's name exists, or when an example file exists in DIR
    (unless --overwrite). Exit codes: 0 ok, 2 bad input.
    """
    from ..runtime.atomic import refuse_existing, write_set
    from ..runtime.examples import bundled_contents

    if folder.exists() and not folder.is_dir():
        raise InputError(OPTION, str(folder), "a folder (a file of that name exists)")
    files = {folder / name: data for name, data in bundled_contents().items()}
    refuse_existing(files, OPTION, overwrite, " in the folder")
    try:
        written = write_set(files)
    except OSError as error:
        raise not_writable(OPTION, folder, error, "a writable folder", "; nothing was written") from None
    stdout.echo(f"wrote {len(written)} files into {folder}: the decks in {folder / 'inputs'}, the records they read "
                f"in {folder / 'records'}", err=True)


def register(app: typer.Typer) -> None:
    app.command("examples")(examples)
