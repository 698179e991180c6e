"""The command line: run writes the CSV and summary of docs/conventions.md; user errors
exit 2 with one line; run imports neither matplotlib nor scipy's solvers."""

import csv
import json
import subprocess
import sys

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main


def test_run_writes_csv_and_summary(tmp_path, capsys):
    assert main(["run", "mechanisms/slider_crank.yaml", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "stroke" in out and "peak reaction" in out and "with friction" in out
    lines = (tmp_path / "results.csv").read_text().splitlines()
    assert lines[0].startswith("# units: s,deg,deg,")
    header = next(csv.reader([lines[1]]))
    assert header[:3] == ["time", "angle", "travel"]
    for name in (
        "crank.x",
        "rod.theta",
        "slider.B.vx",
        "O.Fx",
        "slide.N",
        "slide.M",
        "A.friction_approx",
        "A.friction",
        "slide.N_friction",
        "motor.torque",
        "motor.torque_friction_approx",
        "motor.torque_friction",
        "motor.efficiency",
        "friction.status",
        "friction.iterations",
        "power.input",
        "power.kinetic",
        "power.potential",
        "power.external",
        "power.friction",
        "power.residual",
        "power.residual_friction",
        "rod_slider.cond",
        "rod_slider.pressure_angle",
    ):
        assert name in header, name
    assert len(lines) == 2 + 360
    r = ks.analyze(ks.load("mechanisms/slider_crank.yaml"))
    row = next(csv.reader([lines[2 + 37]]))
    for name in ("motor.torque", "B.Fy", "rod.alpha"):
        assert float(row[header.index(name)]) == r[name][37]  # written at full precision
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["outputs"]["slide"]["stroke"] == pytest.approx(np.ptp(r["slider.x"]), rel=1e-4)
    assert len(summary["events"]) == 2
    assert summary["column_units"]["motor.torque"] == "N*m"


def test_user_error_is_one_line_and_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text(
        (open("mechanisms/slider_crank.yaml").read()).replace(
            "links: [crank, rod]", "links: [crank, rood]"
        )
    )
    assert main(["check", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith(f"{bad}:") and "unknown link 'rood' (did you mean 'rod'?)" in err[0]


def test_run_imports_no_plotting_or_solvers(tmp_path):
    proc = subprocess.run(
        [
            sys.executable,
            "-X",
            "importtime",
            "-m",
            "kinetostatics.cli",
            "run",
            "mechanisms/slotting_machine.yaml",
            "--out",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    imported = {line.split("|")[-1].strip() for line in proc.stderr.splitlines() if "|" in line}
    assert "kinetostatics.analysis.pipeline" in imported  # the guard sees our imports
    for forbidden in ("matplotlib", "scipy.optimize", "scipy.integrate", "scipy.interpolate"):
        assert not any(m == forbidden or m.startswith(forbidden + ".") for m in imported), forbidden


def test_output_cut_short_by_the_reader_is_not_an_error():
    """`kinetostatics check FILE | head -1`: no traceback when the pipe closes early."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    cmd = [sys.executable, "-m", "kinetostatics.cli", "check", "mechanisms/jaw_crusher.yaml"]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=root)
    p.stdout.close()  # the reader goes away before anything is written
    err = p.stderr.read().decode()
    assert p.wait() == 0, err
    assert "Traceback" not in err and "Exception ignored" not in err, err


def test_python_dash_m_kinetostatics_is_the_command(tmp_path):
    """``python -m kinetostatics`` runs the command line (the package had no __main__)."""
    import os
    from pathlib import Path

    env = dict(os.environ, PYTHONPATH=str(Path(__file__).parents[2] / "src"))
    out = subprocess.run(
        [sys.executable, "-m", "kinetostatics", "--version"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0 and out.stdout.startswith("kinetostatics "), out


def test_a_picture_command_gives_the_collector_its_thresholds_back():
    """plot, animate and report run with fewer collections of the cyclic collector and
    give its thresholds back after them, also when they fail (a command may run inside
    a caller's process)."""
    import gc

    from kinetostatics.cli.pictures import COLLECTOR, _fewer_collections

    before = gc.get_threshold()
    assert _fewer_collections(lambda args: gc.get_threshold())(None) == COLLECTOR
    assert gc.get_threshold() == before

    def fails(args):
        raise ValueError("a user's mistake")

    with pytest.raises(ValueError):
        _fewer_collections(fails)(None)
    assert gc.get_threshold() == before


@pytest.mark.parametrize("command", ["plot", "run"])
def test_the_program_ends_without_walking_its_heap_and_a_caller_keeps_its_collector(
    tmp_path, command
):
    """As the process's own command (``main()``, argv from the command line) ``run`` or a
    picture command runs with fewer collections to its end and the heap is frozen before
    the process exits (the collections that would walk it then free nothing a process
    about to end needs); called with an argv, as by a caller's process, the collector is
    given back untouched and nothing is frozen."""
    import gc

    from kinetostatics.cli import COLLECTOR

    mech = "mechanisms/slider_crank.yaml"
    tail = {"plot": ["--sheet", "{}.dxf"], "run": ["--out", "{}"]}[command]
    argv = lambda name: [command, mech, *(a.format(tmp_path / name) for a in tail)]  # noqa: E731
    before, frozen = gc.get_threshold(), gc.get_freeze_count()
    assert main(argv("a")) == 0
    assert (gc.get_threshold(), gc.get_freeze_count()) == (before, frozen)
    code = (
        "import gc, sys\n"
        "from kinetostatics.cli import main\n"
        f"sys.argv = ['kinetostatics', *{argv('b')!r}]\n"
        "assert main() == 0\n"
        "print(gc.get_threshold(), gc.get_freeze_count() > 0)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    assert out.stdout.split("\n")[-2] == f"{COLLECTOR} True", out


def test_the_design_commands_keep_their_memory_as_the_program_only(monkeypatch):
    """``optimize``, ``batch`` and ``sensitivity`` ask for glibc's heap kept (MALLOC_KEPT);
    it is set for the process's own command alone, not where the user set a ``MALLOC_``
    variable, and never for a caller's ``main(argv)`` or another command."""
    import argparse
    import ctypes

    from kinetostatics import cli

    seen = []
    monkeypatch.setattr(cli, "_memory_kept", lambda args: seen.append(args))
    for command in (
        ["optimize", "--vary", "a=0:1", "--minimize", "a"],
        ["batch", "--out", "o"],
        ["sensitivity", "--vary", "a=±1", "--out", "o"],
    ):
        main([command[0], "no-such-file.yaml", *command[1:]])
    main(["run", "no-such-file.yaml"])
    assert [getattr(a, "keeps_memory", False) for a in seen] == [True, True, True, False]
    assert not any(a.program for a in seen)
    monkeypatch.undo()

    calls = []

    class _Libc:
        def mallopt(self, param, value):
            calls.append((param, value))

    monkeypatch.setattr(ctypes, "CDLL", lambda name: _Libc())
    for name in [k for k in __import__("os").environ if k.startswith("MALLOC_")]:
        monkeypatch.delenv(name)
    design = argparse.Namespace(program=True, keeps_memory=True)
    for args in (argparse.Namespace(program=False, keeps_memory=True),
                 argparse.Namespace(program=True)):  # fmt: skip
        cli._memory_kept(args)
    assert calls == []
    cli._memory_kept(design)
    assert calls == list(cli.MALLOC_KEPT)
    calls.clear()
    monkeypatch.setenv("MALLOC_ARENA_MAX", "2")  # the user's own settings
    cli._memory_kept(design)
    assert calls == []
