"""How far the current outputs are from the golden files, on the scale of each quantity's
unit: the check before golden files are rewritten for a change that moves round-off.

    PYTHONPATH=src python tests/golden/audit.py [NAME ...]

For every shipped mechanism (or the NAMEs given) the commands of ``make_golden.py`` run
again and every file is compared by the rule of ``compare.py`` (the test's rule): the
worst ratio of a difference to its unit's scale is printed per file, with every change
of kind (a number against an empty cell, a changed text) as ``inf``.  A change that only
moves round-off shows ratios of a few 1e-13 or less, a simulation's ratios stay below
its integrator's tolerance, and nothing is ``inf``.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import compare as C  # noqa: E402
import make_golden as G  # noqa: E402


def main(names: list[str]) -> int:
    paths = [p for p in G.MECHANISMS if not names or p.stem in names]
    with tempfile.TemporaryDirectory() as tmp:
        for path in paths:
            produced = G.produce(path, Path(tmp))
            golden = {name: G.read(name, HERE / path.stem) for name in produced}
            for name in produced:
                found = C.compare({name: produced[name]}, golden, {"*": 0.0})
                if found:
                    worst, where = max(found)
                    print(f"{path.stem}/{name}: worst {worst:.1e} {where}")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(G.ROOT / "src"))
    raise SystemExit(main(sys.argv[1:]))
