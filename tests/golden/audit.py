"""How far the current outputs are from the golden files, on the scale of each quantity's
unit: the check before golden files are rewritten for a change that moves round-off.

    PYTHONPATH=src python tests/golden/audit.py [NAME ...]

For every shipped mechanism (or the NAMEs given) the commands of ``make_golden.py`` run
again.  A CSV cell is compared with its golden cell against the largest |value| of all
columns of the same unit (a fixed pivot's speed of 1e-17 m/s is round-off of the links'
metres per second, not of its own column of zeros); the worst ratio is printed per file,
with every cell whose text changed kind (a number against an empty cell).  JSON numbers
are compared against the largest |number| of the file.  A change that only moves
round-off shows ratios of a few 1e-13 or less and no changed kinds.
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import make_golden as G  # noqa: E402


def _num(cell: str):
    try:
        return float(cell)
    except ValueError:
        return None


def csv_audit(new: str, old: str) -> tuple[float, str, list[str]]:
    a = list(csv.reader(io.StringIO(new)))
    b = list(csv.reader(io.StringIO(old)))
    if len(a) != len(b) or a[:2] != b[:2]:
        return math.inf, "header or row count differs", []
    units, names = b[0], b[1]
    units = [u.replace("# units: ", "") for u in units]
    scale: dict[str, float] = {}
    for row in b[2:]:
        for u, cell in zip(units, row):
            v = _num(cell)
            if v is not None and math.isfinite(v):
                scale[u] = max(scale.get(u, 0.0), abs(v))
    worst, where, kinds = 0.0, "", []
    for k, (ra, rb) in enumerate(zip(a[2:], b[2:])):
        for name, u, ca, cb in zip(names, units, ra, rb):
            va, vb = _num(ca), _num(cb)
            if (va is None) != (vb is None) or (va is None and ca != cb):
                kinds.append(f"{name} row {k}: {ca!r} (golden {cb!r})")
                continue
            if va is None or va == vb or (math.isnan(va) and math.isnan(vb)):
                continue
            r = abs(va - vb) / max(scale.get(u, 0.0), 1e-300)
            if r > worst:
                worst, where = r, f"{name} row {k}: {ca} (golden {cb}), unit {u}"
    return worst, where, kinds


def _numbers(x, out):
    if isinstance(x, dict):
        for v in x.values():
            _numbers(v, out)
    elif isinstance(x, list):
        for v in x:
            _numbers(v, out)
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        out.append(float(x))
    else:
        out.append(x)
    return out


def json_audit(new: str, old: str) -> tuple[float, str, list[str]]:
    a, b = _numbers(json.loads(new), []), _numbers(json.loads(old), [])
    if len(a) != len(b):
        return math.inf, "structure differs", []
    scale = max((abs(v) for v in b if isinstance(v, float) and math.isfinite(v)), default=1.0)
    worst, where, kinds = 0.0, "", []
    for k, (x, y) in enumerate(zip(a, b)):
        if isinstance(x, float) and isinstance(y, float):
            if x == y or (math.isnan(x) and math.isnan(y)):
                continue
            r = abs(x - y) / scale
            if r > worst:
                worst, where = r, f"value {k}: {x} (golden {y})"
        elif x != y:
            kinds.append(f"value {k}: {x!r} (golden {y!r})")
    return worst, where, kinds


def main(names: list[str]) -> int:
    paths = [p for p in G.MECHANISMS if not names or p.stem in names]
    with tempfile.TemporaryDirectory() as tmp:
        for path in paths:
            for name, text in G.produce(path, Path(tmp)).items():
                old = G.read(name, HERE / path.stem)
                if text == old:
                    continue
                audit = csv_audit if name.endswith(".csv") else json_audit
                worst, where, kinds = (
                    audit(text, old) if name.endswith((".csv", ".json")) else (math.inf, "", [])
                )
                print(f"{path.stem}/{name}: worst {worst:.1e} {where}")
                for k in kinds[:10]:
                    print(f"    changed kind: {k}")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(G.ROOT / "src"))
    raise SystemExit(main(sys.argv[1:]))
