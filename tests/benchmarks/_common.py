"""Shared timing helpers for the benchmarks (not collected by pytest)."""

from __future__ import annotations

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
