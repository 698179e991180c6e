"""Travel bands are measured from the extreme over the whole motion, whatever rows an
analysis asks for (a partial run used to drop the slotting machine's cutting force), and
``dynamics.equivalent`` called as docs/dynamics.md shows (no ``extremes=``) works on a
model with a travel band.

Expected values are closed forms of the geometry, not the program's output:

* slotting machine (docs/validation.md, "The reference machines"): O3 at the origin,
  O2 at (−150, 0) mm, O2A = 75,
  O3B = BC = 100, ram line x = X = 93.30 mm.  B lies on the bar opposite A through O3,
  so y_C(φ) = y_B + √(BC² − (X − x_B)²); the ram's top is at the bar's extreme position
  (crank ⟂ bar, bar at 30°): y_top = 50 + √(100² − (X − 100 cos 30°)²) mm.  The cutting
  force Q = 1000 N acts while the ram moves down with y_top − y ∈ [0.05H, 0.95H]; by
  virtual power it adds Q|v_y|/ω = −Q|dy_C/dφ| (ω < 0) to the frictionless motor torque;
* a four-bar driven at its rocker (D at (3, 0), DB = 2.5; crank 1, coupler 3.2): the
  rocker angle θ is the driver coordinate, y_B = 2.5 sin θ, and the rocker reaches
  |OB| = 4.2 and 2.2 (toggles) at cos θ = (|OB|² − 15.25)/15.  A torque M on the rocker
  itself changes the motor torque by −M exactly.
"""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics import equivalent

ROOT = Path(__file__).resolve().parents[2]
Q, H = 1000.0, 0.100
X = 0.1 * (1 + np.cos(np.radians(30))) / 2
Y_TOP = 0.05 + np.sqrt(0.1**2 - (X - 0.1 * np.cos(np.radians(30))) ** 2)
L_REF = float(ks.build_system(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")).l_ref)


def ram_y(phi):
    ax, ay = -0.150 + 0.075 * np.cos(phi), 0.075 * np.sin(phi)
    beta = np.arctan2(ay, ax) + np.pi
    xb, yb = 0.1 * np.cos(beta), 0.1 * np.sin(beta)
    return yb + np.sqrt(0.1**2 - (X - xb) ** 2)


def cutting_torque(phi):
    """The cutting force's share of the motor torque at crank angles ``phi`` (ω < 0)."""
    h = 1e-6
    dy = (ram_y(phi + h) - ram_y(phi - h)) / (2 * h)  # dy_C/dφ
    down = dy > 0  # φ decreases: y falls if dy/dφ > 0
    travel = Y_TOP - ram_y(phi)
    edge = 1e-9 * L_REF  # bands are closed, to 1e-9 L_ref (docs/yaml.md): event rows
    on = down & (travel >= 0.05 * H - edge) & (travel <= 0.95 * H + edge)  # at an edge are in
    return np.where(on, -Q * np.abs(dy), 0.0), on


@pytest.fixture(scope="module")
def slotting():
    model = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    idle = replace(model, loads=tuple(ld for ld in model.loads if ld.name != "cutting"))
    return model, idle


def test_ram_top_from_geometry(slotting):
    model, _ = slotting
    r = ks.analyze(model, positions=np.radians([210.0]))
    (top,) = r.extremes.values()
    assert -top == pytest.approx(Y_TOP, rel=1e-12)


def test_one_position_keeps_the_cutting_force(slotting):
    """At 210° the ram is 32.7 mm below its top and moving down: cutting (it read +3.47
    N·m, the idle torque, when the top was looked for at 210° only)."""
    model, idle = slotting
    phi = np.radians([210.0])
    extra, on = cutting_torque(phi)
    assert on.all()
    r = ks.analyze(model, positions=phi, friction=False)
    r0 = ks.analyze(idle, positions=phi, friction=False)
    np.testing.assert_allclose(r["motor.torque"] - r0["motor.torque"], extra, rtol=1e-8)
    assert r["motor.torque"][0] < -20.0


def test_a_short_sweep_keeps_the_cutting_force(slotting):
    """start 95°, sweep 10°, 5 positions (clockwise: 95…87°): cutting until the band's
    end near 88.6°, none at 87°."""
    model, idle = slotting
    a = replace(model.analysis, start=np.radians(95.0), sweep=np.radians(10.0), positions=5)
    r = ks.analyze(replace(model, analysis=a), friction=False)
    r0 = ks.analyze(replace(idle, analysis=a), friction=False)
    extra, on = cutting_torque(r.coordinate)
    assert list(on) == [True, True, True, True, False]
    np.testing.assert_allclose(
        r["motor.torque"] - r0["motor.torque"], extra, rtol=1e-8, atol=1e-9 * Q * 0.1
    )
    off = [e for e in r.events if e.switch == "off"]
    assert len(off) == 1 and Y_TOP - ram_y(off[0].coordinate) == pytest.approx(0.95 * H, rel=1e-9)


def test_at_rows_keep_the_cutting_force(slotting):
    model, idle = slotting
    at = tuple(np.radians([210.0, 100.0, 20.0]))
    a = replace(model.analysis, start=np.radians(200.0), sweep=np.radians(20.0), positions=2, at=at)
    r = ks.analyze(replace(model, analysis=a), friction=False)
    r0 = ks.analyze(replace(idle, analysis=a), friction=False)
    extra, on = cutting_torque(r.coordinate)
    assert on.sum() == 4  # all but 20°
    np.testing.assert_allclose(
        r["motor.torque"] - r0["motor.torque"], extra, rtol=1e-8, atol=1e-9 * Q * 0.1
    )


def test_equivalent_as_documented(slotting):
    """``equivalent(system, q, ψ, speed=…)`` without ``extremes=`` (it raised KeyError);
    its load torque, the loads' power over ψ̇, gains +Q|dy_C/dφ| where the tool cuts (the
    cutting share of the motor torque with the opposite sign)."""
    model, idle = slotting
    phi = np.radians([210.0, 150.0, 30.0, 100.0])
    w = -2 * np.pi
    out = {}
    for m in (model, idle):
        system = ks.build_system(m)
        r = ks.analyze(system, positions=phi, friction=False)
        out[m is model] = equivalent(system, r.q, r.coordinate, speed=w)
    extra, on = cutting_torque(phi)
    assert on.tolist() == [True, True, False, True]
    np.testing.assert_allclose(
        out[True]["torque"] - out[False]["torque"], -extra, rtol=1e-8, atol=1e-9 * Q * 0.1
    )
    np.testing.assert_allclose(out[True]["inertia"], out[False]["inertia"], rtol=1e-12)


ROCKER_LOADS = """
loads:
  low:                   # rocker.B within [0.3, 0.4] m above its lowest point
    type: torque
    link: rocker
    value: -5
    active: [{travel: [0.3, 0.4], along: [0, 1], point: rocker.B}]
  high:                  # rocker.B within [0.02, 0.1] m below its highest point
    type: torque
    link: rocker
    value: 3
    active: [{travel: [0.02, 0.1], along: [0, -1], point: rocker.B}]
"""


def _rocker(tmp_path, name):
    text = (ROOT / "tests" / "hard" / name).read_text(encoding="utf-8")
    path = tmp_path / name
    if "\nloads:\n" in text:
        text = text.replace("\nloads:\n", ROCKER_LOADS, 1)
    else:
        text = text.replace("\nsketch:", ROCKER_LOADS + "sketch:", 1)
    path.write_text(text, encoding="utf-8")
    model = ks.load(path)
    return model, replace(
        model, loads=tuple(ld for ld in model.loads if ld.name not in ("low", "high"))
    )


def _rocker_expected(theta, y_min):
    y = 2.5 * np.sin(theta)
    low = (y - y_min >= 0.3) & (y - y_min <= 0.4)
    high = (2.5 - y >= 0.02) & (2.5 - y <= 0.1)
    return -(-5.0 * low + 3.0 * high), low, high


def test_rocker_that_cannot_turn_measures_from_its_reachable_range(tmp_path):
    """Constant speed at the rocker: the whole motion is the reachable range between the
    toggles; the lowest B is at the toggle |OB| = 2.2, the highest at θ = 90°."""
    model, bare = _rocker(tmp_path, "crank_rocker_reversed.yaml")
    theta_hi = np.arccos((2.2**2 - 15.25) / 15)
    y_min = 2.5 * np.sin(theta_hi)
    theta = np.radians([100.0, 104.0, 112.0, 120.0, 125.0, 130.0])  # forward from the start
    r = ks.analyze(model, positions=theta, friction=False)
    r0 = ks.analyze(bare, positions=theta, friction=False)
    ext = sorted(r.extremes.values())
    assert ext[0] == pytest.approx(-2.5, rel=1e-12)
    assert ext[1] == pytest.approx(y_min, abs=1e-5)  # at a limit, within its margin
    extra, low, high = _rocker_expected(theta, y_min)
    assert low.tolist() == [False, False, False, True, False, False]
    assert high.tolist() == [True, True, False, False, False, False]
    np.testing.assert_allclose(r["motor.torque"] - r0["motor.torque"], extra, atol=1e-9)
    whole = ks.analyze(model, reachable=True, friction=False)
    assert sorted(whole.extremes.values()) == ext


def test_motion_law_measures_from_its_whole_run(tmp_path):
    """A harmonic law at the rocker, θ from the toggle (|OB| = 4.2) to toggle + 40°: the
    whole motion is one period; B is lowest at the law's turning point θ = toggle + 40°
    and highest at θ = 90°.  ``times=`` rows agree with the default run."""
    model, bare = _rocker(tmp_path, "rocker_into_toggle.yaml")
    toggle = np.arccos((4.2**2 - 15.25) / 15)
    y_min = 2.5 * np.sin(toggle + np.radians(40.0))
    t = np.array([1.05, 1.1, 1.3, 1.4, 1.7])  # the return half only: θ < 98°
    r = ks.analyze(model, times=t, friction=False)
    r0 = ks.analyze(bare, times=t, friction=False)
    ext = sorted(r.extremes.values())
    assert ext == pytest.approx([-2.5, y_min], rel=1e-12)
    extra, low, high = _rocker_expected(r.coordinate, y_min)
    assert low.all()
    assert high.tolist() == [True, False, False, True, False]
    np.testing.assert_allclose(r["motor.torque"] - r0["motor.torque"], extra, atol=1e-9)
    full = ks.analyze(model, friction=False)
    assert sorted(full.extremes.values()) == ext


def test_times_over_several_turns(slotting):
    """``times=`` beyond one turn (60 rpm clockwise from 300°: ψ = 300° − 360°·t/s):
    the cutting force where the closed form says, and every switch of the 2.4 turns
    between the first and the last row listed, each at its band edge."""
    model, idle = slotting
    t = np.array([0.1, 1.2, 1.9, 2.5])
    r = ks.analyze(model, times=t, events=True, friction=False)
    phi = np.radians(300.0 - 360.0 * r.t)
    r0 = ks.analyze(idle, times=r.t, friction=False)
    extra, on = cutting_torque(phi)
    assert on.any() and not on.all()
    np.testing.assert_allclose(
        r["motor.torque"] - r0["motor.torque"], extra, rtol=1e-8, atol=1e-9 * Q * 0.1
    )
    switches = [(e.condition, e.switch) for e in r.events]
    assert switches == [("travel to", "off"), ("travel from", "on")] * 2
    for e in r.events:
        edge = 0.95 * H if e.switch == "off" else 0.05 * H
        assert Y_TOP - ram_y(e.coordinate) == pytest.approx(edge, rel=1e-9)
        assert 0.1 < e.t < 2.5
    theta = r["crank.theta"]
    assert np.all(np.diff(theta) < 0)  # unwrapped along the run
    np.testing.assert_allclose(np.diff(theta) / np.diff(r.t), -360.0, rtol=1e-9)
