"""The page frame of the HTML report (letterhead, title block, contents around the sections) as
a Jinja2 template: templates/page.html by default, or a firm's own (`uplift report --template
FILE`, docs/report.md). Every value a template prints is HTML-escaped unless it is markup
already (the styles, the title block, the sections); an undefined name is an error.

A template that does not parse or render is an InputError naming the file and its line."""

from __future__ import annotations

import traceback
from html import escape
from pathlib import Path

from ..errors import InputError

#: the report's own page frame
DEFAULT = Path(__file__).resolve().parent / "templates" / "page.html"
#: the option that names a template
OPTION = "--template"


def _finalize(value):
    """A printed value HTML-escaped (as html.escape does) unless it is markup already."""
    from markupsafe import Markup

    return value if isinstance(value, Markup) else escape(str(value))


def load(path: Path | None = None):
    """The jinja2.Template of `path` (default: DEFAULT); `{% include %}` and `{% extends %}` are
    read next to it. InputError (OPTION, the file, its line) when it cannot be read or parsed."""
    import jinja2

    path = Path(path or DEFAULT)
    environment = jinja2.Environment(loader=jinja2.FileSystemLoader(str(path.parent)), autoescape=False,
                                     finalize=_finalize, undefined=jinja2.StrictUndefined, keep_trailing_newline=True)
    try:
        return environment.get_template(path.name)
    except jinja2.TemplateNotFound as error:
        raise InputError(OPTION, str(path), f"a readable Jinja2 template file (not found: {error.name})") from None
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(OPTION, str(path), f"a readable Jinja2 template file in UTF-8 ({error})") from None
    except jinja2.TemplateError as error:
        raise template_error(path, error) from None


def template_error(path: Path, error: Exception) -> InputError:
    """One line naming the template file, the line where it failed (when known) and why."""
    line = error_line(path, error)
    where = f"line {line}" if line else None
    return InputError(f"{OPTION} {path}", where, f"a Jinja2 template ({type(error).__name__}: {error})")


def error_line(path: Path, error: Exception) -> int | None:
    """The line of the template where a Jinja2 error arose: the error's own (a syntax error),
    else the last frame of the template in its traceback (an undefined name while rendering)."""
    if getattr(error, "lineno", None):
        return error.lineno
    frames = [frame.lineno for frame in traceback.extract_tb(error.__traceback__) if _same_file(frame.filename, path)]
    return frames[-1] if frames else None


def _same_file(name: str, path: Path) -> bool:
    """Whether a traceback's file name is the template's."""
    return Path(name).resolve() == path.resolve() if name and not name.startswith("<") else False


def render_page(template, context: dict, path: Path | None = None) -> str:
    """The template rendered with `context`; InputError naming the file and the line when it fails."""
    import jinja2

    try:
        return template.render(**context)
    except (jinja2.TemplateError, TypeError, ValueError, AttributeError, KeyError) as error:
        raise template_error(Path(path or DEFAULT), error) from None
