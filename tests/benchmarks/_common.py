"""Shared timing helpers for the benchmarks (not collected by pytest)."""

from __future__ import annotations

import os
import platform
import re
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # for tests.oracles


def best_of(f, repeat: int = 7, number: int | None = None) -> float:
    """Best wall time of one call of f (s), over ``repeat`` rounds of ``number`` calls."""
    f()
    if number is None:
        t0 = time.perf_counter()
        f()
        number = max(1, int(0.05 / max(time.perf_counter() - t0, 1e-9)))
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            f()
        best = min(best, (time.perf_counter() - t0) / number)
    return best


ACCURACY = ROOT / "docs" / "accuracy.md"


def write_block(begin: str, end: str, body: str, doc: Path = ACCURACY) -> None:
    """Replace what lies between the markers ``begin`` and ``end`` of ``doc`` by ``body``
    (the tables the benchmarks' ``--write`` keep in docs/accuracy.md)."""
    text = doc.read_text(encoding="utf-8")
    pat = re.compile(re.escape(begin) + ".*?" + re.escape(end), re.S)
    if not pat.search(text):
        raise SystemExit(f"{doc.name} has no {begin} … {end} block")
    doc.write_text(pat.sub(lambda _m: f"{begin}\n{body.strip()}\n{end}", text), encoding="utf-8")


def publish(begin: str, end: str, body: str, write: bool, doc: Path = ACCURACY) -> None:
    """Print a benchmark's table ``body`` and, with ``--write``, put it between the markers
    of ``doc`` (:func:`write_block`), saying so."""
    print(body)
    if write:
        write_block(begin, end, body, doc)
        print(f"updated {doc.relative_to(doc.parents[1])}")


def machine() -> str:
    """The CPU, its logical CPUs, Python's and NumPy's versions (a table's conditions)."""
    import numpy

    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return (
        f"{cpu}, {os.cpu_count()} logical CPUs, Python {platform.python_version()}, "
        f"NumPy {numpy.__version__}"
    )


def hold_allocator() -> str:
    """glibc's allocator held warm for this process (``cli.MALLOC_KEPT``: arrays up to
    64 MB from the heap, the heap kept after a free), as issue 40 measures its rows at
    tens of thousands of positions; what was done, for a table's conditions.  Nothing
    where the user set a ``MALLOC_`` variable (theirs stand) or the C library is not
    glibc."""
    if any(name.startswith("MALLOC_") for name in os.environ):
        return "glibc's allocator as the environment's MALLOC_ variables set it"
    import ctypes

    from kinetostatics.cli import MALLOC_KEPT

    try:
        mallopt = ctypes.CDLL("libc.so.6").mallopt
    except (OSError, AttributeError):
        return "the C library's allocator (not glibc) as it is"
    for param, value in MALLOC_KEPT:
        mallopt(param, value)
    return (
        "glibc's allocator held warm for both sides (mallopt: mmap threshold 64 MB, trim "
        "threshold 256 MB, top pad 64 MB; issue 40's rule)"
    )
