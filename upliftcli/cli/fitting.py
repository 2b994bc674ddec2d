"""The console of the terminal tables, and every table fitted to its width (80 columns and up).

A table that is too wide is drawn with the headings of its number columns stacked, and if that is
still too wide, split in parts that repeat its leading label columns (fit_table; the console of
console() does it for every table it prints). A number is never cut. Without a terminal the width
is $COLUMNS, else 120.
"""

from __future__ import annotations

import os

from rich.cells import cell_len
from rich.console import Console
from rich.markup import render as render_markup
from rich.measure import Measurement
from rich.segment import Segment
from rich.table import Column, Table
from rich.text import Text

from ..errors import printable
from ..runtime.patterns import lazy

#: width of the output when it is not a terminal and $COLUMNS does not say
PIPE_WIDTH = 120

_NUMBER = lazy(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?%?|-")
#: a word of a heading; a unit in brackets, "[kN m]", is one word
_WORD = lazy(r"\[[^\]]*\]|[^\s\[]+")


def console_width(environ=os.environ) -> int | None:
    """$COLUMNS when it is a positive integer, else None."""
    text = environ.get("COLUMNS", "").strip()
    return int(text) if text.isdigit() and int(text) > 0 else None


class SafeConsole(Console):
    """A Console whose every text is made safe for the terminal (errors.printable): a deck's
    title, a record's header or a table cell holding ESC [2J is shown as '\\x1b[2J', not obeyed.
    Its strings (titles, cells, headings) are made safe before they are laid out, so that the
    widths are those shown, and every segment drawn once more (a rich Text, a progress label)."""

    def render_str(self, text: str, **kwargs) -> Text:
        return super().render_str(printable(text, lines=True), **kwargs)

    def render(self, renderable, options=None):
        for segment in super().render(renderable, options):
            yield segment if segment.control else _safe(segment)


def _safe(segment: Segment) -> Segment:
    """The segment with its text made safe; the same segment where the text is safe already (rich
    renders nested renderables through render: each segment passes here once per level)."""
    text = printable(segment.text, lines=True)
    return segment if text is segment.text else Segment(text, segment.style)


class FittedConsole(SafeConsole):
    """A Console that draws every table within its width (fit_table); a reader that closes the
    pipe early (`| head`) silences it and the command goes on (cli/stdout.py; rich would exit 1)."""

    def print(self, *objects, **kwargs) -> None:
        super().print(*[part for item in objects for part in _fitted(item, self.width)], **kwargs)

    def on_broken_pipe(self) -> None:
        from .stdout import silence

        silence()
        self.quiet = True


def _fitted(item, width: int) -> list:
    """A table in the parts that fit `width` (fit_table); anything else as it is."""
    return fit_table(item, width) if isinstance(item, Table) else [item]


def console(stderr: bool = False) -> Console:
    """A console that never needs a terminal: on a terminal its width, else $COLUMNS or
    PIPE_WIDTH; tables too wide for it are split (FittedConsole). Texts are printed as they
    are: no ":name:" emoji codes replaced (a deck title "Block B :warning:" stays that)."""
    probe = Console(stderr=stderr)
    width = None if probe.is_terminal else console_width() or PIPE_WIDTH
    return FittedConsole(stderr=stderr, width=width, highlight=False, emoji=False)


def _measure(table: Table) -> Measurement:
    probe = SafeConsole(width=100_000, emoji=False)
    return Measurement.get(probe, probe.options, table)


def minimum_width(table: Table) -> int:
    """The fewest columns the table can be drawn in without cutting a cell (headings and
    texts wrapped at their blanks, numbers whole)."""
    return _measure(table).minimum


def fit_table(table: Table, width: int) -> list[Table]:
    """The table, if it fits `width` as it is; else with the headings of its number columns
    stacked (_part compact), and if that is still too wide, in parts, each with the leading
    label columns (_labels) and as many of the others, in order, as fit (one at least),
    titled "(1/2)" ... A number is never cut."""
    if _fits(table, width):
        return [table]
    every = list(range(len(table.columns)))
    # rich draws a table as wide as its columns' minimums plus its frame (_frame_width): each
    # column is measured once, alone, instead of every candidate part
    columns = _column_widths(table)
    if _drawn_width(table, columns, every) <= width or len(every) < 2:
        return [_part(table, every, compact=True)]
    keys = every[:_labels(table)]
    groups = _groups(table, columns, keys, width)
    return [_part(table, keys + group, k, len(groups), compact=True) for k, group in enumerate(groups)]


def _column_widths(table: Table) -> list[int]:
    """The width of each column drawn alone and compact, without the frame (_frame_width)."""
    return [_column_width(_part(table, [index], compact=True)) - _frame_width(table, 1)
            for index in range(len(table.columns))]


def _fits(table: Table, width: int) -> bool:
    """The table as it is fits `width`: the cheap bound _widest first; where that bound is rich's
    own measure (_measured_exactly) it decides either way, else rich measures the table."""
    widest = _widest(table)
    if widest <= width or _measured_exactly(table):
        return widest <= width
    return _measure(table).maximum <= width


def _groups(table: Table, columns: list[int], keys: list[int], width: int) -> list[list[int]]:
    """The columns after the labels `keys`, in order, in groups that fit `width` beside them (one
    column at least each); `columns`: the width of each column alone."""
    groups: list[list[int]] = [[]]
    for index in range(len(keys), len(columns)):
        if groups[-1] and _drawn_width(table, columns, keys + groups[-1] + [index]) > width:
            groups.append([])
        groups[-1].append(index)
    return groups


def _drawn_width(table: Table, columns: list[int], indices: list[int]) -> int:
    """The width of the part of the table with the columns `indices` (widths `columns`) and its frame."""
    return sum(columns[c] for c in indices) + _frame_width(table, len(indices))


def _labels(table: Table) -> int:
    """Leading label columns that every part of a split table repeats: the first, and after it
    those that are left-justified or hold a text that is not a number (engine, support ...)."""
    count = 1
    for column in table.columns[1:-1]:
        if _is_number_column(column):
            break
        count += 1
    return count


def _is_number_column(column: Column) -> bool:
    """Not left-justified, and every cell that is not blank a number (or '-')."""
    return column.justify != "left" and all(_blank_or_number(_text(cell)) for cell in column.cells)


def _blank_or_number(text: str) -> bool:
    """A cell that is blank or a number (_NUMBER: '-', '12.5', '1e-3', '0.7%' ...)."""
    text = text.strip()
    return not text or _NUMBER.fullmatch(text) is not None


def _text(cell) -> str:
    return cell.plain if isinstance(cell, Text) else str(cell)


def _stacked_header(column: Column) -> str | Text:
    """A number column's heading in lines no wider than its widest cell (or its longest word; a
    unit in brackets, "[kN m]", is one word)."""
    header = column.header
    if not isinstance(header, str):
        return header
    words = _WORD.findall(Text.from_markup(header).plain)
    limit = max([_widest_cell(column), *(len(word) for word in words)])
    return Text("\n".join(_stack(words, limit)))


def _widest_cell(column: Column) -> int:
    """The length of the longest line of the column's cells (0 without cells)."""
    return max((len(line) for cell in column.cells for line in _text(cell).splitlines()), default=0)


def _stack(words: list[str], limit: int) -> list[str]:
    """The words in lines of at most `limit` characters (a longer word alone on its line)."""
    lines: list[str] = []
    for word in words:
        if lines and len(lines[-1]) + 1 + len(word) <= limit:
            lines[-1] += " " + word
        else:
            lines.append(word)
    return lines


def _part(table: Table, indices: list[int], number: int = 0, parts: int = 1, compact: bool = False) -> Table:
    """The table with the columns `indices`; compact: the number (right-justified) columns with
    their headings stacked to the width of their cells and never wrapped (_stacked_header)."""
    part = Table(title=_part_title(table.title, number, parts), caption=table.caption if number == parts - 1 else None,
                 box=table.box, show_header=table.show_header, show_lines=table.show_lines,
                 title_justify=table.title_justify, caption_justify=table.caption_justify, padding=table.padding)
    for index in indices:
        _copy_column(part, table.columns[index], compact)
    _copy_rows(part, [table.columns[index] for index in indices])
    return part


def _copy_rows(part: Table, columns: list[Column]) -> None:
    """Add to the part the rows of these columns."""
    for row in zip(*[list(column.cells) for column in columns], strict=True):
        part.add_row(*row)


def _part_title(title, number: int, parts: int):
    """The title of part `number` (from 0) of `parts`: with " (1/2)" ... when there are several."""
    if parts <= 1 or title is None:
        return title
    suffix = f" ({number + 1}/{parts})"
    return title + suffix if isinstance(title, str) else Text.assemble(title, suffix)


def _copy_column(part: Table, column: Column, compact: bool) -> None:
    """Add the column to the part; compact: a number column with its heading stacked, unwrapped."""
    number_column = compact and column.justify == "right"
    part.add_column(_stacked_header(column) if number_column else column.header, justify=column.justify,
                    no_wrap=column.no_wrap or number_column, overflow=column.overflow,
                    min_width=column.min_width, style=column.style, header_style=column.header_style)


def _column_width(part: Table) -> int:
    """The narrowest a one-column table is drawn: its minimum, or for a column that may not wrap
    (no_wrap: rich never narrows it below its widest line, though it measures it by its longest
    word) its maximum."""
    measured = _quick_measure(part) if _measured_exactly(part) else _measure(part)
    return measured.maximum if part.columns[0].no_wrap else measured.minimum


def _quick_measure(table: Table) -> Measurement:
    """What rich measures of a table that _measured_exactly, from the lengths of its texts: each
    text's longest word and longest line (rich.text.Text), its column's padding and frame."""
    _, right, _, left = table.padding
    padding = len(table.columns) * (left + right) + _frame_width(table, len(table.columns))
    return Measurement(padding + sum(_column_narrowest(column) for column in table.columns),
                       padding + sum(_column_widest(column) for column in table.columns))


def _column_narrowest(column: Column) -> int:
    """A column's minimum without its padding (_quick_measure): its longest word, at least its min_width."""
    if column.width is not None:
        return column.width
    return max(max(_longest_word(_shown(text)) for text in [column.header, *column.cells]), column.min_width or 0)


def _longest_word(text: str) -> int:
    """The longest word of a text; of a text without one (blank) its longest line, as rich measures it."""
    words = text.split()
    return max(cell_len(word) for word in words) if words else max((cell_len(line) for line in text.splitlines()),
                                                                    default=0)


def _widest(table: Table) -> float:
    """An upper bound of the table's natural width, from the lengths of its texts as given
    (markup and escapes only shorten them): most tables fit, and rich measures a table by
    rendering every cell. Infinite when a cell is not text."""
    _, right, _, left = table.padding
    total = _frame_width(table, len(table.columns)) + len(table.columns) * (left + right)
    return total + sum(_column_widest(column) for column in table.columns)


def _column_widest(column: Column) -> float:
    """The natural width of a column from the lengths of its texts (its width when it is set);
    infinite when a cell is not text."""
    texts = [column.header, *column.cells]
    if not all(isinstance(text, (str, Text)) for text in texts):
        return float("inf")
    if column.width is not None:
        return column.width
    return max(_longest_line(texts), column.min_width or 0)


def _longest_line(texts: list) -> int:
    """The cells of the longest line of the texts as drawn (_shown; an empty text: one empty line)."""
    return max(cell_len(line) for text in texts for line in (_shown(text).splitlines() or [""]))


def _shown(text) -> str:
    """The text rich draws: a string's markup rendered (tags dropped, escaped brackets as brackets)."""
    if not isinstance(text, str):
        return _text(text)
    return render_markup(text, emoji=False).plain if "[" in text else text


def _measured_exactly(table: Table) -> bool:
    """Whether _widest is what rich measures (its maximum), not only a bound above it: a table of
    its natural width, its header shown, every edge padded, no column with a maximum width, and
    every text a rich Text or a string drawn as _shown reads it (_plain)."""
    plain = table.width is None and table.show_header and table.pad_edge and not table.collapse_padding
    return plain and all(column.max_width is None and _plain_texts(column) for column in table.columns)


def _plain_texts(column: Column) -> bool:
    return all(isinstance(text, Text) or _plain(text) for text in [column.header, *column.cells])


def _plain(text) -> bool:
    """A string whose drawn text is _shown's: no tab and nothing printable() shows as an escape."""
    return isinstance(text, str) and "\t" not in text and printable(text, lines=True) == text


def _frame_width(table: Table, count: int) -> int:
    """Columns a table of `count` columns adds to its cells (padding included): its outer
    edges and the rules between the columns (as rich.table.Table lays it out)."""
    if table.box is None:
        return 0
    return (2 if table.show_edge else 0) + count - 1
