"""Measure of the layout (issue 10): follow one analysis from `analysis.run` to its result and
count how often the Python call chain returns to a source file of the package it had already
left (consecutive frames in one file merged; properties, dunder methods and comprehensions
are not stages; compiled C loops are invisible). Printed twice: every return, and with
the iterations of a loop counted once (a repeated cycle A -> B -> A -> B kept once).

Counting returns, any layered chain pays one per stage a module calls: analysis -> registry ->
engine -> {model, stepping, post-processing, result} -> registry -> analysis already returns 6
times. A second count is printed for comparison: the re-entries into a file by a call (a file
entered again from another one; coming back from a callee does not count), the back and forth
of data between modules.

    python benchmarks/walk.py [DECK] [--engine exact] [--support uplift]
"""

from __future__ import annotations

import argparse
import collections
import functools
import importlib
import inspect
import pkgutil
import sys
from pathlib import Path

import upliftcli
from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck

ROOT = str(Path(upliftcli.__file__).parent)


def not_stages() -> set:
    """Code objects of the package's properties: attribute reads, not stages."""
    skip = set()
    for info in pkgutil.walk_packages(upliftcli.__path__, "upliftcli."):
        if ".cli" in info.name:
            continue
        try:
            module = importlib.import_module(info.name)
        except ImportError:
            continue
        for _, cls in inspect.getmembers(module, inspect.isclass):
            for value in vars(cls).values():
                if isinstance(value, property) and value.fget:
                    skip.add(value.fget.__code__)
                if isinstance(value, functools.cached_property):
                    skip.add(value.func.__code__)
    return skip


def walk(deck) -> tuple[list[str], list[str]]:
    """The files of the package the call chain is in, in order (consecutive repeats merged),
    and the files entered by a call from another file, in order (consecutive repeats merged)."""
    skip, sequence, stack, entered = not_stages(), [], [], []

    def profile(frame, event, arg):
        if event not in ("call", "return"):
            return
        code = frame.f_code
        if not code.co_filename.startswith(ROOT):
            return
        if code in skip or (code.co_name.startswith("__") and code.co_name.endswith("__")):
            if event == "call":
                stack.append(stack[-1] if stack else None)
            elif stack:
                stack.pop()
            return
        if "<" in code.co_name and code.co_name != "<lambda>":
            return  # comprehensions and generator expressions
        if event == "call":
            if (not stack or stack[-1] != code.co_filename) and (not entered or entered[-1] != code.co_filename):
                entered.append(code.co_filename)
            stack.append(code.co_filename)
        elif stack:
            stack.pop()
        current = stack[-1] if stack else None
        if current and (not sequence or sequence[-1] != current):
            sequence.append(current)

    sys.setprofile(profile)
    try:
        analysis.run(deck)
    finally:
        sys.setprofile(None)
    return [path[len(ROOT) + 1:] for path in sequence], [path[len(ROOT) + 1:] for path in entered]


def loops_once(sequence: list[str]) -> list[str]:
    """The sequence with each run of a repeated cycle (up to 7 files long) kept once."""
    changed = True
    while changed:
        changed = False
        for width in range(1, 8):
            out, i = [], 0
            while i < len(sequence):
                block = sequence[i:i + width]
                j = i + width
                while len(block) == width and sequence[j:j + width] == block:
                    j += width
                    changed = True
                out.extend(block)
                i = j
            sequence = out
    return sequence


def returns(sequence: list[str]) -> int:
    return sum(count - 1 for count in collections.Counter(sequence).values())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("deck", nargs="?", default=str(Path(ROOT).parent / "inputs" / "ten_story_elcentro.toml"))
    parser.add_argument("--engine", default="exact")
    parser.add_argument("--support", default="uplift")
    args = parser.parse_args()
    deck = load_deck(args.deck, [f'analysis.engine="{args.engine}"', f'analysis.supports="{args.support}"'])
    analysis.run(deck)  # compiled code loaded, caches warm
    sequence, entered = walk(deck)
    once = loops_once(sequence)
    print(f"returns to a file already left: {returns(sequence)}; with loop iterations counted once: {returns(once)}")
    print(f"re-entries into a file by a call: {returns(entered)}; with loop iterations counted once: "
          f"{returns(loops_once(entered))}")
    for name, count in collections.Counter(once).most_common():
        if count > 1:
            print(f"  {name}: {count} visits")
    print(" -> ".join(once))


if __name__ == "__main__":
    main()
