"""The progress bars (tqdm) of ``batch`` and ``simulate``: shown on request, counting what
was done; absent otherwise (stderr is not a terminal under pytest)."""

import re

from kinetostatics.cli import main
from tests.helpers import ROOT

SLIDER = ROOT / "mechanisms" / "slider_crank.yaml"
PENDULUM = ROOT / "tests" / "dynamics" / "pendulum.yaml"


def test_batch_progress(tmp_path, capsys):
    # b = 350 mm rod: b = 50 cannot reach the guide (a + |e| = 120 > 50): one failure
    argv = ["batch", str(SLIDER), "--set", "b=340,350,50", "--workers", "1"]
    assert main([*argv, "--out", str(tmp_path / "a"), "--progress"]) == 0
    err = capsys.readouterr().err
    assert re.search(r"batch: 100%.*\b3/3\b", err), err
    assert "failed=1" in err
    assert main([*argv, "--out", str(tmp_path / "b")]) == 0
    assert "batch:" not in capsys.readouterr().err


def test_simulate_progress(tmp_path, capsys):
    argv = ["simulate", str(PENDULUM), "--until", "1", "--points", "11"]
    assert main([*argv, "--out", str(tmp_path), "--progress"]) == 0
    err = capsys.readouterr().err
    assert re.search(r"simulate: 100%.*\b1/1 s", err), err
    assert main([*argv, "--out", str(tmp_path)]) == 0
    assert "simulate:" not in capsys.readouterr().err
