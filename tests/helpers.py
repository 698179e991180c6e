"""Shared helpers for the tests (imported as ``from tests.helpers import …`` from every
folder): the repository's root and shipped mechanisms, model variants made by editing a
shipped file, relative errors, the motion-driven files, Dask or a skip, an executor that
loses its scheduler."""

from __future__ import annotations

import importlib.util
import os
import re
from concurrent.futures import Executor, Future
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from tests.golden.compare import compare_text

ROOT = Path(__file__).resolve().parent.parent
MECHANISMS = sorted((ROOT / "mechanisms").glob("*.yaml"))


def load_script(path: Path):
    """The script at ``path`` (docs/scripts) imported as a module, under its file's name."""
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def variant(name: str, **replacements: str) -> ks.Model:
    """Load ``mechanisms/<name>.yaml`` after regex replacements ``pattern=repl``
    given as keyword pairs ``k=(pattern, repl)``."""
    text = (ROOT / "mechanisms" / f"{name}.yaml").read_text()
    for pattern, repl in replacements.values():
        text, n = re.subn(pattern, repl, text)
        assert n, f"pattern {pattern!r} not found"
    return ks.loads(text, file=f"{name}-variant.yaml")


def rel_err(x, ref) -> float:
    """max|x − ref| / max|ref| (docs/conventions.md, Accuracy)."""
    return float(np.max(np.abs(np.asarray(x) - ref)) / np.max(np.abs(ref)))


def same_lines(got: str, want: str, rel: float = 1e-6) -> None:
    """A page's block as its script writes it again, by the golden files' rule for a text
    (tests/golden/compare.py): line by line, the same words between the numbers, each
    number within ``rel`` of the largest of its line in ``want`` — round-off (a derivative
    that is zero, an error estimate, a value printed to full precision) is the machine's,
    the rest its printed digits."""
    bad = compare_text(got, want, rel)
    assert not bad, [m for _, m in bad]


def assert_close_on_unit_scales(a, b, rel: float = 1e-12, skip: tuple = ()) -> None:
    """Two results with the same columns, each within ``rel`` of its unit's scale (the
    largest finite |value| of ``b``'s columns of that unit), NaN where NaN: the contract of
    the compiled backend and of any reordering of the same formulas (NumPy's SIMD loops and
    the order of a sum move the last bits from one CPU to another); the columns ``skip``
    are left to the caller."""
    assert list(a.columns) == list(b.columns)
    scale: dict[str, float] = {}
    for c in b.columns:
        v = np.asarray(b[c], dtype=float)
        v = v[np.isfinite(v)]
        if v.size:
            u = b.units.get(c, "")
            scale[u] = max(scale.get(u, 0.0), float(np.max(np.abs(v))))
    for c in (c for c in a.columns if c not in skip):
        x, y = np.asarray(a[c], dtype=float), np.asarray(b[c], dtype=float)
        assert x.shape == y.shape, c
        np.testing.assert_array_equal(np.isnan(x), np.isnan(y), err_msg=c)
        np.testing.assert_array_equal(np.isinf(x), np.isinf(y), err_msg=c)
        ok = np.isfinite(y)
        tol = rel * scale.get(b.units.get(c, ""), 0.0)
        np.testing.assert_allclose(x[ok], y[ok], rtol=0, atol=tol, err_msg=c)


def motion_driven() -> list[str]:
    """The shipped mechanisms (file stems) whose drivers all prescribe a motion — the ones
    `run`, `report` and `plot` analyse; an effort-driven file (a driver with ``effort:``)
    is simulated instead."""
    import yaml

    out = []
    for path in sorted((ROOT / "mechanisms").glob("*.yaml")):
        drivers = (yaml.safe_load(path.read_text(encoding="utf-8")) or {}).get("drivers") or {}
        if not any("effort" in (d or {}) for d in drivers.values()):
            out.append(path.stem)
    return out


def distributed_or_skip():
    """``distributed`` (Dask), or skip where it is not installed — but not under CI
    (``CI`` set), which installs the test extra: there a missing Dask fails the test."""
    if os.environ.get("CI"):
        import distributed

        return distributed
    return pytest.importorskip("distributed")


class LosingExecutor(Executor):
    """Runs ``n`` chunks in this process, then loses its scheduler (the message a lost
    Dask scheduler gives)."""

    def __init__(self, n: int):
        self.n = n

    def submit(self, fn, /, *args, **kwargs):
        if self.n == 0:
            raise OSError("Timed out trying to connect to tcp://127.0.0.1:8786")
        self.n -= 1
        f: Future = Future()
        f.set_result(fn(*args, **kwargs))
        return f


def spread_rows(result) -> list[int]:
    """Three rows spread over a run, none at its start."""
    n = len(result.t)
    return [n // 7, 3 * n // 7, 5 * n // 7 + 3]
