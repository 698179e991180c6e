"""docs/accuracy.md shows what the tests/benchmarks/accuracy_*.py scripts compute.

Each script's ``build(timing=False)`` gives its Markdown blocks with the wall
times left out; every table cell outside the timing columns must match the
block of the same name in docs/accuracy.md.  Numbers are compared to the
printed precision (two digits: within 10 %), and values at round-off level
(both ≤ 1e-13) are accepted as equal, since their last bits depend on the
platform.  An error column (``… error``) of a difference quotient is held to a factor
of 2: at the small steps its error is round-off divided by h or h², which moves with
the CPU's summation (1.7e-07 against 1.9e-07 with NumPy's AVX-512 loops switched off);
what the table says is its order of magnitude.  Regenerate the page with ``--update``
(see docs/accuracy.md).
"""

from __future__ import annotations

import importlib
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "tests" / "benchmarks"
NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def _script(name: str):
    if str(SCRIPTS) not in sys.path:
        sys.path.insert(0, str(SCRIPTS))
    return importlib.import_module(f"accuracy_{name}")


def _tables(text: str) -> list[list[list[str]]]:
    tables, cur = [], []
    for line in text.splitlines():
        if line.startswith("|"):
            cur.append([c.strip() for c in line.strip().strip("|").split("|")])
        elif cur:
            tables.append(cur)
            cur = []
    if cur:
        tables.append(cur)
    return tables


def _same(a: str, b: str, factor: float | None = None) -> bool:
    """``a`` and ``b`` alike to the printed precision, or within ``factor`` of each other."""
    if NUMBER.sub("#", a) != NUMBER.sub("#", b):
        return False
    for x, y in zip(map(float, NUMBER.findall(a)), map(float, NUMBER.findall(b))):
        if abs(x) <= 1e-13 and abs(y) <= 1e-13:
            continue
        if factor and x * y > 0 and max(x / y, y / x) <= factor:
            continue
        if abs(x - y) > 0.1 * max(abs(x), abs(y)):
            return False
    return True


def _doc_block(doc: str, name: str) -> str:
    m = re.search(
        rf"<!-- BEGIN accuracy:{re.escape(name)} -->(.*?)<!-- END accuracy:{re.escape(name)} -->",
        doc,
        re.S,
    )
    assert m, f"docs/accuracy.md has no block accuracy:{name}"
    return m.group(1)


@pytest.mark.parametrize(
    "name", ["derivatives", "friction", "needs", "positions", "scales", "stages"]
)
def test_accuracy_tables_are_current(name):
    module = _script(name)
    blocks, _ = module.build(timing=False)
    doc = (ROOT / "docs" / "accuracy.md").read_text()
    for block_name, body in blocks.items():
        ours, theirs = _tables(body), _tables(_doc_block(doc, block_name))
        assert len(ours) == len(theirs), block_name
        for t_ours, t_doc in zip(ours, theirs):
            header = t_ours[0]
            assert t_doc[0] == header, (block_name, t_doc[0])
            assert len(t_doc) == len(t_ours), (block_name, "rows")
            for r_ours, r_doc in zip(t_ours[2:], t_doc[2:]):
                for col, a, b in zip(header, r_ours, r_doc):
                    if a == "·":  # a wall time: not reproducible
                        continue
                    factor = 2.0 if col.endswith("error") else None
                    assert _same(a, b, factor), (
                        f"{block_name}: column '{col}': script {a!r}, doc {b!r}"
                    )
