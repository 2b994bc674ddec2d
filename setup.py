"""The compiled loops (C, built at install: gcc or any C99 compiler; docs/exact-engine.md,
"Compiled loops"). Everything else about the package is in pyproject.toml."""

from setuptools import Extension, setup

# -ffp-contract=off: no fused multiply-adds, so a result does not depend on the machine's
# instruction set (the numpy twins in the tests compare to round-off)
FLAGS = ["-O3", "-std=c99", "-ffp-contract=off", "-fno-math-errno"]


def module(name: str, source: str, depends: tuple[str, ...] = ()) -> Extension:
    return Extension(name, [source], include_dirs=["upliftcli/compiled"], extra_compile_args=FLAGS,
                     depends=["upliftcli/compiled/buffers.h", "upliftcli/compiled/product.h", *depends])


setup(ext_modules=[
    module("upliftcli.engines.exact._stepping", "upliftcli/engines/exact/_stepping.c",
           ("upliftcli/engines/exact/events.h",)),
    module("upliftcli.engines.exact._signals", "upliftcli/engines/exact/_signals.c"),
    module("upliftcli.engines.exact._peaks", "upliftcli/engines/exact/_peaks.c"),
    module("upliftcli.engines.exact._contact", "upliftcli/engines/exact/_contact.c"),
    module("upliftcli.engines.exact._energy", "upliftcli/engines/exact/_energy.c"),
    module("upliftcli.motion._spectra", "upliftcli/motion/_spectra.c", ("upliftcli/motion/turning_points.h",)),
])
