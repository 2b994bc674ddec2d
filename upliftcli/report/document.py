"""The report as data: sections of tables, figures, paragraphs and preformatted text (strings,
already formatted), rendered by report/html.py. Nothing here knows HTML."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..display import number  # noqa: F401 - the report's number format, display.number


@dataclass
class Table:
    """A table: id (unique in the report), caption, column headers (with units), rows of
    cells (text), a note under it."""

    id: str
    caption: str
    headers: list[str]
    rows: list[list[str]]
    note: str = ""


@dataclass
class Figure:
    """A figure of the run: id, caption and the name of its FigureSpec (figures/sets.py)."""

    id: str
    caption: str
    name: str


@dataclass
class Text:
    """Paragraphs of plain text; `items`: a bulleted list after them."""

    paragraphs: list[str]
    items: list[str] = field(default_factory=list)


@dataclass
class Pre:
    """Preformatted text (the deck as given) with a caption."""

    id: str
    caption: str
    text: str


@dataclass
class Section:
    id: str
    title: str
    blocks: list = field(default_factory=list)


@dataclass
class SignOff:
    """The sign-off block: (role, name) rows ("Prepared by", "A. Engineer"), each with lines for
    a signature and a date."""

    rows: list[tuple[str, str]]


#: the [project] fields of a deck (deck_schema.TABLES["project"]) and their labels in the title block
PROJECT_FIELDS = {"project": "Project", "job_number": "Job number", "revision": "Revision",
                  "engineer": "Prepared by", "checker": "Checked by"}


@dataclass
class Report:
    """Title, the lines under it, the sections, the criteria verdict and the exit code
    `uplift analyze` gives for the same run; project: the [project] fields given (PROJECT_FIELDS);
    subject: what is calculated (the deck's title); date: the run's (UTC); footer: the tool and
    its version, printed at the foot of every page."""

    title: str
    subtitle: list[str]
    sections: list[Section]
    verdict: str
    exit_code: int
    project: dict[str, str] = field(default_factory=dict)
    subject: str = ""
    date: str = ""
    footer: str = ""

    def tables(self) -> list[Table]:
        return blocks_of(self, Table)

    def figures(self) -> list[Figure]:
        return blocks_of(self, Figure)


def blocks_of(report: Report, kind: type) -> list:
    """The blocks of a kind (Table, Figure ...) in every section, in order."""
    return [b for s in report.sections for b in s.blocks if isinstance(b, kind)]
