"""The links read as beams (sizing/beams.py, sizing/loads.py) against the closed forms of
a beam under a linearly distributed inertia load and its end forces, and against a
numerical integration of the distributed load written here; the invariants at the pins on
the shipped file with sizing data."""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.sizing import sizing_stage
from kinetostatics.sizing.beams import beam_forces
from kinetostatics.sizing.loads import beam_loads
from tests.helpers import ROOT

A, B, E = 100.0, 350.0, -20.0  # mm
M1, M2, M3 = 2.0, 3.0, 4.0  # kg
UNIFORM = f"""
name: uniform slider-crank
units: {{length: mm, angle: deg, speed: rpm, mass: kg, force: N, inertia: kg*m^2}}
gravity: [0, -9.81]
links:
  ground: {{points: {{O: [0, 0], guide: [0, {E}]}}}}
  crank:
    points: {{O: [0, 0], A: [{A}, 0]}}
    com: [{A / 2}, 0]
    mass: {M1}
    inertia: {M1 * (A / 1000) ** 2 / 12}
    section: {{shape: circle, diameter: 20}}
  rod:
    points: {{A: [0, 0], B: [{B}, 0]}}
    com: [{B / 2}, 0]
    mass: {M2}
    inertia: {M2 * (B / 1000) ** 2 / 12}
    section: {{shape: rectangle, width: 10, height: 25}}
  slider: {{points: {{B: [0, 0]}}, mass: {M3}}}
joints:
  O: {{type: revolute, links: [ground, crank]}}
  A: {{type: revolute, links: [crank, rod]}}
  B: {{type: revolute, links: [rod, slider]}}
  slide: {{type: prismatic, links: [ground, slider], axis: {{point: guide, direction: [1, 0]}},
          point: B}}
drivers:
  motor: {{joint: O, motion: {{speed: 600}}}}
loads:
  push: {{type: force, link: slider, point: B, value: [-800, 0]}}
sketch: {{A: [{A}, 0], B: [{A + B - 10}, {E}]}}
analysis: {{start: 0, sweep: 360, positions: 24}}
"""


@pytest.fixture(scope="module")
def uniform():
    return ks.analyze(ks.loads(UNIFORM, file="uniform.yaml"))


def _pins(result, link, near, far):
    """Global places (n, 2) of the link's pins, its unit axis e and normal n, length (m)."""
    p0 = np.stack([result[f"{link}.{near}.x"], result[f"{link}.{near}.y"]], -1)
    p1 = np.stack([result[f"{link}.{far}.x"], result[f"{link}.{far}.y"]], -1)
    d = p1 - p0
    L = np.hypot(*d.T)
    e = d / L[:, None]
    return e, np.stack([-e[:, 1], e[:, 0]], -1), L


def _acc(result, link, point):
    return np.stack([result[f"{link}.{point}.ax"], result[f"{link}.{point}.ay"]], -1)


def _far_end(result, m, link, near, far, f_far, s, integrate):
    """(N, V, M) at stations ``s`` from the part beyond each station: the far pin's force
    ``f_far`` on the link and the distributed (m/L)·(g − a(x)), with the rigid body's
    a(x) = a_near + (x/L)(a_far − a_near) from the pins' accelerations — in closed form,
    or (``integrate``) by the trapezoid rule on 4001 points."""
    e, n, L = _pins(result, link, near, far)
    g = np.array([0.0, -9.81])
    a0, a1 = _acc(result, link, near), _acc(result, link, far)
    out = []
    for k in range(len(result)):
        rows = []
        for sk in s:
            if integrate:
                x = np.linspace(sk, L[k], 4001)
                w = (m / L[k]) * (g - a0[k] - np.outer(x / L[k], a1[k] - a0[k]))
                we, wn = w @ e[k], w @ n[k]
                Nk = np.trapezoid(we, x) + f_far[k] @ e[k]
                Vk = np.trapezoid(wn, x) + f_far[k] @ n[k]
                Mk = np.trapezoid((x - sk) * wn, x) + (L[k] - sk) * (f_far[k] @ n[k])
            else:
                ue, un = (g - a0[k]) @ e[k], (g - a0[k]) @ n[k]
                de, dn = (a1[k] - a0[k]) @ e[k], (a1[k] - a0[k]) @ n[k]
                Lk, q = L[k], m / L[k]
                Nk = q * (ue * (Lk - sk) - de * (Lk**2 - sk**2) / (2 * Lk)) + f_far[k] @ e[k]
                Vk = q * (un * (Lk - sk) - dn * (Lk**2 - sk**2) / (2 * Lk)) + f_far[k] @ n[k]
                # ∫_s^L (x − s)(u_n − d_n x/L) dx
                cubic = (Lk**3 - sk**3) / 3 - sk * (Lk**2 - sk**2) / 2
                mm = un * (Lk - sk) ** 2 / 2 - dn / Lk * cubic
                Mk = q * mm + (Lk - sk) * (f_far[k] @ n[k])
            rows.append((Nk, Vk, Mk))
        out.append(rows)
    a = np.array(out)
    return a[..., 0], a[..., 1], a[..., 2]


def _force(result, joint):
    return np.stack([result[f"{joint}.Fx"], result[f"{joint}.Fy"]], -1)


@pytest.mark.parametrize("integrate", [False, True], ids=["closed form", "integrated"])
@pytest.mark.parametrize(
    "link, near, far, mass, far_force",
    [
        ("crank", "O", "A", M1, lambda r: -_force(r, "A")),  # A = [crank, rod]: crank on rod
        ("rod", "A", "B", M2, lambda r: -_force(r, "B")),  # B = [rod, slider]: rod on slider
    ],
)
def test_uniform_link_against_the_beam(uniform, link, near, far, mass, far_force, integrate):
    loads, note = beam_loads(uniform, link)
    assert note is None and loads.distributed is not None  # uniform: distributed
    s = np.linspace(0.0, loads.length, 9)
    N, V, M = beam_forces(loads, s)
    Nx, Vx, Mx = _far_end(uniform, mass, link, near, far, far_force(uniform), s, integrate)
    f_scale = np.max(np.abs(far_force(uniform)))
    assert np.max(np.abs(N[:, :-1] - Nx[:, :-1])) < 1e-6 * f_scale
    assert np.max(np.abs(V[:, :-1] - Vx[:, :-1])) < 1e-6 * f_scale
    assert np.max(np.abs(M[:, :-1] - Mx[:, :-1])) < 1e-6 * f_scale * loads.length


def test_the_crank_carries_the_driving_torque_at_its_shaft(uniform):
    """M just past O is the motor's torque on the crank, turned: the couple the rest of the
    crank puts on its shaft end (M = −τ)."""
    loads, _ = beam_loads(uniform, "crank")
    _, _, M = beam_forces(loads, np.array([0.0]))
    tau = uniform["motor.torque"]
    assert np.max(np.abs(M[:, 0] + tau)) < 1e-9 * np.max(np.abs(tau))


@pytest.fixture(scope="module")
def sized():
    result = ks.analyze(ks.load(ROOT / "mechanisms" / "slider_crank_sized.yaml"))
    return result, sizing_stage(result)


def test_pin_ends_hold_the_invariants(sized):
    """On every link with a section of the shipped file: the moment is zero at a pin that
    carries no couple (the rod's two, the crank's A), N and V at each end are the joint's
    reaction on the link projected on the axis and its normal."""
    result, sizing = sized
    model = result.system.model
    for rec in sizing.links:
        near, far = rec.pins
        e, n, _ = _pins(result, rec.link, near, far)
        scale = max(np.max(np.abs(_force(result, j))) for j in rec.pins)
        for k, j in ((0, near), (-1, far)):
            f = _force(result, j) * (1.0 if model.joint(j).links[1] == rec.link else -1.0)
            sign = -1.0 if k == 0 else 1.0  # N(0) = −F₀·e, N(L) = F₁·e
            assert np.max(np.abs(rec.N[:, k] - sign * np.sum(f * e, -1))) < 1e-9 * scale
            assert np.max(np.abs(rec.V[:, k] - sign * np.sum(f * n, -1))) < 1e-9 * scale
        assert np.max(np.abs(rec.M[:, -1])) < 1e-9 * scale * rec.stations[-1]
        if rec.link == "rod":
            assert np.max(np.abs(rec.M[:, 0])) < 1e-9 * scale * rec.stations[-1]


def test_the_largest_stress_is_found_where_it_is(sized):
    """The peak normal stress is |N|/A + |M|/Z at the critical station, the largest over the
    stations and rows (the nodes may only raise it)."""
    _, sizing = sized
    for rec in sizing.links:
        s = np.abs(rec.N) / rec.area + np.abs(rec.M) / rec.modulus
        assert rec.peak_stress >= s.max() * (1 - 1e-12)
        assert rec.peak_stress <= s.max() * 1.05  # the nodes lie between rows 1° apart


def test_a_uniform_link_with_more_inertia_carries_the_rest_at_mid_span():
    """A uniform rod whose J is 1.5·mL²/12: the distributed load gives mL²/12 of its inertia
    couple, the rest −(J − mL²/12)·α acts at mid-span — the far-end closed form plus that
    couple on the stations before mid-span."""
    L = B / 1000
    text = UNIFORM.replace(f"inertia: {M2 * L**2 / 12}", f"inertia: {1.5 * M2 * L**2 / 12}")
    result = ks.analyze(ks.loads(text, file="heavy.yaml"))
    loads, note = beam_loads(result, "rod")
    assert note is None
    s = np.linspace(0.0, loads.length, 9)
    N, V, M = beam_forces(loads, s)
    f_far = -_force(result, "B")
    Nx, Vx, Mx = _far_end(result, M2, "rod", "A", "B", f_far, s, False)
    couple = -(0.5 * M2 * L**2 / 12) * result["rod.alpha"]
    Mx = Mx + np.where(s[None, :] < L / 2, couple[:, None], 0.0)
    scale = np.max(np.abs(f_far))
    assert np.max(np.abs(M[:, :-1] - Mx[:, :-1])) < 1e-6 * scale * L
    assert np.max(np.abs(N[:, :-1] - Nx[:, :-1])) < 1e-6 * scale


def test_a_link_that_is_not_between_two_pins_is_reported(sized):
    """The slider has a pin and a slide: a section on it is reported, not checked."""
    text = (ROOT / "mechanisms" / "slider_crank_sized.yaml").read_text()
    slider = "    points: {B: [0, 0]}\n    mass: 4"
    text = text.replace(slider, slider + "\n    section: {shape: circle, diameter: 30}")
    sizing = sizing_stage(ks.analyze(ks.loads(text, file="slider.yaml")))
    assert [x.link for x in sizing.links] == ["crank", "rod"]
    assert any("link 'slider'" in w and "not checked" in w for w in sizing.warnings)
