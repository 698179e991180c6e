"""``kinetostatics optimize`` at its edges (issue 36, items 7 and 11): options and bounds
that cannot make a search are one line and exit 2 with nothing written; an objective that
has no value at any design says so; a best design on a bound is said to be on it; Ctrl-C
stops with one line and exit 130, ``designs.csv`` holding every design evaluated, and the
same command resumes from it to the best design of an uninterrupted run."""

from __future__ import annotations

import importlib
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import kinetostatics as ks
from kinetostatics.batch.table import read_summary
from kinetostatics.cli import main

opt = importlib.import_module("kinetostatics.batch.optimize")  # the module, not the function
ROOT = Path(__file__).resolve().parents[2]
FOURBAR = ROOT / "mechanisms" / "fourbar_balancing.yaml"
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "src"))

SMALL = ["--positions", "12", "--popsize", "3", "--maxiter", "2", "--no-polish", "--quiet"]


def _cli(capsys, *args: str) -> tuple[int, str, str]:
    code = main(["optimize", str(FOURBAR), *args])
    out, err = capsys.readouterr()
    return code, out, err


def _one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.mark.parametrize(
    ("args", "named"),
    [
        # the search's designs are midpoint + u·span: 1e307 + 1.7e308 overflows
        (["--vary", "x1=1e307:1.7e308"], "--vary x1="),
        (["--vary", "x1=-1.7e308:0"], "--vary x1="),
        (["--vary", "x1=-0.3:0.1", "--vary", "x1=-0.2:0"], "--vary x1: named twice"),
        (["--vary", "x1=-0.3:0.1", "--popsize", "0"], "--popsize 0: must be from 1 to 1000"),
        (["--vary", "x1=-0.3:0.1", "--popsize", "-1"], "--popsize -1: must be from 1 to 1000"),
        (["--vary", "x1=-0.3:0.1", "--popsize", "100000000"], "--popsize 100000000: must be"),
        (["--vary", "x1=-0.3:0.1", "--maxiter", "-1"], "--maxiter -1: must be from 0 to"),
        (["--vary", "x1=-0.3:0.1", "--seed", "-1"], "--seed -1: must be from 0 to"),
    ],
)
def test_a_search_that_cannot_be_made_is_one_line_and_writes_nothing(tmp_path, capsys, args, named):
    out = tmp_path / "o"
    code, _, err = _cli(
        capsys, *args, "--minimize", "shaking.force_rms", "--out", str(out), *SMALL[:2]
    )
    assert code == 2
    assert named in _one_line(err)
    assert not out.exists() or not any(out.iterdir())


def test_the_api_refuses_the_same_options():
    with pytest.raises(opt.OptimizeError, match="named twice"):
        opt.parse_vary(["x1=0:1", "x1=0:2"])
    with pytest.raises(opt.OptimizeError, match="--popsize 0"):
        ks.optimize(FOURBAR, {"x1": (-0.3, 0.1)}, "shaking.force_rms", popsize=0)
    with pytest.raises(opt.OptimizeError, match="--maxiter 1.5: must be a whole number"):
        ks.optimize(FOURBAR, {"x1": (-0.3, 0.1)}, "shaking.force_rms", maxiter=1.5)


@pytest.mark.parametrize("expression", ["9**9**9**9", "sqrt(-x1 - 1)"])
def test_an_objective_with_no_value_at_any_design_says_so(tmp_path, capsys, expression):
    """9**9**9**9 overflows at every design, and −x1 − 1 < 0 for every x1 in [−0.3, 0.1]: no
    design gives either a value.  Without constraints this was 'INFEASIBLE' and exit 0."""
    out = tmp_path / "o"
    code, stdout, err = _cli(
        capsys, "--vary", "x1=-0.3:0.1", "--minimize", expression, "--out", str(out), *SMALL
    )
    assert code == 2 and "INFEASIBLE" not in stdout
    line = _one_line(err)
    assert f"--minimize {expression!r}: could not be evaluated at any" in line
    assert not out.exists() or not any(out.iterdir())  # no designs.csv, no best.yaml


SLIDER_CRANK = """
name: centred slider-crank
units: {length: mm, angle: deg, speed: rpm}
parameters: {a: 80, b: 300, m: 1}
links:
  ground: {points: {O: [0, 0], guide: [0, 0]}}
  crank: {points: {O: [0, 0], A: [a, 0]}, com: [a/2, 0], mass: m, inertia: 0.001}
  rod: {points: {A: [0, 0], B: [b, 0]}, com: [b/2, 0], mass: 2, inertia: 0.01}
  slider: {points: {B: [0, 0]}, mass: 1}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, rod]}
  B: {type: revolute, links: [rod, slider]}
  slide: {type: prismatic, links: [ground, slider], axis: {point: guide, direction: [1, 0]},
          point: B}
drivers:
  motor: {joint: O, motion: {speed: 60}}
sketch: {A: [a, 0], B: [a + b, 0]}
"""


def test_bounds_where_no_design_can_be_analysed_say_so(tmp_path, capsys):
    """A negative mass makes the file invalid: no design of m in [−2, −1] is analysed.
    This was 'INFEASIBLE (no design met every constraint)' with no constraint, exit 0,
    and a best.yaml that does not load.  (A rod shorter than the crank fails as surely,
    but a batch takes over a second to say so for each design.)"""
    path = tmp_path / "sc.yaml"
    path.write_text(SLIDER_CRANK, encoding="utf-8")
    out = tmp_path / "o"
    code = main(
        ["optimize", str(path), "--vary", "m=-2:-1", "--minimize", "motor.torque_rms"]
        + ["--out", str(out), *SMALL]
    )
    stdout, err = capsys.readouterr()
    assert code == 2 and "INFEASIBLE" not in stdout
    line = _one_line(err)
    assert line.startswith("kinetostatics: --vary m=-2:-1: none of the")
    assert "could be analysed (e.g. " in line and "links.crank.mass: must be zero or" in line
    assert not out.exists() or not any(out.iterdir())


def test_a_best_design_on_a_bound_is_said_to_be_on_it(tmp_path, capsys):
    """y1 over [0, 0.1] is least at 0, its lower bound (the file's own design, x1 = y1 = 0,
    is in the first population); x1 = 0 lies inside [−0.3, 0.1].  −x1 + y1 over
    [−0.3, 0] × [0, 0.1] is least at x1 = 0 (upper bound), y1 = 0 (lower)."""
    out = tmp_path / "o"
    code, stdout, _ = _cli(
        capsys,
        "--vary",
        "x1=-0.3:0.1",
        "--vary",
        "y1=0:0.1",
        "--minimize",
        "y1",
        "--out",
        str(out),
        *SMALL,
    )
    assert code == 0
    lines: dict[str, str] = {}  # the parameters' lines come first, then the objective's
    for line in stdout.splitlines():
        if " = " in line:
            lines.setdefault(*line.strip().split(" = ", 1))
    assert lines["y1"] == "0 (on its lower bound)"
    assert "bound" not in lines["x1"] and float(lines["x1"]) == pytest.approx(0, abs=1e-12)
    best = (out / "best.yaml").read_text(encoding="utf-8")
    assert best.startswith("# y1 = 0 is on its lower bound")
    assert "x1 = " not in best.split("\n")[1]
    assert ks.load(out / "best.yaml").parameters["y1"] == 0.0
    result = ks.optimize(
        FOURBAR,
        {"x1": (-0.3, 0.0), "y1": (0.0, 0.1)},
        "-x1 + y1",
        positions=12,
        popsize=3,
        maxiter=2,
        polish=False,
        progress=False,
    )
    assert result.on_bound == {"x1": "upper", "y1": "lower"}


# -- Ctrl-C, and the same command resumed ------------------------------------------------
# The interrupted run is made slow (a pause before each population) so that the signal
# falls within the search whatever the machine's load: a wrapper, not the program.
SLOW = """
import importlib, sys, time
o = importlib.import_module("kinetostatics.batch.optimize")
rows = o._Problem.rows
def slow(self, overrides):
    time.sleep(0.05)
    return rows(self, overrides)
o._Problem.rows = slow
from kinetostatics.cli import main
sys.exit(main(sys.argv[1:]))
"""
SEARCH = [
    "--vary",
    "x1=-0.3:0.1",
    "--vary",
    "y1=-0.1:0.1",
    "--minimize",
    "shaking.force_rms",
    "--positions",
    "12",
    "--popsize",
    "3",
    "--maxiter",
    "6",
    "--no-polish",
    "--quiet",
]


def test_ctrl_c_stops_with_one_line_and_the_same_command_resumes(tmp_path, monkeypatch, capsys):
    out = tmp_path / "o"
    args = ["optimize", str(FOURBAR), *SEARCH, "--out", str(out)]
    p = subprocess.Popen(
        [sys.executable, "-c", SLOW, *args],
        env=ENV,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        # Python turns SIGINT into KeyboardInterrupt only where it is not ignored
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    designs = out / "designs.csv"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and p.poll() is None:
        if designs.exists() and read_summary(designs)[1]:
            break
        time.sleep(0.01)
    assert p.poll() is None, p.communicate()
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=120)
    assert p.returncode == 130, (stdout, stderr)
    line = _one_line(stderr)
    assert "interrupted" in line and str(designs) in line and "resume" in line
    assert not (out / "best.yaml").exists()
    header, before = read_summary(designs)
    assert before and header[:4] == ["evaluation", "stage", "x1", "y1"]
    for row in before:  # every row whole: numbers where numbers belong
        assert int(row["evaluation"]) >= 1 and row["status"] in ("ok", "infeasible", "failed")
        assert math.isfinite(float(row["x1"])) and math.isfinite(float(row["score"]))
    with designs.open("a", encoding="utf-8") as fh:
        fh.write(f"{len(before) + 1},generation 9,-0.1")  # a row cut by a kill: left out

    analysed = []
    rows = opt._Problem.rows

    def counted(self, overrides):
        analysed.extend(overrides)
        return rows(self, overrides)

    monkeypatch.setattr(opt._Problem, "rows", counted)
    assert main(args) == 0
    capsys.readouterr()
    _, after = read_summary(designs)
    assert after[: len(before)] == before  # the rows read back, as they were
    # only the designs not evaluated before (and the best design's row, when it is one of
    # those read back) are analysed again
    assert len(after) - len(before) <= len(analysed) <= len(after) - len(before) + 1
    assert len(analysed) < len(after)
    monkeypatch.setattr(opt._Problem, "rows", rows)

    fresh = ks.optimize(
        FOURBAR,
        ["x1=-0.3:0.1", "y1=-0.1:0.1"],
        "shaking.force_rms",
        positions=12,
        popsize=3,
        maxiter=6,
        polish=False,
        progress=False,
    )
    assert len(after) == len(fresh.designs)
    resumed = ks.load(out / "best.yaml").parameters
    for name, span in (("x1", 0.4), ("y1", 0.2)):
        assert resumed[name] == pytest.approx(fresh.parameters[name], abs=1e-12 * span)
        column = [float(r[name]) for r in after]
        assert column == pytest.approx([d[name] for d in fresh.designs], abs=1e-12 * span)


def test_a_folder_of_another_search_is_refused_unless_overwrite(tmp_path, capsys):
    out = tmp_path / "o"
    args = ["--vary", "x1=-0.3:0.1", "--out", str(out), *SMALL]
    assert _cli(capsys, *args, "--minimize", "shaking.force_rms")[0] == 0
    code, _, err = _cli(capsys, *args, "--minimize", "shaking.force_peak")
    assert code == 2 and "holds the designs of another search" in _one_line(err)
    code, _, _ = _cli(capsys, *args, "--minimize", "shaking.force_peak", "--overwrite")
    assert code == 0
    _, rows = read_summary(out / "designs.csv")
    assert rows and len(rows) == len({r["evaluation"] for r in rows})


def test_ctrl_c_at_a_terminal_with_workers_is_one_line(tmp_path):
    """A terminal's Ctrl-C reaches the whole process group: the pool's workers, waiting for
    their next chunk between two generations, printed a traceback each."""
    out = tmp_path / "o"
    p = subprocess.Popen(
        [sys.executable, "-m", "kinetostatics.cli", "optimize", str(FOURBAR), *SEARCH]
        + ["--maxiter", "1000", "--workers", "2", "--out", str(out)],
        env=ENV,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, as a terminal's job
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    designs = out / "designs.csv"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and p.poll() is None:
        if designs.exists() and len(read_summary(designs)[1]) >= 3 * 2 * 3:  # 3 generations
            break
        time.sleep(0.01)
    assert p.poll() is None, p.communicate()
    os.killpg(p.pid, signal.SIGINT)
    _, stderr = p.communicate(timeout=120)
    assert p.returncode == 130, stderr
    assert "interrupted" in _one_line(stderr)


@pytest.mark.parametrize("after", [0, 4])
def test_a_full_disk_is_one_line_and_the_same_command_resumes(tmp_path, capsys, monkeypatch, after):
    """ENOSPC at optimize.json, or in the second append (half of its text written): one
    line, exit 2, no temporary file; the rerun keeps the whole rows, drops the cut one and
    ends with the designs of an uninterrupted search."""
    from kinetostatics.batch import table as batch_table

    real, calls = batch_table._Table._write, {"n": 0}

    def full(path, text, mode):
        calls["n"] += 1
        if calls["n"] > after:
            with open(path, mode, encoding="utf-8", newline="") as fh:
                fh.write(text[: len(text) // 2])
            raise OSError(28, os.strerror(28), str(path))
        real(path, text, mode)

    out = tmp_path / "o"
    args = ["--vary", "x1=-0.3:0.1", "--minimize", "shaking.force_rms", *SMALL]
    monkeypatch.setattr(batch_table._Table, "_write", staticmethod(full))
    code, _, err = _cli(capsys, *args, "--out", str(out))
    assert code == 2 and _one_line(err).endswith("No space left on device")
    assert not any(p.name.endswith(".tmp") for p in out.iterdir())
    monkeypatch.undo()
    assert _cli(capsys, *args, "--out", str(out))[0] == 0
    assert _cli(capsys, *args, "--out", str(tmp_path / "fresh"))[0] == 0
    _, resumed = read_summary(out / "designs.csv")
    _, fresh = read_summary(tmp_path / "fresh" / "designs.csv")
    assert [r["evaluation"] for r in resumed] == [r["evaluation"] for r in fresh]
    for a, b in zip(resumed, fresh):
        assert float(a["x1"]) == pytest.approx(float(b["x1"]), abs=1e-12 * 0.4)


def test_a_second_search_on_the_same_out_is_refused(tmp_path, capsys):
    from kinetostatics.batch.table import _Lock

    out = tmp_path / "o"
    out.mkdir()
    held = _Lock(out)
    held.path = out / "optimize.lock"
    held.acquire()
    try:
        code, _, err = _cli(
            capsys, "--vary", "x1=-0.3:0.1", "--minimize", "y1", "--out", str(out), *SMALL
        )
    finally:
        held.release()
    assert code == 2
    assert "another search is writing to this folder" in _one_line(err)


def test_the_keywords_make_a_frozen_search_options_checked_before_any_design():
    """optimize's keywords as one record: frozen, its whole numbers checked against
    RANGES with the command's one line, the bar as long as the generations (maxiter + 1,
    the initial population) and the local steps."""
    import dataclasses

    o = opt.SearchOptions(popsize=0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.seed = 1
    with pytest.raises(opt.OptimizeError, match=r"^--popsize 0: must be from 1 to 1000$"):
        o.check()
    with pytest.raises(opt.OptimizeError, match=r"^--positions 0: must be from 1 to"):
        opt.SearchOptions(positions=0).check()
    assert opt.SearchOptions(maxiter=5, local_maxiter=7).steps == 13
    assert opt.SearchOptions(maxiter=5, polish=False).steps == 6
