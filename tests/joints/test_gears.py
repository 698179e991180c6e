"""Gear pair and rack-and-pinion: kinematic ratios, power, the tooth force.

Each check compares with independent truth: closed-form ratios, the pitch
point and line of action computed here from the positions alone, the moment
balance of a single link about its pivot, and power conservation.  The
interface contract (residual, Jacobian, γ, reaction, coordinate) of the
shipped instances is covered by ``test_joint_contract.py``; here the same
finite-difference checks run on the variants the shipped files do not use
(internal mesh, moving centres, the other flank).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.io import dump
from kinetostatics.joints import JOINT_TYPES
from kinetostatics.outputs.loading import loads
from tests.helpers import ROOT, rel_err
from tests.joints.test_joint_contract import _fd, _states

ALPHA = math.radians(20.0)


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _xy(r, name):
    return np.stack((r[f"{name}.x"], r[f"{name}.y"]), axis=-1)


def _v_of_point(r, link, p):
    """Velocity of the material point of ``link`` at global positions ``p``."""
    s, w = _xy(r, link), r[f"{link}.omega"]
    v = np.stack((r[f"{link}.vx"], r[f"{link}.vy"]), axis=-1)
    rel = p - s
    return v + w[:, None] * np.stack((-rel[:, 1], rel[:, 0]), axis=-1)


@pytest.fixture(scope="module")
def fivebar():
    model = ks.load(ROOT / "mechanisms" / "geared_fivebar.yaml")
    return model, ks.analyze(model)


@pytest.fixture(scope="module")
def rocker():
    model = ks.load(ROOT / "mechanisms" / "rack_rocker.yaml")
    return model, ks.analyze(model)


# -- small test mechanisms (not shipped) ---------------------------------------------
TRAIN = """
name: gear train
units: {{length: mm, angle: deg, speed: rpm, torque: N*m, inertia: kg*m^2}}
gravity: [0, 0]
links:
  ground: {{points: {{O1: [0, 0], O2: [{d}, 0]}}}}
  pinion: {{points: {{O1: [0, 0], T: [10, 0]}}, mass: 0.2, inertia: 1.0e-5}}
  wheel: {{points: {{O2: [0, 0], T: [10, 0]}}, mass: 0.9, inertia: 4.0e-4}}
joints:
  O1: {{type: revolute, links: [ground, pinion]}}
  O2: {{type: revolute, links: [ground, wheel]}}
  mesh:
    type: gear
    links: [pinion, wheel]
    centres: [O1, O2]
    teeth: [20, 45]
    module: 2
    mesh: {mesh}
    flank: {flank}
    phase: 10
    friction: {{efficiency: 0.97}}
drivers:
  motor: {{joint: O1, motion: {{speed: 300}}, points: [x, T]}}
loads:
  out: {{type: torque, link: wheel, value: {torque}}}
sketch: {{pinion.T: [10, 0]}}
analysis: {{start: 0, sweep: 720, positions: 48}}
"""

PLANETARY = """
name: planet on an arm
units: {{length: mm, angle: deg, speed: rpm, torque: N*m, inertia: kg*m^2}}
gravity: [0, -9.81]
links:
  ground: {{points: {{O: [0, 0]}}}}
  arm: {{points: {{O: [0, 0], P: [{arm}, 0]}}, com: [20, 0], mass: 0.5, inertia: 1.0e-4}}
  planet: {{points: {{P: [0, 0], T: [15, 0]}}, com: [2, 1], mass: 0.3, inertia: 3.0e-5}}
joints:
  O: {{type: revolute, links: [ground, arm]}}
  P: {{type: revolute, links: [arm, planet]}}
  mesh:
    type: gear
    links: [ground, planet]
    centres: [O, P]
    teeth: [{z_sun}, 20]
    module: 2
    mesh: {mesh}
    flank: ccw
    friction: {{coefficient: 0.06}}
drivers:
  motor: {{joint: O, motion: {{speed: 100}}}}
loads:
  drag: {{type: torque, link: planet, value: 0.5}}
sketch: {{P: [{arm}, 0], planet.T: [{tip}, 0]}}
analysis: {{start: 0, sweep: 360, positions: 36}}
"""


def train(mesh="external", flank="ccw", torque=2.0):
    d = 65 if mesh == "external" else 25
    return loads(TRAIN.format(d=d, mesh=mesh, flank=flank, torque=torque), file="train.yaml")


def planetary(mesh="internal"):
    """A planet (z = 20) on an arm, meshing with a fixed annulus (z = 60) or sun (z = 40)."""
    z_sun, arm = (60, 40) if mesh == "internal" else (40, 60)
    return loads(
        PLANETARY.format(z_sun=z_sun, arm=arm, tip=arm + 15, mesh=mesh), file="planetary.yaml"
    )


# -- structure ---------------------------------------------------------------------
@pytest.mark.parametrize(
    "name, group",
    [
        ("geared_fivebar", "1-link group {crank2} via O2, mesh"),
        ("rack_rocker", "1-link group {rocker} via O3, mesh"),
    ],
)
def test_check_counts_each_higher_pair_once(name, group, capsys):
    assert main(["check", str(ROOT / "mechanisms" / f"{name}.yaml")]) == 0
    out = capsys.readouterr().out
    assert "mobility (Grübler–Kutzbach): 1" in out
    assert "mobility (numerical, at the sketched pose): 1" in out
    assert group in out
    system = ks.build_system(ks.load(ROOT / "mechanisms" / f"{name}.yaml"))
    assert sum(j.n_eq for j in system.model.joints if j.kind in ("gear", "rack")) == 1


def test_both_types_are_registered_and_shipped():
    assert JOINT_TYPES["gear"].n_eq == JOINT_TYPES["rack"].n_eq == 1
    kinds = {j.kind for p in (ROOT / "mechanisms").glob("*.yaml") for j in ks.load(p).joints}
    assert {"gear", "rack"} <= kinds


# -- kinematic ratios ----------------------------------------------------------------
def test_geared_fivebar_cranks_counter_rotate_exactly(fivebar):
    _, r = fivebar
    # equal gears, external: θ2 − β = φ − (θ1 − β) with β = 0 and φ = 30°
    np.testing.assert_allclose(r["crank2.omega"] / r["crank1.omega"], -1.0, rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["crank2.alpha"], -r["crank1.alpha"], atol=1e-9)
    diff = (r["crank2.theta"] - (30.0 - r["crank1.theta"]) + 180.0) % 360.0 - 180.0
    np.testing.assert_allclose(diff, 0.0, atol=1e-9)


@pytest.mark.parametrize("mesh", ["external", "internal"])
def test_fixed_centre_ratio_is_minus_or_plus_r_i_over_r_j(mesh):
    r = ks.analyze(train(mesh), friction=False)
    ratio = (-1.0 if mesh == "external" else 1.0) * 20 / 45
    assert rel_err(r["wheel.omega"], ratio * r["pinion.omega"]) < 1e-13
    # positions over two pinion turns, through the tooth period of the wrapped row
    expect = 10.0 + ratio * r["pinion.theta"]
    diff = (r["wheel.theta"] - expect + 180.0) % 360.0 - 180.0
    np.testing.assert_allclose(diff, 0.0, atol=1e-9)


@pytest.mark.parametrize("mesh, ratio", [("internal", 1 - 60 / 20), ("external", 1 + 40 / 20)])
def test_moving_centres_planet_ratio(mesh, ratio):
    """A planet on an arm: the line of centres turns with the arm, a full turn."""
    r = ks.analyze(planetary(mesh))
    # ω_planet = ω_arm (1 ∓ R/r): r_j(ω_j − β̇) = ±R(0 − β̇), β̇ = ω_arm
    assert rel_err(r["planet.omega"], ratio * r["arm.omega"]) < 1e-12
    scale = np.max(np.abs(r["power.input"]))
    assert np.max(np.abs(r["power.residual"])) <= 1e-9 * scale
    assert np.max(np.abs(r["power.residual_friction"])) <= 1e-9 * scale


def test_rack_speed_is_r_omega(rocker):
    model, r = rocker
    radius = model.joint("mesh").r
    assert radius == pytest.approx(0.05)
    # the sector sits above the rack (ν = +1): v_rack = r·ω_rocker
    assert rel_err(r["rack.vx"], radius * r["rocker.omega"]) < 1e-13
    assert rel_err(r["rack.ax"], radius * r["rocker.alpha"]) < 1e-12
    # phase 0: the lever is horizontal when P0 (x of the pin B) is under O3 (x = 160 mm)
    np.testing.assert_allclose(
        np.radians(r["rocker.theta"]), (r["rack.B.x"] - 0.160) / radius, atol=1e-12
    )


def test_a_mesh_chosen_as_output_gives_its_rolling_travel(rocker):
    """``output_motion`` of a rack pair: the travel along the pitch line, whose rate is
    the rack's speed past the fixed sector (c = ½[s − ν r Δθ], s = u·(C − A): ċ = −v_rack)."""
    from kinetostatics.outputs import plotting as pl

    _, r = rocker
    out = pl.output_motion(r, "mesh")
    assert out["kind"] == "joint"
    assert out["series"][0][:2] == ("relative travel of mesh", "mm")
    assert rel_err(out["series"][1][2], -r["rack.vx"]) < 1e-13
    assert rel_err(out["series"][2][2], -r["rack.ax"]) < 1e-12
    fig = pl.motion_diagram(r, "mesh", dpi=30)
    assert "joint mesh" in fig._suptitle.get_text()


# -- power -------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["geared_fivebar", "rack_rocker"])
def test_power_balance_of_the_shipped_mechanisms(name, fivebar, rocker):
    _, r = fivebar if name == "geared_fivebar" else rocker
    scale = np.max(np.abs(r["power.input"]))
    assert np.max(np.abs(r["power.residual"])) <= 1e-9 * scale
    ok = r["friction.status"] != 2  # 3: a pin at rest, friction there is 0
    assert ok.all()
    assert np.max(np.abs(r["power.residual_friction"][ok])) <= 1e-9 * scale


def test_pitch_points_roll_and_the_tooth_force_does_no_net_work(fivebar):
    """Both gears' material points at the pitch point move together, so the
    tooth force's power on crank2 cancels its reaction's power on crank1."""
    model, r = fivebar
    o1, o2 = model.link("ground").points["O1"], model.link("ground").points["O2"]
    rad = model.joint("mesh").r_i
    e = (o2 - o1) / np.linalg.norm(o2 - o1)
    p = np.broadcast_to(o1 + rad * e, (len(r["angle"]), 2))
    vi, vj = _v_of_point(r, "crank1", p), _v_of_point(r, "crank2", p)
    speed = np.max(np.hypot(*vi.T))
    np.testing.assert_allclose(vj, vi, atol=1e-12 * speed)
    f = np.stack((r["mesh.Fx"], r["mesh.Fy"]), axis=-1)
    power_on_j, power_on_i = np.sum(f * vj, axis=-1), np.sum(-f * vi, axis=-1)
    assert np.max(np.abs(power_on_j)) > 1.0  # the mesh carries power
    assert np.max(np.abs(power_on_j + power_on_i)) <= 1e-12 * np.max(np.abs(power_on_j))


@pytest.mark.parametrize("flank, torque, expect", [("cw", 2.0, "eta"), ("ccw", -2.0, "1/eta")])
def test_mesh_efficiency_is_exact_in_either_direction_of_power_flow(flank, torque, expect):
    """No inertia loads (constant speed, centres of mass on the pivots) and no
    other friction: the motor sees exactly the mesh efficiency.  The wheel turns
    clockwise; resisting it, the pinion's teeth turn it clockwise (flank cw).
    With the load driving (torque along the wheel's rotation) the other flank
    is loaded and the motor brakes: 1/η."""
    r = ks.analyze(train("external", flank, torque))
    eta = 0.97
    assert (r["mesh.F"] > 0).all()
    ratio = r["motor.torque"] / r["motor.torque_friction"]
    np.testing.assert_allclose(ratio, eta if expect == "eta" else 1 / eta, rtol=1e-12)
    if expect == "eta":
        np.testing.assert_allclose(r["motor.efficiency"], eta, rtol=1e-12)
    else:  # the load drives the motor: no efficiency of the drive (docs/friction.md)
        assert np.isnan(r["motor.efficiency"]).all()
    scale = np.max(np.abs(r["power.input"]))
    assert np.max(np.abs(r["power.residual_friction"])) <= 1e-9 * scale
    # the loss: P_out (1/η − 1) when the motor drives, P_in (1 − η) when the load does
    out = np.abs(r["power.external"])
    np.testing.assert_allclose(
        r["power.friction"], out * (1 / eta - 1) if expect == "eta" else out * (1 - eta), rtol=1e-9
    )


# -- the tooth force along the line of action ---------------------------------------------
def test_gear_tooth_force_lies_on_the_line_of_action(fivebar):
    model, r = fivebar
    o1, o2 = model.link("ground").points["O1"], model.link("ground").points["O2"]
    joint = model.joint("mesh")
    ri, rj = joint.r_i, joint.r_j
    e = (o2 - o1) / np.linalg.norm(o2 - o1)
    p = o1 + ri * e  # pitch point
    f = np.stack((r["mesh.Fx"], r["mesh.Fy"]), axis=-1)
    mag = np.hypot(*f.T)
    np.testing.assert_allclose(mag, r["mesh.F"], rtol=1e-12)  # F is the tooth force
    assert (r["mesh.F"] > 0).all()  # the chosen flank carries the load
    u = f / mag[:, None]
    # the line through P along F is tangent to both base circles (radius r cos α) ...
    np.testing.assert_allclose(np.abs(_cross(u, p - o1)), ri * math.cos(ALPHA), rtol=1e-12)
    np.testing.assert_allclose(np.abs(_cross(u, p - o2)), rj * math.cos(ALPHA), rtol=1e-12)
    # ... inclined by α to the common tangent, pushing gear j away from gear i ...
    np.testing.assert_allclose(u @ e, math.sin(ALPHA), rtol=1e-12)
    # ... and turning crank2 clockwise (flank: cw)
    assert (_cross(p - o2, f) < 0).all()


def test_rack_tooth_force_lies_on_the_line_of_action(rocker):
    model, r = rocker
    o3 = model.link("ground").points["O3"]
    radius = model.joint("mesh").r
    p = o3 - radius * np.array([0.0, 1.0])  # below O3 on the horizontal pitch line
    f = np.stack((r["mesh.Fx"], r["mesh.Fy"]), axis=-1)
    assert (r["mesh.F"] > 0).all()
    np.testing.assert_allclose(np.hypot(*f.T), r["mesh.F"], rtol=1e-12)
    np.testing.assert_allclose(np.abs(f[:, 0]), r["mesh.F"] * math.cos(ALPHA), rtol=1e-12)
    # the radial component lifts the sector (pushes it away from the rack)
    np.testing.assert_allclose(f[:, 1], r["mesh.F"] * math.sin(ALPHA), rtol=1e-12)
    assert (_cross(p - o3, f) > 0).all()  # flank: ccw


def test_sector_moment_balance_with_the_tooth_force_at_the_pitch_point(rocker):
    """About O3 (its reaction passes through O3): tooth force at P + weight at D
    + gravity and d'Alembert loads of the sector = 0."""
    model, r = rocker
    link = model.link("rocker")
    o3 = model.link("ground").points["O3"]
    p = o3 - model.joint("mesh").r * np.array([0.0, 1.0])
    f = np.stack((r["mesh.Fx"], r["mesh.Fy"]), axis=-1)
    s, d = _xy(r, "rocker"), _xy(r, "rocker.D")
    a = np.stack((r["rocker.ax"], r["rocker.ay"]), axis=-1)
    body = link.mass * (model.gravity - a)
    moment = (
        _cross(p - o3, f)
        + _cross(d - o3, np.array([0.0, -100.0]))
        + _cross(s - o3, body)
        - link.inertia * r["rocker.alpha"]
    )
    assert np.max(np.abs(moment)) <= 1e-10 * np.max(np.abs(_cross(p - o3, f)))


def test_crank2_moment_balance_with_the_tooth_force_at_the_pitch_point(fivebar):
    model, r = fivebar
    link = model.link("crank2")
    o1, o2 = model.link("ground").points["O1"], model.link("ground").points["O2"]
    p = o1 + model.joint("mesh").r_i * (o2 - o1) / np.linalg.norm(o2 - o1)
    f = np.stack((r["mesh.Fx"], r["mesh.Fy"]), axis=-1)
    f_b = -np.stack((r["B.Fx"], r["B.Fy"]), axis=-1)  # B reports crank2 on coupler2
    s, b = _xy(r, "crank2"), _xy(r, "crank2.B")
    a = np.stack((r["crank2.ax"], r["crank2.ay"]), axis=-1)
    body = link.mass * (model.gravity - a)
    moment = (
        _cross(p - o2, f)
        + _cross(b - o2, f_b)
        + 12.0
        + _cross(s - o2, body)
        - link.inertia * r["crank2.alpha"]
    )
    assert np.max(np.abs(moment)) <= 1e-10 * np.max(np.abs(_cross(p - o2, f)))


# -- the interface on the variants the shipped files do not use ----------------------------
VARIANTS = {
    "internal, j annulus": lambda: train("internal").joint("mesh"),
    "external, cw": lambda: train("external", "cw").joint("mesh"),
    "internal, i annulus, moving": lambda: planetary("internal").joint("mesh"),
    "external, moving": lambda: planetary("external").joint("mesh"),
    "rack, cw, pinion below": lambda: ks.loads(
        (ROOT / "mechanisms" / "rack_rocker.yaml")
        .read_text()
        .replace("flank: ccw", "flank: cw")
        .replace("direction: [1, 0]}   #", "direction: [-1, 0]}   #"),
        file="r.yaml",
    ).joint("mesh"),
}


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_variant_jacobian_gamma_and_coordinate_match_finite_differences(name):
    joint = VARIANTS[name]()
    qi, qj, vi, vj = _states()
    ji, jj = joint.jacobian(qi, qj)
    fi, fj = _fd(joint.residual, qi, qj)
    np.testing.assert_allclose(ji, fi, atol=1e-7)
    np.testing.assert_allclose(jj, fj, atol=1e-7)
    h = 1e-6

    def phiq_qd(s):
        a, b = joint.jacobian(qi + s * vi, qj + s * vj)
        return np.einsum("...ij,...j->...i", a, vi) + np.einsum("...ij,...j->...i", b, vj)

    np.testing.assert_allclose(
        joint.acceleration_rhs(qi, qj, vi, vj), -(phiq_qd(h) - phiq_qd(-h)) / (2 * h), atol=1e-6
    )
    gi, gj = joint.motion_direction(qi, qj)
    ci, cj = _fd(lambda a, b: joint.coordinate(a, b)[..., None], qi, qj)
    np.testing.assert_allclose(gi, ci[..., 0, :], atol=1e-7)
    np.testing.assert_allclose(gj, cj[..., 0, :], atol=1e-7)
    lam = np.random.default_rng(3).normal(size=qi.shape[:-1] + (1,))
    reac = joint.reaction(lam, qi, qj)
    np.testing.assert_allclose(
        np.einsum("...ij,...i->...j", jj, lam)[..., :2],
        np.stack((reac["Fx"], reac["Fy"]), axis=-1),
        atol=1e-12,
    )


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_residual_is_a_function_of_the_poses(name):
    """A full turn of either link leaves Φ unchanged (the row is wrapped to its tooth period)."""
    joint = VARIANTS[name]()
    qi, qj, _, _ = _states()
    turn = np.array([0.0, 0.0, 2 * np.pi])
    base = joint.residual(qi, qj)
    for a, b in ((qi + turn, qj), (qi, qj + turn), (qi - turn, qj + 3 * turn)):
        np.testing.assert_allclose(joint.residual(a, b), base, atol=1e-12)


def test_variants_round_trip_through_yaml():
    for make in (lambda: train("internal", "cw"), lambda: planetary("external")):
        model = make()
        again = loads(dump(model))
        a, b = model.joint("mesh"), again.joint("mesh")
        assert (a.teeth, a.internal, a.flank, a.centre_names) == (
            b.teeth,
            b.internal,
            b.flank,
            b.centre_names,
        )
        for name in ("r_i", "r_j", "alpha", "phase", "loss"):
            assert getattr(a, name) == pytest.approx(getattr(b, name), rel=1e-14)


# -- YAML errors --------------------------------------------------------------------------
@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            "teeth: [20, 45]",
            "teeth: [20, 45.5]",
            "mesh.teeth[1]: a number of teeth must be a whole number",
        ),
        ("module: 2", "module: 2\n    radii: [20, 45]", "mesh.module: give either the pitch radii"),
        (
            "module: 2",
            "radii: [20, 40]",
            "mesh.radii: the pitch radii must be in the ratio of the teeth",
        ),
        ("mesh: external", "mesh: outer", "mesh.mesh: mesh must be external or internal"),
        ("flank: ccw", "flank: left", "mesh.flank: flank must be ccw or cw"),
        (
            "centres: [O1, O2]",
            "centres: [O1, O3]",
            "mesh.centres[1]: unknown point 'O3' on link 'wheel'",
        ),
        (
            "efficiency: 0.97",
            "efficiency: 1.2",
            "mesh.friction.efficiency: a mesh efficiency must be in",
        ),
    ],
)
def test_yaml_errors_name_the_key(old, new, message):
    text = TRAIN.format(d=65, mesh="external", flank="ccw", torque=2.0)
    assert old in text
    with pytest.raises(ks.ModelError) as info:
        loads(text.replace(old, new), file="train.yaml")
    assert message in str(info.value)
    assert str(info.value).startswith("train.yaml:")


# -- docs/extending.md shows what check prints ----------------------------------------------
@pytest.mark.parametrize("name", ["geared_fivebar", "rack_rocker"])
def test_extending_doc_shows_the_check_output(name, capsys):
    doc = (ROOT / "docs" / "extending.md").read_text(encoding="utf-8")
    assert main(["check", str(ROOT / "mechanisms" / f"{name}.yaml")]) == 0
    out = capsys.readouterr().out
    assert f"```text\n{out}```" in doc
