"""The example decks and the records they read, as `uplift examples DIR` writes them: inputs/*.toml
and everything under records/ (the records, records/README.md with the provenance of each, a
suite's manifest), in the layout of the repository, so that a deck's `../records/...` paths hold
and every command of the README runs in DIR as in a clone.

The repository keeps one copy of them, inputs/ and records/ at its root. A wheel or an sdist
install carries them as package data, upliftcli/examples/, copied there at build time
(setup.py, BuildWithExamples; MANIFEST.in puts them in the sdist). A source checkout (PYTHONPATH,
`pip install -e .`) reads them from the checkout's root.
"""

from __future__ import annotations

from pathlib import Path

#: the package data of a wheel (setup.py writes it at build time)
PACKAGED = Path(__file__).resolve().parents[1] / "examples"
#: a source checkout's root, where the repository keeps them
CHECKOUT = Path(__file__).resolve().parents[2]
#: the decks: the *.toml files of the first folder; the records: every file under the second
FOLDERS = ("inputs", "records")


def bundled_root() -> Path:
    """The folder that holds inputs/ and records/: the package's examples/ where it was built
    with them, else the source checkout's root."""
    return PACKAGED if (PACKAGED / FOLDERS[0]).is_dir() else CHECKOUT


def bundled_files(root: Path | None = None) -> list[str]:
    """The example files, as paths relative to `root` (default bundled_root()) with '/' between
    parts, sorted: inputs/*.toml, then every file under records/."""
    root = bundled_root() if root is None else root
    decks = sorted((root / FOLDERS[0]).glob("*.toml"))
    records = sorted(path for path in (root / FOLDERS[1]).rglob("*") if path.is_file())
    return [path.relative_to(root).as_posix() for path in (*decks, *records)]


def bundled_contents(root: Path | None = None) -> dict[str, bytes]:
    """Each example file's bytes by its relative path (bundled_files)."""
    root = bundled_root() if root is None else root
    return {name: (root / name).read_bytes() for name in bundled_files(root)}
