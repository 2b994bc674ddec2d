"""The compiled loops (C, built at install where a C compiler works; docs/exact-engine.md,
"Compiled loops"). Without a working compiler the package installs without them and runs their
numpy twins (upliftcli/runtime/backend.py). And the example decks and records, copied into the
built package (BuildWithExamples). Everything else about the package is in pyproject.toml."""

import importlib.machinery
import os
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.bdist_wheel import bdist_wheel
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py
from setuptools.errors import CCompilerError, CompileError, ExecError, LinkError, PlatformError

# No fused multiply-adds, so a result does not depend on the machine's instruction set (the
# numpy twins agree to round-off): -ffp-contract=off for GCC and Clang; MSVC's /fp:precise does
# not contract (it would with /fp:contract).
FLAGS = {
    "unix": ["-O3", "-std=c99", "-ffp-contract=off", "-fno-math-errno"],
    "mingw32": ["-O3", "-std=c99", "-ffp-contract=off", "-fno-math-errno"],
    "msvc": ["/O2", "/fp:precise"],
}
#: the stable ABI the loops are built against (Python 3.11's limited API, which has the buffer
#: protocol they read arrays with): one wheel per platform serves every CPython from 3.11 on
LIMITED_API = "0x030B0000"
#: the repository's root (the example decks and records are in its inputs/ and records/)
ROOT = os.path.dirname(os.path.abspath(__file__))
#: what a failed build costs, said once
WITHOUT = ("uplift: the compiled loops were not built ({reason}); installed without them: their numpy twins run "
           "instead, with the same results to round-off in 1.5-6x the time (the README analysis 1.5x, an exact "
           "spectrum sweep 3.4x, the spectra of long records 6x). A C compiler and a reinstall build them.")


class OptionalBuildExt(build_ext):
    """build_ext with compiler flags chosen per compiler, where a compiler that fails (or is
    missing) leaves the package without its extensions, saying so in one line."""

    def run(self) -> None:
        try:
            super().run()
        except (CCompilerError, ExecError, PlatformError, OSError) as error:
            self.without(last_line(error))

    def build_extensions(self) -> None:
        flags = FLAGS.get(self.compiler.compiler_type, [])
        for extension in self.extensions:
            extension.extra_compile_args = flags
        failed = []
        for extension in self.extensions:
            try:
                self.build_extension(extension)
            except (CCompilerError, CompileError, LinkError, ExecError, PlatformError, OSError) as error:
                failed.append((extension.name, error))
        if failed:
            names = ", ".join(name.rsplit(".", 1)[1] for name, _ in failed)
            self.without(f"{names}: {self.reason(failed[0][1])}")

    def copy_extensions_to_source(self) -> None:
        """An in-place build (pip install -e .) also removes an earlier build's module beside each
        new one (`_stepping.cpython-311-x86_64-linux-gnu.so` beside `_stepping.abi3.so`), which
        Python would import first."""
        super().copy_extensions_to_source()
        build_py = self.get_finalized_command("build_py")
        for extension in self.extensions:
            package, _, stem = extension.name.rpartition(".")
            built = Path(build_py.get_package_dir(package)) / Path(self.get_ext_filename(extension.name)).name
            for suffix in importlib.machinery.EXTENSION_SUFFIXES if built.is_file() else ():
                old = built.with_name(stem + suffix)
                if old != built and old.is_file():
                    old.unlink()

    def reason(self, error: Exception) -> str:
        """Why a build failed, in a few words: a compiler's command line is too long for that (a
        compiler that ran has printed its messages above)."""
        text = last_line(error)
        if isinstance(error, (CompileError, LinkError)) and len(text) > 100:
            program = getattr(self.compiler, "compiler_so", None) or ["the C compiler"]
            return f"{program[0]} failed"
        return text

    def without(self, reason: str) -> None:
        print(WITHOUT.format(reason=reason), flush=True)


def last_line(error: Exception) -> str:
    """The last line of an error's text (a compiler's own message ends it), at most 200 characters."""
    lines = str(error).strip().splitlines() or [type(error).__name__]
    return lines[-1][:200]


class StableWheel(bdist_wheel):
    """A wheel for every CPython from LIMITED_API on (cp311-abi3-<platform>); where no extension
    was built (OptionalBuildExt went without them), a pure one (py3-none-any): the numpy twins
    run on any platform, and a wheel tagged for one would claim compiled loops it has not."""

    def run(self) -> None:
        self.run_command("build_ext")
        build = self.get_finalized_command("build_ext")
        if not any(os.path.exists(path) for path in build.get_outputs()):
            self.distribution.ext_modules = []  # the files go to the wheel's root, build_ext is not run again
            self.root_is_pure, self.py_limited_api = True, False
        super().run()


class BuildWithExamples(build_py):
    """build_py, and the example decks and records copied into the built package as
    upliftcli/examples/ (inputs/*.toml and every file under records/, in the repository's layout),
    where `uplift examples DIR` finds them in a wheel (upliftcli/runtime/examples.py). The
    repository keeps its one copy at its root, where the tests, docs and README use them (and
    MANIFEST.in puts them in the sdist); an editable install reads them there."""

    def run(self) -> None:
        super().run()
        if self.editable_mode:
            return
        for name in example_files():
            target = os.path.join(self.build_lib, "upliftcli", "examples", name)
            self.mkpath(os.path.dirname(target))
            self.copy_file(os.path.join(ROOT, name), target)


def example_files() -> list[str]:
    """The files `uplift examples` writes, relative to the repository's root: inputs/*.toml, then
    every file under records/ (upliftcli/runtime/examples.bundled_files lists the same)."""
    root = Path(ROOT)
    decks = sorted(root.glob("inputs/*.toml"))
    records = sorted(path for path in root.glob("records/**/*") if path.is_file())
    return [path.relative_to(root).as_posix() for path in (*decks, *records)]


def module(name: str, source: str, depends: tuple[str, ...] = ()) -> Extension:
    return Extension(name, [source], include_dirs=["upliftcli/compiled"], optional=True, py_limited_api=True,
                     define_macros=[("Py_LIMITED_API", LIMITED_API)],
                     depends=["upliftcli/compiled/buffers.h", "upliftcli/compiled/product.h", *depends])


setup(cmdclass={"build_ext": OptionalBuildExt, "bdist_wheel": StableWheel, "build_py": BuildWithExamples},
      options={"bdist_wheel": {"py_limited_api": "cp311"}}, ext_modules=[
    module("upliftcli.engines.exact._stepping", "upliftcli/engines/exact/_stepping.c",
           ("upliftcli/engines/exact/events.h", "upliftcli/engines/exact/transitions.h",
            "upliftcli/engines/exact/levels.h", "upliftcli/engines/exact/builds.h")),
    module("upliftcli.engines.exact._signals", "upliftcli/engines/exact/_signals.c",
           ("upliftcli/engines/exact/derivatives.h",)),
    module("upliftcli.engines.exact._peaks", "upliftcli/engines/exact/_peaks.c",
           ("upliftcli/engines/exact/response_lanes.h", "upliftcli/engines/exact/peak_products.h")),
    module("upliftcli.engines.exact._contact", "upliftcli/engines/exact/_contact.c"),
    module("upliftcli.engines.exact._energy", "upliftcli/engines/exact/_energy.c"),
    module("upliftcli.engines.exact._levels", "upliftcli/engines/exact/_levels.c",
           ("upliftcli/engines/exact/levels.h",)),
    module("upliftcli.engines.exact._soil_states", "upliftcli/engines/exact/_soil_states.c"),
    module("upliftcli.engines.exact._soil_operators", "upliftcli/engines/exact/_soil_operators.c",
           ("upliftcli/engines/exact/pade.h",)),
    module("upliftcli.motion._spectra", "upliftcli/motion/_spectra.c", ("upliftcli/motion/turning_points.h",)),
])
