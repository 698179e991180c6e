"""Behaviour is unchanged by refactors: every shipped mechanism gives the golden files.

The files under tests/golden/ were written by ``tests/golden/make_golden.py``
before the architecture step moved any code.  Every number must agree to 1e-12 of
its unit's scale, the rule of ``tests/golden/compare.py`` (its docstring says it
whole), so that the files mean the same on every CPU: NumPy's SIMD loops move last
bits, and the test must be blind to exactly that.  A simulation is an adaptive
integration, where a reordered sum may change a step size: it is held to the relative
tolerance it was integrated to (``simulate``'s default ``--rtol 1e-8``) of its unit's
scale (Andrews' squeezer moves by 2.7e-9 with NumPy's AVX-512 loops switched off).

The second half of this file shows that the comparison can still fail: a real column
moved by 1e-9 of its scale, a cell emptied, a self-check leaving round-off.
"""

from __future__ import annotations

import csv
import io
import json
import re
import sys
from pathlib import Path

import pytest

GOLDEN = Path(__file__).resolve().parents[1] / "golden"
sys.path.insert(0, str(GOLDEN))
import compare as C  # noqa: E402
import make_golden as G  # noqa: E402

sys.path.remove(str(GOLDEN))

REL = {"*": 1e-12, "simulation.csv": 1e-8}


def _golden(folder: Path) -> dict[str, str]:
    return {
        p.name.removesuffix(".gz"): G.read(p.name.removesuffix(".gz"), folder)
        for p in folder.iterdir()
    }


@pytest.mark.parametrize("path", G.MECHANISMS, ids=lambda p: p.stem)
def test_golden(path, tmp_path):
    golden = _golden(GOLDEN / path.stem)
    produced = G.produce(path, tmp_path)
    assert sorted(produced) == sorted(golden)
    bad = [m for _, m in C.compare(produced, golden, REL)]
    assert not bad, "\n".join(bad[:20])


# --- the comparison can fail --------------------------------------------------------


@pytest.fixture(scope="module")
def slider_crank() -> dict[str, str]:
    return _golden(GOLDEN / "slider_crank")


def _edit_csv(text: str, column: str, edit) -> str:
    rows = list(csv.reader(io.StringIO(text)))
    j = rows[1].index(column)
    edit(rows[2:], j)
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows(rows)
    return out.getvalue()


def _found(golden: dict[str, str], **changed: str) -> list[str]:
    return [m for _, m in C.compare({**golden, **changed}, golden, REL)]


def test_golden_unchanged_passes(slider_crank):
    assert _found(slider_crank) == []


@pytest.mark.parametrize("column", ["rod.ax", "O.Fx", "motor.torque", "slider.x"])
def test_a_column_moved_by_1e_9_of_its_scale_is_caught(slider_crank, column):
    text = slider_crank["results.csv"]
    rows = list(csv.reader(io.StringIO(text)))
    unit = rows[0][rows[1].index(column)].replace("# units: ", "")
    scale = C.unit_scales(text)[unit]

    def move(body, j):
        body[7][j] = repr(float(body[7][j]) + 1e-9 * scale)

    bad = _found(slider_crank, **{"results.csv": _edit_csv(text, column, move)})
    assert len(bad) == 1 and bad[0].startswith(f"results.csv: {column} [{unit}] row 7")


def test_round_off_of_the_unit_passes(slider_crank):
    """A column of zeros (a fixed pivot's speed) may gain round-off of its unit."""
    text = slider_crank["results.csv"]
    scale = C.unit_scales(text)["m/s"]

    def nudge(body, j):
        for r in body:
            r[j] = repr(float(r[j]) + 1e-14 * scale)

    assert _found(slider_crank, **{"results.csv": _edit_csv(text, "crank.O.vx", nudge)}) == []


def test_an_emptied_cell_is_caught(slider_crank):
    def empty(body, j):
        body[3][j] = ""

    bad = _found(
        slider_crank,
        **{"results.csv": _edit_csv(slider_crank["results.csv"], "motor.torque", empty)},
    )
    assert len(bad) == 1 and "motor.torque" in bad[0]


def test_summary_on_its_unit(slider_crank):
    summary = json.loads(slider_crank["summary.json"])
    torque = C.unit_scales(slider_crank["results.csv"])["N*m"]
    summary["drivers"]["motor"]["mean"] += 1e-14 * torque  # round-off of N·m: passes
    assert _found(slider_crank, **{"summary.json": json.dumps(summary)}) == []
    summary["drivers"]["motor"]["rms"] += 1e-9 * torque
    bad = _found(slider_crank, **{"summary.json": json.dumps(summary)})
    assert bad and all("drivers.motor.rms" in m for m in bad)


def test_a_self_check_leaving_round_off_is_caught(slider_crank):
    summary = json.loads(slider_crank["summary.json"])
    tol = summary["checks"]["power"]["tolerance"]
    summary["checks"]["power"]["where"] = "angle 1°"  # where round-off peaks: not compared
    assert _found(slider_crank, **{"summary.json": json.dumps(summary)}) == []
    summary["checks"]["power"]["value"] = 0.01 * tol
    bad = _found(slider_crank, **{"summary.json": json.dumps(summary)})
    assert len(bad) == 1 and "checks.power.value" in bad[0]


def test_where_a_real_extreme_lies_is_compared(slider_crank):
    summary = json.loads(slider_crank["summary.json"])
    summary["extremes"]["motor.torque"]["at_max"] += 1.0
    bad = _found(slider_crank, **{"summary.json": json.dumps(summary)})
    assert len(bad) == 1 and "extremes.motor.torque.at_max" in bad[0]


def test_a_text_on_the_scale_of_its_line(slider_crank):
    """check.txt: the self-checks' round-off may move (1e-16 printed for 2e-16 where the
    CPU fuses a multiply and an add); a real number or a word that changes is caught."""
    text = slider_crank["check.txt"]
    line = next(x for x in text.splitlines() if x.startswith("checks (start pose)"))
    residual = re.search(r"constraints (\S+)", line).group(1)
    moved = line.replace(f"constraints {residual}", "constraints 3e-16")
    assert _found(slider_crank, **{"check.txt": text.replace(line, moved)}) == []
    cond = re.search(r"cond ≤ (\S+)", line).group(1)
    worse = line.replace(f"cond ≤ {cond}", f"cond ≤ {float(cond) * (1 + 1e-9)!r}")
    bad = _found(slider_crank, **{"check.txt": text.replace(line, worse)})
    assert len(bad) == 1 and bad[0].startswith("check.txt: line")
    renamed = text.replace("driven link", "driving link")
    bad = _found(slider_crank, **{"check.txt": renamed})
    assert bad and "differs" in bad[0]
    assert _found(slider_crank, **{"check.txt": text + "one more line\n"})
