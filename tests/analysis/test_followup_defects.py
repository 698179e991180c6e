"""Regression tests for the follow-up defects: each fails on the code before its fix.

Expected values come from closed forms, power identities and geometry, not from
the program's own output."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics import flywheel
from tests.helpers import ROOT, variant

# -- 3. efficiency 0/0 ----------------------------------------------------------------------


def _massless_slider_crank():
    """The shipped slider-crank without masses and gravity: only the working-stroke
    resistance loads it, so on the return stroke both efforts are exactly 0."""
    return variant(
        "slider_crank",
        g=(r"gravity: \[0, -9.81\]", "gravity: [0, 0]"),
        m1=(r"mass: 2\n    inertia: 0.006", "mass: 0\n    inertia: 0"),
        m2=(r"mass: 3\n    inertia: 0.031", "mass: 0\n    inertia: 0"),
        m3=(r"mass: 4", "mass: 0"),
    )


def test_efficiency_undefined_where_no_effort_goes_through_the_drive():
    # 30°: the slider moves in −x (return stroke, x_B' = −a sin φ − ... < 0), nothing loads
    # the linkage: torque = torque_friction = 0 and η = 0/0 is undefined; 200°: working stroke
    r = ks.analyze(_massless_slider_crank(), positions=np.radians([30.0, 200.0]))
    assert r["motor.torque"][0] == 0.0 and r["motor.torque_friction"][0] == 0.0
    assert np.isnan(r["motor.efficiency"][0])
    eta = r["motor.torque"][1] / r["motor.torque_friction"][1]
    assert 0.0 < eta < 1.0 and r["motor.efficiency"][1] == pytest.approx(eta, rel=1e-15)
    fc = r.checks.friction
    assert dict(fc.detail)["efficiency_undefined"] == 1
    assert "efficiency undefined at 1" in r.checks.line()
    assert r.checks.ok  # counted, not a failure


# -- 4. flywheel delta ----------------------------------------------------------------------


@pytest.mark.parametrize("delta", [1.0, 1.5])
def test_flywheel_delta_below_one_as_in_a_file(delta):
    model = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    with pytest.raises(ValueError, match="delta"):
        flywheel.design(model, delta=delta)


# -- 7. batch rows: balance_at at a prismatic joint, self-locked zones ------------------------

SLIDER_DRIVEN = ROOT / "tests" / "hard" / "slider_crank_slider_driven.yaml"
A_SC, B_SC = 100.0, 350.0


def _locking_edge_deg(rho_o=1.5, rho_a=1.2, rho_b=1.0) -> float:
    """Upper edge of the friction-circle locked zone around crank 0° of the slider-driven
    slider-crank (closed form, see tests/kinetics/test_singular_rows.py); the lower is its
    negative."""
    g = np.arcsin((rho_o + rho_a) / A_SC) + np.arcsin((rho_a + rho_b) / B_SC)
    return float(np.degrees(np.arctan2(B_SC * np.sin(g), A_SC + B_SC * np.cos(g))))


def test_batch_row_of_a_slide_balanced_driver():
    from kinetostatics.batch.variants import summary_row

    text = SLIDER_DRIVEN.read_text().replace("positions: 360", "positions: 36")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = ks.analyze(ks.loads(text, file="slider_driven_36.yaml"))
    row = summary_row(r)
    # the effort is a force at the slide: its peak is the largest |force| of the rows
    assert row["motor.force_peak"] == pytest.approx(np.nanmax(np.abs(r["motor.force"])))
    assert row["motor.force_friction_peak"] == pytest.approx(
        np.nanmax(np.abs(r["motor.force_friction"]))
    )
    assert "motor.torque_peak" not in row
    # input work over the cycle by the slide: Σ F·ẋ_B (ẋ_B = the slider's vx)
    f, ff, v = r["motor.force"], r["motor.force_friction"], r["slider.vx"]
    both = np.isfinite(f) & np.isfinite(ff)
    assert row["motor.efficiency_cycle"] == pytest.approx(
        np.sum((f * v)[both]) / np.sum((ff * v)[both]), rel=1e-9
    )
    # the zones with located edges: one zone across 0° (closed form ±1.4835°), and the
    # dead centre at 180°, not grid rows
    e = _locking_edge_deg()
    zones = [
        tuple(float(x) for x in z.split("–")) for z in row["friction.self_locking"].split("; ")
    ]
    assert len(zones) == 2
    assert zones[0][0] == pytest.approx(360.0 - e, abs=1e-6)
    assert zones[0][1] == pytest.approx(e, abs=1e-6)
    # 180°: the dead centre and the rows where the slide's speed per unit crank speed,
    # ≈ a δ (1 − a/b)/L_ref (L_ref = b), is at most EFFORT_SPEED_TOL (no effort there)
    from kinetostatics.kinetics.reactions import EFFORT_SPEED_TOL

    half = np.degrees(EFFORT_SPEED_TOL * B_SC / (A_SC * (1 - A_SC / B_SC)))
    assert zones[1] == pytest.approx((180.0 - half, 180.0 + half), abs=1e-6)


# -- 6. a crank that cannot fully turn: its limit is a fold, not a change point ---------------


def _non_grashof_fourbar() -> ks.Model:
    """tests/hard/fourbar_change_point.yaml with coupler 2.4 (crank 1, ground 3, rocker 1.5):
    1 + 3 > 2.4 + 1.5, the crank stops where coupler and rocker stretch out in line."""
    text = (ROOT / "tests" / "hard" / "fourbar_change_point.yaml").read_text()
    text = text.replace("B: [2.5, 0]}, com: [1.25", "B: [2.4, 0]}, com: [1.2")
    return ks.loads(text, file="fourbar_limit.yaml")


def _limit_deg() -> float:
    """|OA − D|² = a² + d² − 2ad cos φ = (b + c)²  (a = 1, d = 3, b + c = 3.9)."""
    return float(np.degrees(np.arccos((1.0 + 9.0 - 3.9**2) / 6.0)))


def test_limit_position_reports_the_reachable_range():
    lim = _limit_deg()  # 150.2655°
    with pytest.raises(ks.AssemblyError) as info:
        ks.analyze(_non_grashof_fourbar())
    exc = info.value
    assert not isinstance(exc, ks.SingularConfigurationError)
    assert "reachable range" in str(exc) and "reachable=True" in str(exc)
    lo, hi = np.degrees(exc.reachable)
    assert hi == pytest.approx(lim, abs=1e-4)  # forwards from 90°
    assert lo == pytest.approx(-lim, abs=1e-4)  # backwards through 0°
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = ks.analyze(_non_grashof_fourbar(), reachable=True)
    span = 2 * lim
    assert (r["travel"][-1] - r["travel"][0]) == pytest.approx(span, rel=1e-5)
    assert r.checks.constraints.ok and r.checks.power.ok


# -- 5. positions behind the start of a crank that cannot turn fully --------------------------

ROCKER = ROOT / "tests" / "hard" / "crank_rocker_reversed.yaml"  # driven at the rocker D


def _crank_angle_deg(rocker_deg: float, near_deg: float) -> float:
    """The four-bar of crank_rocker_reversed.yaml driven at its rocker (O = 0, D = (3, 0),
    OA = 1, AB = 3.2, DB = 2.5): A is where the circles about O (1) and B (3.2) meet, the
    one nearer the crank angle ``near_deg`` (the sketch's branch, continued)."""
    b = np.array([3.0, 0.0]) + 2.5 * np.array(
        [np.cos(np.radians(rocker_deg)), np.sin(np.radians(rocker_deg))]
    )
    d = np.hypot(*b)
    base = np.arctan2(b[1], b[0])
    off = np.arccos((1.0 + d * d - 3.2**2) / (2.0 * d))
    cands = np.degrees([base + off, base - off])
    return float(min(cands, key=lambda c: abs((c - near_deg + 180.0) % 360.0 - 180.0)))


def test_positions_behind_the_start_of_a_rocker():
    model = ks.load(ROCKER)  # start 100°, CCW, swings between toggles
    r = ks.analyze(model, positions=np.radians([95.0, 100.0, 130.0, -265.0]))
    np.testing.assert_allclose(r["angle"], [95.0, 100.0, 130.0, 95.0], atol=1e-9)
    crank0 = _crank_angle_deg(100.0, 105.0)  # the sketch: A at (−0.45, 0.9)...
    start = ks.analyze(model, positions=np.radians([100.0]))["crank.theta"][0]
    assert start % 360.0 == pytest.approx(crank0 % 360.0, abs=1e-9)
    for row, rocker in ((0, 95.0), (2, 130.0), (3, 95.0)):
        # the branch continued from the start: the nearer intersection to the start's crank
        want = _crank_angle_deg(rocker, crank0)
        assert r["crank.theta"][row] % 360.0 == pytest.approx(want % 360.0, abs=1e-8)
    # the row 5° behind is reached running backwards: 5° at 30 rpm before the start
    assert r["time"][1] - r["time"][0] == pytest.approx(np.radians(5.0) / np.pi, rel=1e-12)
    assert r.checks.constraints.ok and r.checks.power.ok


def test_positions_out_of_reach_either_way_name_the_range():
    with pytest.raises(ks.AssemblyError, match="reachable range"):
        ks.analyze(ks.load(ROCKER), positions=np.radians([250.0]))


# -- 1. effort at a joint (nearly) at rest: flagged, or exact to the power balance ------------

JAW = ROOT / "mechanisms" / "jaw_crusher.yaml"
OMEGA_CRANK = 250.0 * np.pi / 30.0  # rad/s (the crank's -250 rpm)


@pytest.mark.parametrize("joint, link", [("O3", "rear"), ("O2", "jaw")])
def test_effort_at_a_pivot_where_the_jaw_reverses(joint, link):
    text = JAW.read_text().replace("balance_at: Om", f"balance_at: {joint}")
    model = ks.loads(text, file=f"jaw_crusher_{joint}.yaml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        coarse = ks.loads(text.replace("positions: 360", "positions: 12"), file="coarse.yaml")
        events = ks.analyze(coarse, friction=False).events
        reversal = [e.coordinate for e in events]  # the jaw's speed is zero there
        assert len(reversal) == 2
        rows = [
            c + d
            for c in reversal
            for d in (-1e-3, -1e-5, -1e-7, -1e-9, -1e-12, 0.0, 1e-12, 1e-9, 1e-7, 1e-5, 1e-3)
        ]
        r = ks.analyze(model, positions=rows)
    effort = r["motor.torque"]
    # the pivot's relative speed is the link's ω (the other link is the ground)
    ratio = np.abs(r[f"{link}.omega"]) / OMEGA_CRANK
    flagged = np.isnan(effort)
    assert flagged.any() and (~flagged).any()
    # every row whose pivot moves by more than 1e-7 of the crank is computed, the others
    # are flagged: NaN, a singular 'equilibrium' position, friction.status 2
    np.testing.assert_array_equal(flagged, ratio <= 1e-7)
    singular_t = sorted(s.t for s in r.singular if s.group == "equilibrium")
    np.testing.assert_allclose(singular_t, np.sort(r.t[flagged]), atol=1e-12)
    assert (r["friction.status"][flagged] == 2).all()
    # the power balance (virtual power, independent of the reactions' equations) on every
    # computed row: τ·ω_pivot = dT/dt + dV/dt + P_ext, to 1e-9 of the loads' power there
    scale = np.max(np.abs([r["power.kinetic"], r["power.potential"], r["power.external"]]), axis=0)
    tau_w = effort * r[f"{link}.omega"]
    balance = r["power.kinetic"] + r["power.potential"] + r["power.external"]
    ok = ~flagged
    assert np.all(np.abs(tau_w[ok] - balance[ok]) <= 1e-9 * scale[ok])
    assert r.checks.power.ok and r.checks.power_friction.ok


# -- 2. redundant constraints, friction and a non-square equilibrium ------------------------

PARALLELOGRAM = """
name: parallelogram with a redundant crank
units: {length: m, angle: deg, speed: rpm}
links:
  ground: {points: {O: [0, 0], D: [3, 0], E: [1.5, 0]}}
  crank: {points: {O: [0, 0], A: [1, 0]}, com: [0.5, 0], mass: 1, inertia: 0.1}
  coupler: {points: {A: [0, 0], B: [3, 0], F: [1.5, 0]}, com: [1.5, 0], mass: 2, inertia: 1.5}
  rocker: {points: {D: [0, 0], B: [1, 0]}, com: [0.5, 0], mass: 1, inertia: 0.1}
  crank2: {points: {E: [0, 0], F: [1, 0]}, com: [0.5, 0], mass: 1, inertia: 0.1}
joints:
  O: {type: revolute, links: [ground, crank], friction: {radius: 0.01}}
  A: {type: revolute, links: [crank, coupler], friction: {radius: 0.01}}
  B: {type: revolute, links: [coupler, rocker], friction: {radius: 0.01}}
  D: {type: revolute, links: [ground, rocker], friction: {radius: 0.01}}
  E: {type: revolute, links: [ground, crank2], friction: {radius: 0.01}}
  F: {type: revolute, links: [crank2, coupler], friction: {radius: 0.01}}
DRIVERS
sketch: {A: [0.7, 0.7], B: [3.7, 0.7], F: [2.2, 0.7]}
analysis: {start: 45, sweep: 360, positions: 12}
"""


def test_overconstrained_parallelogram_is_refused_clearly():
    # 4 moving links, 6 revolutes: Grübler–Kutzbach 3·4 − 2·6 = 0, yet it moves (the
    # third crank is parallel to the others)
    model = ks.loads(
        PARALLELOGRAM.replace("DRIVERS", "drivers:\n  motor: {joint: O, motion: {speed: 60}}"),
        file="parallelogram.yaml",
    )
    with pytest.raises(ks.StructureError, match="overconstrained.*redundant"):
        ks.analyze(model)


def test_redundant_joint_named_from_the_equilibrium_matrix():
    from kinetostatics.kinetics.inverse import redundant_joints
    from kinetostatics.kinetics.reactions import equilibrium_matrix
    from kinetostatics.structure.system import build_system, phi

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system = build_system(ks.loads(PARALLELOGRAM.replace("DRIVERS", ""), file="p.yaml"))
    c, s = np.cos(np.radians(40.0)), np.sin(np.radians(40.0))
    # the pose at crank 40° by geometry (centres of mass): cranks parallel, coupler level
    q = np.array(
        [
            0.5 * c,
            0.5 * s,
            np.radians(40.0),
            c + 1.5,
            s,
            0.0,
            3 + 0.5 * c,
            0.5 * s,
            np.radians(40.0),
            1.5 + 0.5 * c,
            0.5 * s,
            np.radians(40.0),
        ]
    )
    assert np.max(np.abs(phi(system, q, np.zeros(0), range(6)))) < 1e-15
    a = equilibrium_matrix(system, q)
    assert np.linalg.matrix_rank(a) == a.shape[1] - 1  # one redundant constraint
    assert redundant_joints(system, a) == ["F"]  # the last joint closing it


def test_friction_with_a_non_square_equilibrium_is_a_clear_error():
    from kinetostatics.analysis.pipeline import kinetics
    from kinetostatics.structure.system import build_system

    # the slider-crank with an applied torque instead of a prescribed motion: no unknown
    # effort, 9 equations for 8 reactions; friction needs the equilibrium solved
    text = (
        (ROOT / "mechanisms" / "slider_crank.yaml")
        .read_text()
        .replace("motor: {joint: O, motion: {speed: 300}}", "motor: {joint: O, effort: 10}")
    )
    system = build_system(ks.loads(text, file="slider_crank_effort.yaml"))
    ref = ks.analyze(
        ks.load(ROOT / "mechanisms" / "slider_crank.yaml"),
        positions=[0.3, 1.0],
        kinematics_only=True,
    )
    with pytest.raises(ks.StructureError, match="motion drivers as the mobility"):
        kinetics(
            system,
            ref.q,
            ref.qd,
            ref.qdd,
            ref.coordinate[:, None],
            ref_speed=10 * np.pi,
            friction=True,
        )
