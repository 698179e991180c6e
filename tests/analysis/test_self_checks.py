"""Self-checks carried by every result (docs/theory.md, "Self-checks")."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics import ModelError
from kinetostatics.analysis.checks import COND_TOL, CONSTRAINT_TOL, POWER_TOL
from kinetostatics.cli import main
from kinetostatics.kinematics.positions import SKETCH_TOL
from kinetostatics.structure.system import build_system

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted((ROOT / "mechanisms").glob("*.yaml"))
SLIDER = ROOT / "mechanisms" / "slider_crank.yaml"


def _analysable(path: Path) -> bool:
    system = build_system(ks.load(path))
    return len(system.motion_drivers) == system.structure.mobility > 0


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_checks_pass_on_every_shipped_mechanism(path):
    if not _analysable(path):
        pytest.skip("simulated (fewer motion drivers than the mobility), not analysed")
    checks = ks.analyze(ks.load(path)).checks
    assert checks.ok, checks.warning()
    assert checks.failed() == []
    assert checks.constraints.value <= CONSTRAINT_TOL
    assert checks.sketch is not None and checks.sketch.value <= SKETCH_TOL
    assert checks.cond is not None and checks.cond.value <= COND_TOL
    if checks.power is not None:
        assert checks.power.value <= POWER_TOL


@pytest.fixture(scope="module")
def slider():
    return ks.analyze(ks.load(SLIDER))


def test_the_numbers_behind_the_checks(slider):
    c = slider.checks
    l_ref = slider.system.l_ref
    assert c.power.value == pytest.approx(
        np.max(np.abs(slider["power.residual"])) / np.max(np.abs(slider["power.input"]))
    )
    # B sketched at [440, -20] mm; assembled at crank 0 it is at a + sqrt(b² − e²)
    b_x = 0.1 + np.sqrt(0.35**2 - 0.02**2)
    assert c.sketch.value * l_ref == pytest.approx(abs(0.44 - b_x), rel=1e-9)
    assert c.sketch.to_dict()["point"] == "B"
    assert c.cond.value == pytest.approx(np.max(slider["rod_slider.cond"]))
    st = slider["friction.status"]
    assert c.friction_status == tuple(int(np.sum(st == s)) for s in range(4))
    assert sum(c.friction_status) == len(slider)


def test_a_corrupted_result_fails_the_constraint_check(slider):
    q = slider.q.copy()
    q[17, 3 * slider.system.link_index("rod")] += 1e-6  # the rod moved by 1 µm
    bad = dataclasses.replace(slider, q=q).checks
    assert not bad.ok
    assert [c.name for c in bad.failed()] == ["constraints"]
    assert bad.constraints.value == pytest.approx(1e-6 / slider.system.l_ref, rel=1e-6)
    assert bad.constraints.where == f"angle {slider['angle'][17]:.4g}°"
    assert "constraints" in bad.warning() and slider.checks.ok  # the original is untouched


def test_kinematics_only_has_no_power_or_friction_check():
    c = ks.analyze(ks.load(SLIDER), kinematics_only=True).checks
    assert c.power is None and c.friction is None and c.ok
    assert "power" not in c.line() and "constraints" in c.line()


def test_self_locking_fails_the_friction_check():
    c = ks.analyze(ks.load(ROOT / "tests" / "hard" / "slider_crank_self_locking.yaml")).checks
    assert c.friction_status[2] > 0
    assert [x.name for x in c.failed()] == ["friction"]
    assert c.power_friction.ok  # the rows that have a solution balance


def test_the_mirrored_jaw_crusher_is_refused_with_the_point_named():
    with pytest.raises(
        ModelError,
        match=r"jaw_crusher_mirrored\.yaml:78:3: sketch\.C: C is "
        r"assembled 5\d\d\.\d mm from its sketched position",
    ):
        ks.analyze(ks.load(ROOT / "tests" / "hard" / "jaw_crusher_mirrored.yaml"))


def test_run_prints_the_line_and_writes_the_section(tmp_path, capsys):
    assert main(["run", str(SLIDER), "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    line = [x for x in out.splitlines() if x.startswith("checks: ")]
    assert len(line) == 1 and err == ""
    for word in ("constraints", "power", "sketch", "(B)", "cond", "friction"):
        assert word in line[0]
    section = json.loads((tmp_path / "summary.json").read_text())["checks"]
    assert section["ok"] is True and section["failed"] == []
    for name in ("constraints", "power", "power_friction", "sketch", "cond", "friction"):
        assert section[name]["ok"] is True and section[name]["value"] <= section[name]["tolerance"]
    assert section["sketch"]["point"] == "B" and section["sketch"]["distance"] > 0
    assert sum(section["friction"]["status"].values()) == 360


def test_a_failed_check_is_a_warning_on_stderr_and_exit_0(tmp_path, capsys):
    path = ROOT / "tests" / "hard" / "slider_crank_self_locking.yaml"
    assert main(["run", str(path), "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "checks: " in out
    assert "kinetostatics: warning: self-check failed: friction" in err
    section = json.loads((tmp_path / "summary.json").read_text())["checks"]
    assert section["ok"] is False and section["failed"] == ["friction"]


def test_check_prints_the_start_pose_checks(capsys):
    assert main(["check", str(ROOT / "mechanisms" / "jaw_crusher.yaml")]) == 0
    out = capsys.readouterr().out
    line = [x for x in out.splitlines() if x.startswith("checks (start pose): ")]
    assert len(line) == 1 and "sketch" in line[0] and "(C)" in line[0] and "cond" in line[0]
