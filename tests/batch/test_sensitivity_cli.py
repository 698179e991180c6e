"""``kinetostatics sensitivity`` (cli/sensitivity.py): its files, its one-line errors, a
resumed Monte Carlo, and the same numbers on a Dask cluster."""

from __future__ import annotations

import csv
import json
import math

import pytest

from kinetostatics.batch.runner import BatchOptions
from kinetostatics.batch.sensitivity import sensitivity
from kinetostatics.cli import main
from tests.batch.test_sensitivity import SLIDER, stroke, stroke_gradient

FAST = ["--serial", "--positions", "36", "--no-friction"]


def _cli(capsys, *args: str) -> tuple[int, str, str]:
    code = main(["sensitivity", str(SLIDER), *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_the_command_writes_its_files_with_the_closed_forms_numbers(tmp_path, capsys):
    out = tmp_path / "s"
    code, text, err = _cli(
        capsys,
        *("--vary", "a=±0.5", "--vary", "e=±0.5", "--of", "slide.stroke"),
        *("--samples", "30", "--seed", "4"),
        *("--limit", "slide.stroke <= 0.2003", "--out", str(out), *FAST),
    )
    assert code == 0, err
    data = json.loads((out / "sensitivity.json").read_text(encoding="utf-8"))
    grad = stroke_gradient(100.0, 350.0, -20.0)
    s = data["sensitivity"]["quantities"]["slide.stroke"]
    assert s["nominal"] == pytest.approx(stroke(100.0, 350.0, -20.0), rel=1e-12)
    assert s["parameters"]["a"]["derivative"] == pytest.approx(grad[0], rel=1e-8)
    assert s["parameters"]["e"]["derivative"] == pytest.approx(grad[2], rel=1e-8)
    mc = data["monte_carlo"]
    assert mc["samples"] == 30 and mc["failed"] == 0 and mc["dist"] == "normal"
    # the share outside the limit is that of the closed form's strokes of samples.csv
    lines = (out / "samples.csv").read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("# units:")
    names, *rows = list(csv.reader(lines[1:]))
    assert len(rows) == 30 and names[:3] == ["sample", "a", "e"]
    strokes = [stroke(float(r[1]), 350.0, float(r[2])) for r in rows]
    outside = sum(v > 0.2003 for v in strokes)
    assert mc["limits"][0]["outside"] == outside
    assert [float(r[names.index("slide.stroke")]) for r in rows] == pytest.approx(
        strokes, rel=1e-11
    )
    for name in ("sensitivity.md", "tornado-slide.stroke.png", "tornado-slide.stroke.svg"):
        assert (out / name).stat().st_size > 0
    # the page's table states its units: dQ/dp in m per unit of p as the file gives it
    page = (out / "sensitivity.md").read_text(encoding="utf-8")
    assert "| dQ/dp [m per unit of p] |" in page and "| Q(p + t) [m] |" in page
    assert (out / "histogram-slide.stroke.png").stat().st_size > 0
    assert "slide.stroke = 0.2003" in text and "d/da = 0.002" in text
    # the same command again takes every sample from the table on disk
    code, _, err = _cli(
        capsys,
        *("--vary", "a=±0.5", "--vary", "e=±0.5", "--of", "slide.stroke"),
        *("--samples", "30", "--seed", "4"),
        *("--limit", "slide.stroke <= 0.2003", "--out", str(out), *FAST),
    )
    assert code == 0, err
    again = json.loads((out / "sensitivity.json").read_text(encoding="utf-8"))["monte_carlo"]
    assert again["reused"] == 30
    assert again["quantities"] == mc["quantities"]


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["--vary", "q=±1"], "--vary q=±1: the file has no parameter 'q'"),
        (["--vary", "a=±-1"], "--vary a=±-1: the tolerance must be a positive number"),
        (["--vary", "a=±1", "--of", "slide.strok"], "no quantity or parameter 'slide.strok'"),
        (["--vary", "a=±1", "--samples", "1"], "--samples 1: must be from 2 to"),
        (["--vary", "a=±1", "--samples", "5", "--limit", "slide.stroke"], "--limit 'slide.stroke'"),
        (
            ["--vary", "a=±1", "--samples", "5", "--limit", "x.y <= 1"],
            "no quantity or parameter 'x.y'",
        ),
        (["--vary", "a=±1", "--chunk", "0"], "--chunk 0: must be from 1 to"),
        (["--vary", "a=±1", "--limit", "slide.stroke <= 1"], "--limit needs --samples"),
        (["--vary", "a=±1", "--of", "a", "--of", "a"], "--of 'a': named twice"),
        (["--vary", "a=±1", "--dist", "cauchy"], "argument --dist: invalid choice: 'cauchy'"),
    ],
)
def test_a_bad_argument_is_one_line_naming_it(tmp_path, capsys, args, named):
    out = tmp_path / "s"
    try:
        code, _, err = _cli(capsys, *args, "--out", str(out), *FAST)
    except SystemExit as exc:  # argparse's own errors
        code, err = exc.code, capsys.readouterr().err
    assert code == 2
    assert named in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists() or not (out / "sensitivity.json").exists()


@pytest.mark.timeout(120)
def test_a_local_dask_cluster_gives_the_same_sensitivities(tmp_path, dask_cluster):
    vary, of = ["a=±1", "b=±1%"], ["slide.stroke", "motor.torque_peak"]
    ref = sensitivity(SLIDER, vary, of, options=BatchOptions(executor="serial", positions=36))
    on = BatchOptions(executor=dask_cluster.scheduler_address, positions=36, chunk=5)
    got = sensitivity(SLIDER, vary, of, options=on, out=tmp_path)
    for a, b in zip(ref.derivatives, got.derivatives, strict=True):
        assert b.value == pytest.approx(a.value, rel=1e-9, abs=1e-12 * math.fabs(a.value) + 1e-15)
        assert b.low == pytest.approx(a.low, rel=1e-12)
        assert b.high == pytest.approx(a.high, rel=1e-12)
