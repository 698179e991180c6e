"""Behaviour is unchanged by refactors: every shipped mechanism gives the golden files.

The files under tests/golden/ were written by ``tests/golden/make_golden.py``
before the architecture step moved any code.  Numbers must agree to 1e-12
relative to the largest magnitude of their column (of their array in the
drawing data); text must agree exactly.  The simulation is an adaptive
integration, where a reordered sum may change a step size: it is held to 1e-9.
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

GOLDEN = Path(__file__).resolve().parent / "golden"
sys.path.insert(0, str(GOLDEN))
import make_golden as G  # noqa: E402

sys.path.remove(str(GOLDEN))

REL = 1e-12


def _number(cell: str):
    try:
        return float(cell)
    except ValueError:
        return None


def _compare_csv(new: str, old: str, rel: float) -> list[str]:
    a = list(csv.reader(io.StringIO(new)))
    b = list(csv.reader(io.StringIO(old)))
    if len(a) != len(b) or a[:2] != b[:2]:
        return [f"header or row count differs ({len(a)} rows, golden {len(b)})"]
    bad = []
    body_a, body_b = a[2:], b[2:]
    for j, name in enumerate(b[1]):
        col_b = [r[j] for r in body_b]
        col_a = [r[j] for r in body_a]
        nb = [_number(c) for c in col_b]
        if any(v is None for v in nb):
            if col_a != col_b:
                bad.append(f"{name}: text differs")
            continue
        na = np.array([_number(c) if _number(c) is not None else math.inf for c in col_a])
        nb = np.array(nb)
        scale = np.max(np.abs(nb[np.isfinite(nb)]), initial=0.0)
        same = (na == nb) | (np.abs(na - nb) <= rel * scale) | (np.isnan(na) & np.isnan(nb))
        if not same.all():
            k = int(np.argmin(same))
            bad.append(f"{name}: row {k}: {col_a[k]} != {col_b[k]}")
    return bad


def _compare_json(a, b, rel: float, where: str = "") -> list[str]:
    if isinstance(b, dict):
        if not isinstance(a, dict) or list(a) != list(b):
            return [f"{where}: keys differ"]
        return [m for k in b for m in _compare_json(a[k], b[k], rel, f"{where}.{k}")]
    if isinstance(b, list):
        if not isinstance(a, list) or len(a) != len(b):
            return [f"{where}: length differs"]
        flat = [v for v in b if isinstance(v, (int, float)) and not isinstance(v, bool)]
        scale = max((abs(v) for v in flat if math.isfinite(v)), default=0.0)
        out = []
        for k, (x, y) in enumerate(zip(a, b)):
            if isinstance(y, float) and isinstance(x, (int, float)):
                if not (
                    x == y
                    or abs(x - y) <= rel * max(scale, abs(y))
                    or (math.isnan(x) and math.isnan(y))
                ):
                    out.append(f"{where}[{k}]: {x!r} != {y!r}")
            else:
                out += _compare_json(x, y, rel, f"{where}[{k}]")
        return out
    if isinstance(b, float) and isinstance(a, (int, float)):
        ok = a == b or abs(a - b) <= rel * abs(b) or (math.isnan(a) and math.isnan(b))
        return [] if ok else [f"{where}: {a!r} != {b!r}"]
    return [] if a == b else [f"{where}: {a!r} != {b!r}"]


@pytest.mark.parametrize("path", G.MECHANISMS, ids=lambda p: p.stem)
def test_golden(path, tmp_path):
    folder = GOLDEN / path.stem
    produced = G.produce(path, tmp_path)
    expected = sorted(p.name.removesuffix(".gz") for p in folder.iterdir())
    assert sorted(produced) == expected
    bad = []
    for name, text in produced.items():
        old = G.read(name, folder)
        if name.endswith(".csv"):
            rel = 1e-9 if name == "simulation.csv" else REL
            bad += [f"{name}: {m}" for m in _compare_csv(text, old, rel)]
        elif name.endswith(".json"):
            bad += [f"{name}: {m}" for m in _compare_json(json.loads(text), json.loads(old), REL)]
        elif text != old:
            bad.append(f"{name}: text differs")
    assert not bad, "\n".join(bad[:20])
