"""Documented limits on the size of an analysis, checked before anything is allocated (see
docs/deck.md, "Limits", and docs/sweep.md).

Each limit is refused with an InputError naming the field (or option) that exceeds it, the
limit and the value. Pure functions of numbers, and a bounded file read; nothing here prints.
"""

from __future__ import annotations

import errno
import math
import os
import stat

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
#: levels of tables and arrays in a deck (its own need four: [ground_motion] suite = [{...}] with
#: a list of pairs); 1,000 levels passed the TOML parser and then broke the deck's own walks
MAX_NESTING = 32
#: bytes of a record file and samples of a record
MAX_RECORD_BYTES = 64 * 2**20
MAX_RECORD_SAMPLES = 1_000_000
#: record time step [s]
MAX_RECORD_DT = 10.0
#: response spectra: shortest period relative to the record step, T >= dt / MAX_DT_OVER_PERIOD
#: (sub-steps of T/4 inside a record step), and sub-steps of one oscillator over the record
MAX_DT_OVER_PERIOD = 2_500
MAX_SPECTRUM_STEPS = 100_000_000
#: record selection: sub-steps of the candidates' spectra at a suite's check periods, all candidates
#: together (`record select` ranks a pool, not a suite). Measured: the FEMA P695 near-field set,
#: 56 records at 347 periods from 0.2 s, 152 million sub-steps in 2 s compiled, 39 s with the numpy
#: twins (about 250 ns each); 400 million keep a pool to about 1.7 minutes without the compiled loops
MAX_SELECTION_WORK = 400_000_000
#: exact and approximate engines: internal steps x (state size + 2) of one analysis, a bound
#: on its run time (the memory is bounded anyway: the post-processing streams); measured 52
#: million steps x states, fifty stories, in 20 s on this project's 2-core machine
MAX_STEP_STATES = 50_000_000
#: exact and approximate engines: internal steps of one run, whatever the state size. The peak
#: search between samples works on every interval that ends at a contact transition, and a mat
#: that chatters (a stiff, almost undamped foundation) makes that every step: measured 11 us a
#: step for ten stories (`--set foundation.frequency_ratio=1000 --set foundation.c_f=1e-12` on
#: the El Centro deck: 374,160 steps of a 0.5 ms vertical period, 4 s a run, 11 s with the
#: step refinement that cannot help it); 250,000 steps keep such a run to about 3 s. The example
#: decks take 3,118 steps; a 0.1 s building on a foundation 100 times stiffer (w_v/w_1 = 100)
#: under El Centro 187,000
MAX_STEPS = 250_000
#: exact and approximate engines: internal steps x (state size + 2)^2 of one run. The stepping
#: (a matrix of the state size a step) and the post-processing (every response of every story
#: from the state at every step: responses grow with the states) cost the square of the state
#: size a step, which MAX_STEP_STATES does not see for a tall building: measured 500 stories
#: (1,008 states) under El Centro, 4,677 steps: 4.8e9, 19 s of CPU (11 s peak search, 7 s
#: matrix exponentials, 3 s stepping); ten times that record (4.8e7 steps x states, within
#: MAX_STEP_STATES) would have run for minutes
MAX_STEP_STATES_SQUARED = 5_000_000_000
#: exact and approximate engines: memory of the step operators of the distinct contact states one run
#: meets [bytes] (13 matrices of the state size each: 450 kB on a 20-element Winkler mat with a bearing
#: capacity, 570 kB on 31). An elastic mat meets tens of states and a yielding one hundreds (441 for the
#: 20-element mat of benchmarks/bench_yielding.py, FS_v = 1.5); a yielding mat that chatters meets
#: thousands, each built in about 1 ms and kept: 3,368 states, 1.9 GB and 53 s of one run on the
#: Winkler deck with 31 elements, k_w = 6e12 N/m^2 and no damping. 1 GiB stops that run after
#: 1,885 states, in 16 s (about what MAX_STEP_STATES intends)
MAX_OPERATOR_BYTES = 2**30
#: response spectra of one command (`record spectrum`, `record info`): periods, and oscillator
#: sub-steps over all periods and dampings (about 150 ns each: 100 million take about 15 s)
MAX_SPECTRUM_PERIODS = 10_000
MAX_SPECTRUM_WORK = 100_000_000
#: exact engine: contact elements of a foundation (one bit each in a 64-bit contact pattern)
MAX_CONTACT_ELEMENTS = 62
#: exact engine: contact elements with a bearing capacity (two bits each: lifted, yielding)
MAX_YIELDING_ELEMENTS = 31
#: exact engine: bits of the 64-bit contact pattern (the compiled loop's event rows): one per contact
#: element, two per element with a bearing capacity and two per yielding story (docs/theory.md 15.2)
MAX_PATTERN_BITS = 62


def too_many_bits(element_bits: int, yielding_stories: int) -> str:
    """Why a contact pattern of element_bits for the foundation and two per yielding story does not fit
    MAX_PATTERN_BITS, naming the field to change (the stories' alone: building.story_strengths)."""
    total = element_bits + 2 * yielding_stories
    field = "building.story_strengths" if 2 * yielding_stories > MAX_PATTERN_BITS else "foundation.elements"
    return (f"the exact engine's contact pattern holds {MAX_PATTERN_BITS} bits: one per contact element, two per "
            f"element with a bearing capacity and two per yielding story, here {total}: lower {field}")
#: record suites: records generated, and samples generated or matched in all (the spectral
#: iteration costs about 0.2 ms per sample: 500,000 samples take about 100 s on 2 cores)
MAX_SUITE_RECORDS = 1_000
MAX_SUITE_SAMPLES = 500_000
#: seeds of `record generate` (numpy's SeedSequence takes non-negative integers)
MAX_SEED = 2**63 - 1
#: sweeps: values of one --vary range and cases of a plan
MAX_VARY_VALUES = 10_000
MAX_CASES = 100_000
#: sweeps: local worker processes beyond the cores (only with --oversubscribe)
MAX_WORKERS = 256


def too_deeply_nested(value, limit: int = MAX_NESTING) -> bool:
    """A parsed deck (or value) with tables or arrays nested more than `limit` levels deep,
    walked level by level (no recursion, whatever the depth)."""
    level = [value]
    for _ in range(limit + 1):
        level = [child for item in level for child in _members(item)]
        if not level:
            return False
    return True


def _members(item) -> list:
    """The values of a table, the items of an array; none of anything else."""
    if isinstance(item, dict):
        return list(item.values())
    return list(item) if isinstance(item, (list, tuple)) else []


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


def spectrum_work(periods, dampings: int, dt: float, samples: int) -> int:
    """Oscillator sub-steps of a response spectrum: samples x sub-steps per record step
    (max(1, ceil(4 dt / T)), as spectra.substeps) summed over the periods, times the dampings."""
    steps = sum(max(1, math.ceil(4.0 * dt / float(t) - 1e-9)) if float(t) > 0.0 else 1 for t in periods)
    return steps * max(samples, 1) * max(int(dampings), 1)


def spectrum_work_problem(periods, dampings: int, dt: float, samples: int) -> str | None:
    """The words of the spectrum limits (MAX_SPECTRUM_PERIODS, MAX_SPECTRUM_WORK) if exceeded."""
    count = len(periods)
    if count > MAX_SPECTRUM_PERIODS:
        return f"at most {MAX_SPECTRUM_PERIODS:,} periods (limit of the tool), got {count:,}"
    work = spectrum_work(periods, dampings, dt, samples)
    if work <= MAX_SPECTRUM_WORK:
        return None
    return (f"at most {MAX_SPECTRUM_WORK:,} oscillator sub-steps (about 15 s), got {work:,} ({count:,} periods x "
            f"{int(dampings)} dampings x {samples:,} samples, sub-steps of T/4 below 4 dt = {4 * dt:g} s): "
            "fewer periods, fewer dampings or a shorter --window")


def suite_samples_problem(counts, what: str) -> str | None:
    """The words of the record-suite limits if the records (their samples each, `counts`) exceed
    them: MAX_SUITE_RECORDS records, MAX_RECORD_SAMPLES samples each (a record the tool can read
    back), MAX_SUITE_SAMPLES samples in all. what: the records, in words ('records of 2,001 samples')."""
    counts = list(counts)
    if len(counts) > MAX_SUITE_RECORDS:
        return f"at most {MAX_SUITE_RECORDS:,} records (limit of the tool), got {len(counts):,}"
    longest = max(counts, default=0)
    if longest > MAX_RECORD_SAMPLES:
        return f"records of at most {MAX_RECORD_SAMPLES:,} samples (limit of the tool), got {what}"
    total = sum(counts)
    if total > MAX_SUITE_SAMPLES:
        return (f"at most {MAX_SUITE_SAMPLES:,} samples in all (limit of the tool: about 100 s of spectral "
                f"iteration), got {total:,} ({what})")
    return None


def step_states_problem(steps: int, states: int) -> str | None:
    """The words of the exact engine's run-time limit if steps x (states + 2) exceeds it."""
    product = steps * (states + 2)
    if product <= MAX_STEP_STATES:
        return None
    return (f"at most {MAX_STEP_STATES:,} internal steps x states (about 20 s of stepping on 2 cores), got "
            f"{steps:,} steps x {states + 2} = {product:,}")


def steps_problem(steps: int, states: int) -> str | None:
    """The words of the exact engine's limits on one run if exceeded: its internal steps
    (MAX_STEPS), and steps x (states + 2)^2 (MAX_STEP_STATES_SQUARED)."""
    if steps > MAX_STEPS:
        return (f"at most {MAX_STEPS:,} internal steps of one run (about 3 s of peak search when the mat chatters "
                f"at every step), got {steps:,}")
    product = steps * (states + 2) ** 2
    if product > MAX_STEP_STATES_SQUARED:
        return (f"at most {MAX_STEP_STATES_SQUARED:,} internal steps x states^2 of one run (about 20 s on 2 cores), "
                f"got {steps:,} steps x {states + 2}^2 = {product:,}")
    return None


def cases_problem(counts, per_combination: int) -> str | None:
    """The words of the case limit if the product of the --vary counts x engines x supports
    exceeds MAX_CASES (computed without expanding)."""
    total = math.prod(counts) * per_combination
    if total <= MAX_CASES:
        return None
    return f"at most {MAX_CASES:,} cases, got {total:,} ({' x '.join(str(c) for c in counts)} x {per_combination})"


class NotRegularFile(ValueError):
    """An input path that is not a regular file (a FIFO, a device, a socket): never opened."""


def read_limited(path, limit: int) -> bytes:
    """The bytes of a regular file, refusing (ValueError with the limit in words) a file longer
    than `limit` bytes before reading more than that. A path that is not a regular file (a FIFO
    would block the reader for ever, a device such as /dev/zero never ends) is refused from
    os.stat, before it is opened (NotRegularFile)."""
    _regular(os.stat(path).st_mode, path)
    with open(path, "rb", opener=_nonblocking) as handle:  # a FIFO put in its place meanwhile does not block
        _regular(os.fstat(handle.fileno()).st_mode, path)
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise ValueError(f"at most {limit / 2**20:g} MiB (limit of the tool)")
    return data


#: what a file that is not a regular file or a directory is, by the test of its mode
_KINDS = ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a device"), (stat.S_ISBLK, "a device"),
          (stat.S_ISSOCK, "a socket"))


def _regular(mode: int, path) -> None:
    """NotRegularFile naming what `path` is unless its mode is a regular file's (a directory:
    IsADirectoryError, as open() raises it)."""
    if stat.S_ISREG(mode):
        return
    if stat.S_ISDIR(mode):
        raise IsADirectoryError(errno.EISDIR, "Is a directory", str(path))
    raise NotRegularFile(next((name for test, name in _KINDS if test(mode)), "not a file"))


def _nonblocking(path, flags: int) -> int:
    """os.open for read_limited: O_NONBLOCK, so that opening a FIFO swapped in after os.stat
    returns at once (reads of a regular file are not affected by the flag)."""
    return os.open(path, flags | getattr(os, "O_NONBLOCK", 0))


def read_input(path, limit: int, source: str, location: str | None, what: str) -> bytes:
    """The bytes of an input file (a deck, a record, a spectrum table) read with read_limited;
    InputError(source, location, ...) naming `what` was expected if it is missing, a
    directory, unreadable or longer than `limit` bytes."""
    from ..errors import InputError

    try:
        return read_limited(path, limit)
    except FileNotFoundError:
        raise InputError(source, location, f"an existing {what} (file not found)") from None
    except IsADirectoryError:
        raise InputError(source, location, f"a {what} (this is a directory)") from None
    except NotRegularFile as error:
        raise InputError(source, location, f"a regular {what} (this is {error})") from None
    except OSError as error:
        raise InputError(source, location, f"a readable {what} ({error.strerror or error})") from None
    except ValueError as error:
        raise InputError(source, location, f"a {what} of {error}") from None
