"""Documented limits on the size of an analysis, checked before anything is allocated (see
docs/deck.md, "Limits", and docs/sweep.md).

Each limit is refused with an InputError naming the field (or option) that exceeds it, the
limit and the value. Pure functions of numbers, and a bounded file read; nothing here prints.
"""

from __future__ import annotations

import math

#: number magnitudes accepted in any numeric field: 0 where the field allows it, otherwise
#: MIN_MAGNITUDE <= |value| <= MAX_MAGNITUDE (squares and cubes of the physical quantities
#: derived from them stay finite in double precision)
MAX_MAGNITUDE = 1e30
MIN_MAGNITUDE = 1e-30
#: largest value of an integer field (stories have their own limit)
MAX_INTEGER = 1_000_000
#: stories of a building (dense N x N eigenproblem)
MAX_STORIES = 500
#: bytes of a deck file
MAX_DECK_BYTES = 16 * 2**20
#: bytes of a record file and samples of a record
MAX_RECORD_BYTES = 64 * 2**20
MAX_RECORD_SAMPLES = 1_000_000
#: record time step [s]
MAX_RECORD_DT = 10.0
#: response spectra: shortest period relative to the record step, T >= dt / MAX_DT_OVER_PERIOD
#: (sub-steps of T/4 inside a record step), and sub-steps of one oscillator over the record
MAX_DT_OVER_PERIOD = 2_500
MAX_SPECTRUM_STEPS = 100_000_000
#: exact and approximate engines: internal steps x (state size + 2) of one analysis, a bound
#: on its run time (the memory is bounded anyway: the post-processing streams); measured 52
#: million steps x states, fifty stories, in 20 s on this project's 2-core machine
MAX_STEP_STATES = 50_000_000
#: sweeps: values of one --vary range and cases of a plan
MAX_VARY_VALUES = 10_000
MAX_CASES = 100_000


def shortest_period(dt: float, samples: int) -> float:
    """Shortest non-zero period [s] whose response spectrum ordinate may be computed for a
    record of `samples` samples at step dt [s] (MAX_DT_OVER_PERIOD, MAX_SPECTRUM_STEPS)."""
    per_step = 4.0 * dt * max(samples - 1, 1) / MAX_SPECTRUM_STEPS
    return max(dt / MAX_DT_OVER_PERIOD, per_step)


def period_problem(periods, dt: float, samples: int) -> str | None:
    """The words of the expectation a period violates (None if all are fine): every T is 0
    or at least shortest_period(dt, samples)."""
    limit = shortest_period(dt, samples)
    short = [float(t) for t in periods if 0.0 < float(t) < limit]
    if not short:
        return None
    return (f"periods of at least {limit:.3g} s or 0 (limit for the record's dt = {dt:g} s and "
            f"{samples:,} samples: T >= dt/{MAX_DT_OVER_PERIOD:,}), got {min(short):.3g} s")


def step_states_problem(steps: int, states: int) -> str | None:
    """The words of the exact engine's run-time limit if steps x (states + 2) exceeds it."""
    product = steps * (states + 2)
    if product <= MAX_STEP_STATES:
        return None
    return (f"at most {MAX_STEP_STATES:,} internal steps x states (about 20 s of stepping on 2 cores), got "
            f"{steps:,} steps x {states + 2} = {product:,}")


def cases_problem(counts, per_combination: int) -> str | None:
    """The words of the case limit if the product of the --vary counts x engines x supports
    exceeds MAX_CASES (computed without expanding)."""
    total = math.prod(counts) * per_combination
    if total <= MAX_CASES:
        return None
    return f"at most {MAX_CASES:,} cases, got {total:,} ({' x '.join(str(c) for c in counts)} x {per_combination})"


def read_limited(path, limit: int) -> bytes:
    """The bytes of a file, refusing (ValueError with the limit in words) a file longer than
    `limit` bytes before reading more than that (a device such as /dev/zero included)."""
    with open(path, "rb") as handle:
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise ValueError(f"at most {limit / 2**20:g} MiB (limit of the tool)")
    return data


def read_input(path, limit: int, source: str, location: str | None, what: str) -> bytes:
    """The bytes of an input file (a deck, a record, a spectrum table) read with read_limited;
    InputError(source, location, ...) naming `what` was expected if it is missing, a
    directory, unreadable or longer than `limit` bytes."""
    from .errors import InputError

    try:
        return read_limited(path, limit)
    except FileNotFoundError:
        raise InputError(source, location, f"an existing {what} (file not found)") from None
    except IsADirectoryError:
        raise InputError(source, location, f"a {what} (this is a directory)") from None
    except OSError as error:
        raise InputError(source, location, f"a readable {what} ({error.strerror or error})") from None
    except ValueError as error:
        raise InputError(source, location, f"a {what} of {error}") from None
