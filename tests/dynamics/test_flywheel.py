"""Flywheel sizing for the slotting machine (docs/validation.md, "The reference
machines"; δ = 0.04) and its check by simulation; the numbers in docs/dynamics.md
are the script's."""

import json
import subprocess
import sys

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics.flywheel import design, verify
from kinetostatics.dynamics.stages import full_summary
from tests.helpers import ROOT

SLOTTING = ROOT / "mechanisms" / "slotting_machine.yaml"


@pytest.fixture(scope="module")
def machine():
    model = ks.load(SLOTTING)
    return model, design(model, ratio=24)


def test_flywheel_inertia_with_its_assumptions(machine):
    model, fw = machine
    assert model.flywheel.delta == 0.04 and fw.delta == 0.04
    # the cutting force does the only net work: 1000 N over 0.9 H = 90 mm
    assert fw.work_per_cycle == pytest.approx(90.0, rel=1e-6)
    assert fw.mean_torque == pytest.approx(90.0 / (2 * np.pi), rel=1e-6)
    assert fw.omega_m == pytest.approx(2 * np.pi) and fw.sense == -1.0
    assert fw.inertia == pytest.approx(fw.energy_swing / (fw.omega_m**2 * 0.04), rel=1e-12)
    assert fw.inertia_net == pytest.approx(fw.inertia - fw.machine_inertia["mean"], rel=1e-12)
    assert fw.motor_inertia == pytest.approx(fw.inertia / 24**2)
    assert 0 < fw.machine_inertia["mean"] < 0.01 * fw.inertia
    assert fw.machine_inertia["min"] == pytest.approx(0.0, abs=1e-9)  # links at rest at the limits
    # the maximum stored energy is where cutting starts (the moment jumps there)
    cut_on = next(e.coordinate for e in ks.analyze(model).events if e.switch == "on")
    assert (np.degrees(fw.at_max - cut_on) + 180) % 360 - 180 == pytest.approx(0.0, abs=1e-4)
    assert any("constant" in a for a in fw.assumptions) and len(fw.assumptions) >= 4
    coarse = design(model, positions=1800)  # the pictures' grid: no part of the numbers
    assert coarse.energy_swing == fw.energy_swing
    assert 30 < fw.energy_swing < 40 and 18 < fw.inertia < 25


def test_energy_swing_is_the_integral_between_the_extremes_by_adaptive_quadrature(machine):
    """ΔW_max = |∫ ω (M_d − M_b) dt| from the minimum to the maximum of stored energy, by
    scipy's adaptive quadrature calling the pipeline one crank angle at a time (breakpoints
    at the load events): independent of the design's piecewise Gauss–Legendre sums.  At an
    extreme M_b crosses M_d, or a load switches."""
    from scipy.integrate import quad

    from kinetostatics.dynamics.flywheel import _moment
    from kinetostatics.kinematics.schedule import schedule

    model, fw = machine
    system = fw.system
    sched = schedule(system)
    period = 2 * np.pi / fw.omega_m

    def time_of(psi):
        return float(np.mod((psi - sched.start[0]) / sched.speed[0], period))

    def rate(t):
        r = ks.analyze(system, times=np.array([t]), friction=False, events=False)
        return fw.omega_m * (fw.mean_torque - _moment(system, r, False)[0][0])

    a, b = sorted((time_of(fw.at_min), time_of(fw.at_max)))
    events = [time_of(e) for e in fw.events]
    inside = [t for t in events if a < t < b]
    value, _ = quad(rate, a, b, points=inside or None, epsabs=1e-12, epsrel=1e-13, limit=200)
    assert abs(value) == pytest.approx(fw.energy_swing, rel=1e-12)
    for t in (a, b):
        at_event = min(abs(t - te) for te in events) < 1e-9 * period
        assert at_event or abs(rate(t)) < 1e-9 * fw.omega_m * abs(fw.mean_torque)


def test_energy_swing_agrees_with_the_equivalent_torque_form(machine):
    """ΔW from the balancing moment = ΔW of the applied loads − ½ ΔJ_e ω_m² (the link
    inertia torques at constant speed are the derivative of ½ J_e ω_m²)."""
    model, fw = machine
    c = fw.curve
    from kinetostatics.dynamics import equivalent

    r = c["result"]
    eq = equivalent(r.system, r.q, r.coordinate, speed=-fw.omega_m, extremes=r.extremes)
    phi = c["travel"]
    applied = fw.sense * eq["torque"]  # the loads' moment in the sense of motion
    x = np.append(phi, phi[0] + 2 * np.pi)
    f = np.append(fw.mean_torque + applied, fw.mean_torque + applied[0])
    w_applied = np.concatenate(([0.0], np.cumsum(0.5 * np.diff(x) * (f[:-1] + f[1:]))))
    je = np.append(eq["inertia"], eq["inertia"][0])
    stored = w_applied - 0.5 * (je - je[0]) * fw.omega_m**2
    assert np.ptp(stored) == pytest.approx(fw.energy_swing, rel=1e-4)  # a trapezoid rule


def test_simulated_speed_fluctuation_under_the_mean_torque(machine):
    model, fw = machine
    check = verify(model, fw)  # from max stored energy at ω_m, one cycle
    assert check["delta"] == pytest.approx(0.04, rel=0.10)
    last = check["last_cycle"]
    assert last["omega_max"] == pytest.approx(fw.omega_m, rel=1e-6)  # it started there
    # started at ω_m(1 + δ/2) instead, the mean speed is ω_m and δ comes closer
    check = verify(model, fw, speed=fw.omega_m * 1.02)
    assert check["delta"] == pytest.approx(0.04, rel=0.02)
    assert check["last_cycle"]["omega_mean"] == pytest.approx(fw.omega_m, rel=5e-3)


def test_run_reports_the_flywheel(tmp_path, capsys):
    from kinetostatics.cli import main

    assert main(["run", str(SLOTTING), "--out", str(tmp_path)]) == 0
    assert "flywheel for delta = 0.04: J_F = " in capsys.readouterr().out
    fw = json.loads((tmp_path / "summary.json").read_text())["flywheel"]
    assert fw["inertia"]["crank"] == pytest.approx(design(ks.load(SLOTTING)).inertia)
    assert fw["assumptions"] and fw["units"]["inertia"] == "kg*m^2"
    ks.loads(
        SLOTTING.read_text().replace(
            "flywheel: {delta: 0.04}", "flywheel: {delta: 0.04, ratio: 24, friction: true}"
        )
    )
    with pytest.raises(ks.ModelError, match="flywheel.delta: must be positive"):
        ks.loads(SLOTTING.read_text().replace("delta: 0.04", "delta: 0"), file="s.yaml")


def test_docs_show_the_script_numbers():
    out = subprocess.run(
        [sys.executable, str(ROOT / "docs/scripts/dynamics_values.py"), "--design"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert out.strip() and out.strip() in (ROOT / "docs/dynamics.md").read_text()


def test_the_fine_grid_rule_serves_where_the_exact_pieces_cannot(machine, monkeypatch):
    """Where a node lacks the moment (a self-locked zone with friction) the design falls back
    on the trapezoid rule over its 3600-position curve: the same design to that rule's
    error (~3e-7), not a crash."""
    from kinetostatics.dynamics import flywheel as F

    model, fw = machine
    real = F._moment

    def missing_one(system, r, friction):
        m, je = real(system, r, friction)
        return (np.where(np.arange(len(m)) == 5, np.nan, m), je) if len(m) < 3000 else (m, je)

    monkeypatch.setattr(F, "_moment", missing_one)
    grid = F.design(model, ratio=24)
    monkeypatch.setattr(F, "_moment", real)
    assert grid.energy_swing == pytest.approx(fw.energy_swing, rel=1e-6)
    assert (np.degrees(grid.at_max - fw.at_max) + 180) % 360 - 180 == pytest.approx(0, abs=1e-3)
    assert grid.machine_inertia["mean"] == pytest.approx(fw.machine_inertia["mean"], rel=1e-6)


def test_a_flywheel_with_friction_on_a_self_locking_machine_is_said_undefined(monkeypatch):
    """A slide with a friction coefficient of 120 (a fuzz case) self-locks over part of the
    cycle: the balancing moment with friction does not exist there, so neither does the
    energy over the cycle.  The design says why (and `run` prints it) instead of spending
    20 s on a 3600-position grid of friction homotopies to return NaN."""
    from kinetostatics.dynamics import flywheel as F

    def no_grid(*args, **kw):
        raise AssertionError("the fine grid was analysed")

    monkeypatch.setattr(F, "_on_the_grid", no_grid)
    r = ks.analyze(ks.load(ROOT / "tests" / "cases" / "flywheel_friction_self_locked.yaml"))
    assert (np.asarray(r["friction.status"]) == 2).any()  # self-locked rows
    fw = F.design(r)
    assert fw.friction and fw.undefined == F.SELF_LOCKED
    assert np.isnan(fw.energy_swing) and np.isnan(fw.inertia)
    d = fw.to_dict()
    assert d["undefined"] == F.SELF_LOCKED and np.isnan(d["max_energy_at"])


def test_two_equal_extremes_of_the_energy_report_the_first():
    """A load torque of period 180° (a triangle +1000, −1000 N·m per half turn) on a crank
    whose centre of mass is its pivot: M_b = −T, M_d = 0 and ΔW(φ) = ∫T dφ has two equal
    maxima (90°, 270°) and minima (0°, 180°) by symmetry. Round-off chose between them
    (37 rows: the least at 180°); a tie within 1e-9 of ΔW_max reports the first of the
    cycle, whatever the rows and the units."""
    text = (
        "units: {length: UNIT, angle: deg, speed: rpm, mass: kg, force: N, torque: N*m}\n"
        "links: {ground: {points: {O: [0, 0]}}, crank: {points: {O: [0, 0], A: [L, 0]},"
        " inertia: 10}}\n"
        "joints: {O: {type: revolute, links: [ground, crank]}}\n"
        "drivers: {motor: {joint: O, motion: {speed: 60}, points: [x, A]}}\n"
        "loads: {T: {type: torque, link: crank, table: {at: [0, 45, 90, 135, 180, 225, 270,"
        " 315, 360], value: [0, 1000, 0, -1000, 0, 1000, 0, -1000, 0]}}}\n"
        "flywheel: {delta: 0.05}\n"
        "sketch: {crank.A: [L, 0]}\n"
        "analysis: {positions: N}\n"
    )
    for unit, length in (("m", "1"), ("mm", "1000")):
        for n in (36, 37, 360):
            doc = text.replace("UNIT", unit).replace("L", length).replace("N}", f"{n}}}")
            fw = full_summary(ks.analyze(ks.loads(doc)))["flywheel"]
            assert abs(fw["max_energy_at"] - 90.0) < 1e-9, (unit, n, fw["max_energy_at"])
            assert abs(fw["min_energy_at"] - 0.0) < 1e-9, (unit, n, fw["min_energy_at"])


def test_a_tie_reports_the_first_place_and_the_extreme_value():
    """Seed 1008810: ΔW's minimum lies 2.2e-6 s after a piece's start, 2.6e-9 J below the
    start's value — a tie within 1e-9 of the swing, so the start is the place reported; its
    value was reported too, and 16 nodes (which put a piece's start there) gave a swing
    7.5e-11 of 2π·scale off 8 nodes' and 32 nodes'.  The swing is now from the extreme
    values, tie or not: the orders agree to round-off."""
    import yaml

    from tests.net import relations as R

    path = ROOT / "tests" / "net" / "cases" / "tie_inside_a_piece.yaml"
    doc = yaml.safe_load(path.read_text(encoding="utf-8"))
    assert R.relation_cycle_means(doc, 0) <= 1e-12
