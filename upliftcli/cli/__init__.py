"""The `uplift` command: a typer app assembled from the command modules in this package.

The commands are split by group (analyze/modes, record, sweep/spectra) because one
module holding all of them would pass 400 lines; nothing but CLI code lives here.
Each command module exposes `register(app)`; COMMANDS names the module of each command and a
module that is not present (yet) is skipped. A command line registers only the module of its
command (`uplift modes DECK` imports neither the record nor the sweep commands, and typer builds
the options of its own commands only); `uplift --help` and anything else registers them all, as
does `app` when it is first read from this module (tests drive it with typer's CliRunner).

Exit codes: 0 ok, 2 bad input (errors.InputError: one line on stderr, no traceback),
3 an acceptance criterion of the deck is violated, 4 analysis failure (errors.AnalysisError).
"""

from __future__ import annotations

import importlib
import sys
import warnings

import typer
from typer.core import TyperGroup

from ..errors import AnalysisError, InputError, lines, one_line
from ..runtime.process import exit_now, exit_on_stop_signals, keep_freed_memory
from . import stdout

EXIT_OK, EXIT_INPUT, EXIT_CRITERIA, EXIT_ANALYSIS = 0, 2, 3, 4

#: each command (the first word after `uplift`) -> the module of this package that registers it
COMMANDS = {"analyze": "analyze", "modes": "modes", "record": "record", "sweep": "sweep", "spectra": "sweep",
            "report": "report", "examples": "examples"}
#: command modules, registered in this order if present
COMMAND_MODULES = tuple(dict.fromkeys(COMMANDS.values()))


class UpliftGroup(TyperGroup):
    """Top-level group: turns InputError / AnalysisError from any command into one line + exit code."""

    def invoke(self, ctx):
        try:
            with warnings.catch_warnings():  # numpy's RuntimeWarnings never reach the user (the results are checked)
                warnings.simplefilter("ignore", RuntimeWarning)
                return super().invoke(ctx)
        except USAGE_ERROR as error:  # a bad option value: one line naming the option, not a usage box
            if type(error).__name__ == "NoArgsIsHelpError":
                raise
            stdout.echo(f"error: {usage_line(error)}", err=True)
            raise typer.Exit(EXIT_INPUT) from None
        except (InputError, AnalysisError) as error:
            raise typer.Exit(echo_error(error)) from None


def echo_error(error: InputError | AnalysisError) -> int:
    """An InputError as 'error: ...' lines, an AnalysisError as 'analysis failed: ...', on stderr; the exit code."""
    if isinstance(error, AnalysisError):
        stdout.echo(f"analysis failed: {error}", err=True)
        return EXIT_ANALYSIS
    for line in lines(error):
        stdout.echo(f"error: {line}", err=True)
    return EXIT_INPUT


#: click's UsageError as typer ships it (the base of typer.BadParameter)
USAGE_ERROR = next(cls for cls in typer.BadParameter.__mro__ if cls.__name__ == "UsageError")


def usage_line(error: Exception) -> str:
    """'--format: 'xml' is not one of 'table', 'json'.' for click's error of a command-line value."""
    if type(error).__name__ == "MissingParameter":
        return one_line(error.format_message())
    message = error.message.removeprefix("Value error, ").strip()
    param = getattr(error, "param", None)
    if param is None:
        return one_line(message)
    return one_line(f"{_param_name(param)}: {message}")


def _param_name(param) -> str:
    """An option's first long name (--format; else its first name), an argument's name (DECK)."""
    if param.param_type_name != "option":
        return param.human_readable_name
    names = [name for name in param.opts if name.startswith("--")] or param.opts or [param.name or ""]
    return names[0]


_app = typer.Typer(
    cls=UpliftGroup,
    name="uplift",
    help="Earthquake response of multistory buildings whose foundation mat may lift off (Yim & Chopra).",
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_show_locals=False,
    context_settings={"help_option_names": ["-h", "--help"]},
    rich_markup_mode=None,  # help texts are plain: units such as [s] and [m/s^2] are kept, not read as markup
)


def _version(value: bool) -> None:
    if value:
        from ..runtime.backend import describe
        from ..runtime.installed import DISTRIBUTION, TOOL, package_version

        found, loops = package_version(DISTRIBUTION), describe()
        stdout.echo(f"{TOOL} (not installed)" if found == "not installed" else found)
        stdout.echo(loops)
        raise typer.Exit()


@_app.callback()
def _root(
    show_version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                      help="Print the version and the loops in use (compiled or numpy) and exit."),
) -> None:
    """Earthquake response of multistory buildings with foundation-mat uplift.

    Exit codes: 0 ok, 2 bad input, 3 acceptance criterion violated, 4 analysis failure.
    """


#: the command modules registered on _app so far
_registered: set[str] = set()


def register(names: tuple[str, ...] = COMMAND_MODULES) -> typer.Typer:
    """Register the command modules named (all by default) that are not registered yet, in
    COMMAND_MODULES' order; the app."""
    for name in COMMAND_MODULES:
        if name in names and name not in _registered:
            _registered.add(name)
            _register_module(name)
    resolve_annotations(_app)
    return _app


def resolve_annotations(typer_app: typer.Typer) -> None:
    """Each command's annotations as objects: typer reads them four times per command (its
    parameters and its callback, each by inspect.signature(eval_str=True) and get_type_hints), and
    under `from __future__ import annotations` each is a string compiled anew every time; resolved
    once here, to the same objects."""
    for info in typer_app.registered_commands:
        _resolve(info.callback)
    for group in typer_app.registered_groups:
        resolve_annotations(group.typer_instance)


def _resolve(function) -> None:
    """A function's string annotations evaluated in its module, as inspect.signature(eval_str=True)
    does; the same text of the same module is evaluated once (`Path | None`, `list[str]` ...)."""
    if function is not None:
        namespace = function.__globals__
        function.__annotations__ = {name: _evaluated(value, namespace)
                                    for name, value in function.__annotations__.items()}


#: (annotation text, id of its module's namespace) -> its value
_EVALUATED: dict[tuple[str, int], object] = {}


def _evaluated(value, namespace: dict):
    if not isinstance(value, str):
        return value
    key = (value, id(namespace))
    if key not in _EVALUATED:
        _EVALUATED[key] = eval(value, namespace)  # an annotation of this package, as inspect evaluates it
    return _EVALUATED[key]


def _register_module(name: str) -> None:
    module_name = f"{__name__}.{name}"
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as error:
        if error.name == module_name:
            return  # not written yet
        raise
    module.register(_app)


def needed_modules(args: list[str]) -> tuple[str, ...]:
    """The command modules a command line needs: its command's (its first word that is not an
    option), none for `--version` alone, else all of them (the top-level help lists every command)."""
    word = next((arg for arg in args if not arg.startswith("-")), None)
    if word in COMMANDS:
        return (COMMANDS[word],)
    if word is None and args and set(args) == {"--version"}:
        return ()
    return COMMAND_MODULES


def __getattr__(name: str):
    """`app`, the typer app with every command registered (PEP 562: read on first use)."""
    if name == "app":
        return register()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def main() -> None:
    """Run the command line in sys.argv; ends with SystemExit (the exit code)."""
    keep_freed_memory()
    exit_on_stop_signals()
    warnings.showwarning = stdout.show_warning  # a library's warning made safe too
    try:
        register(needed_modules(sys.argv[1:]))()
    except (InputError, AnalysisError) as error:  # raised outside a command (e.g. while parsing)
        raise SystemExit(echo_error(error)) from None


def console() -> None:
    """Console-script entry point (`uplift`): main(), then the process ends at once
    (process.exit_now) instead of tearing the interpreter down."""
    try:
        main()
    except SystemExit as end:
        exit_now(end.code)
    exit_now(0)
