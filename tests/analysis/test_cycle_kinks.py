"""The kinks the cycle integral is cut at are located on the solved state (analysis/cycle.py,
``_solved_kinks``), as the load events are: a zero of the driving torque a few degrees from
a load switch is not placed by a cubic through rows on both sides of the jump.

Drive sizing's motor-side torque T_M = T/(i·η) where the shaft takes power and T·η/i where
it gives it back has a kink at each zero of T.  The reference integrates T_M by 20-point
Gauss–Legendre on eight sub-pieces of each piece between the switches and the zeros of T,
each zero found by bisection (``brentq``) on single-position analyses; T_M is formed here
from the rows' torque by the rule above.  The means must agree to 1e-12 of the largest |T_M|.
"""

from __future__ import annotations

import re

import numpy as np
from scipy.optimize import brentq

import kinetostatics as ks
from kinetostatics.analysis.cycle import cycle_stats
from kinetostatics.dynamics.drive import size
from tests.helpers import ROOT

BAND = (75.5, 181.5)  # the brake acts here: each end within a degree of a zero of the torque
RATIO, EFF = 10.0, 0.8


def _model() -> ks.Model:
    """The shipped slider-crank without friction and its resistance, braked on an arc that
    starts 1.5° after a zero of its torque (74.0°) and ends 0.6° after another (180.9°)."""
    text = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
    text = re.sub(r", friction: \{[^}]*\}", "", text)
    text = text.replace("    friction: {coefficient: 0.10}\n", "")
    text = text[: text.index("loads:")] + text[text.index("sketch:") :]
    text += (
        f"loads:\n  brake: {{type: torque, link: crank, value: -20, "
        f"active: [{{angle: [{BAND[0]}, {BAND[1]}]}}]}}\n"
        f"drive: {{reduction: {{ratio: {RATIO}, efficiency: {EFF}}}}}\n"
    )
    return ks.loads(text, file="slider_crank_braked.yaml")


def _torque(model, deg) -> np.ndarray:
    r = ks.analyze(model, positions=np.radians(np.atleast_1d(deg)), events=False)
    return np.asarray(r["motor.torque"], dtype=float)


def _motor_side(tau):
    return np.where(tau >= 0, tau / (RATIO * EFF), tau * EFF / RATIO)


def _gauss_between_zeros(fn, ends, samples: int, xtol: float):
    """(nodes, weights, cuts) of the reference rule: the span cut at ``ends`` and at the
    zeros of ``fn`` between them (sign changes on ``samples`` points, then brentq on
    single-time analyses), each piece in eight sub-pieces of 20-point Gauss–Legendre."""
    cuts = list(ends)
    for a, b in zip(ends[:-1], ends[1:]):
        grid = np.linspace(a, b, samples)[1:-1]
        v = fn(grid)
        for k in np.flatnonzero(np.sign(v[:-1]) != np.sign(v[1:])):
            f = lambda x: float(fn(x)[0])  # noqa: E731
            cuts.append(brentq(f, grid[k], grid[k + 1], xtol=xtol, rtol=1e-15))
    cuts = np.sort(cuts)
    x, w = np.polynomial.legendre.leggauss(20)
    nodes, weights = [], []
    for a, b in zip(cuts[:-1], cuts[1:]):
        sub = np.linspace(a, b, 9)
        for c0, c1 in zip(sub[:-1], sub[1:]):
            nodes.append(c0 + (c1 - c0) * (x + 1) / 2)
            weights.append((c1 - c0) / 2 * w)
    return np.concatenate(nodes), np.concatenate(weights), cuts


def _reference(model):
    """(mean, RMS) of T_M over the turn, the pieces cut at the switches and at the zeros."""
    nodes, weights, cuts = _gauss_between_zeros(
        lambda deg: _torque(model, deg), [0.0, *BAND, 360.0], 401, 1e-13
    )
    tm = _motor_side(_torque(model, nodes))
    return np.sum(weights * tm) / 360.0, np.sqrt(np.sum(weights * tm**2) / 360.0), cuts


def test_the_motor_side_means_near_a_load_switch_are_exact():
    model = _model()
    mean, rms, cuts = _reference(model)
    zeros = cuts[~np.isin(cuts, [0.0, *BAND, 360.0])]
    # the case at stake: a zero of the torque within 2° of a switch
    assert np.min(np.abs(zeros[:, None] - np.array(BAND)[None, :])) < 2.0
    r = ks.analyze(model)
    motor = size(r).motor["torque"]
    scale = float(np.max(np.abs(_motor_side(r["motor.torque"]))))
    assert abs(motor["mean"] - mean) <= 1e-12 * scale, motor["mean"] - mean
    assert abs(motor["rms"] - rms) <= 1e-12 * scale, motor["rms"] - rms


def _slider_crank(loads: str) -> ks.Model:
    """An offset slider-crank (crank 0.1 m, rod 0.35 m, guide 0.02 m below the crank
    pivot), its slider carrying two points, a brake ``loads`` on the crank."""
    return ks.loads(
        f"""
units: {{length: m, angle: deg, speed: rpm, mass: kg, force: N, torque: N*m}}
links:
  ground: {{points: {{O: [0, 0], guide: [0, -0.02]}}}}
  crank: {{points: {{O: [0, 0], A: [0.1, 0]}}, mass: 1, com: [0.03, 0], inertia: 0.002}}
  rod: {{points: {{A: [0, 0], B: [0.35, 0]}}, mass: 2, com: [0.1, 0], inertia: 0.02}}
  slider: {{points: {{B: [0, 0], P: [0.05, 0.01]}}, mass: 3}}
joints:
  O: {{type: revolute, links: [ground, crank]}}
  A: {{type: revolute, links: [crank, rod]}}
  B: {{type: revolute, links: [rod, slider]}}
  slide: {{type: prismatic, links: [ground, slider], axis: {{point: guide, direction: [1, 0]}},
          point: B}}
drivers: {{motor: {{joint: O, motion: {{speed: 120}}, points: [x, A]}}}}
sketch: {{A: [0.1, 0], B: [0.449, -0.02]}}
{loads}""",
        file="slider_crank_two_points.yaml",
    )


def test_a_load_switched_by_two_conditions_at_the_same_instant_is_cut_there():
    """A brake on while two points of the slider both move in +x: both conditions change
    at the dead centres at the same instant, where each, looked at on its own root, saw
    the other at its zero, and the switches were lost (a generated mechanism of the net:
    its mean torque 7e-6 off).  The events are at the dead centres (closed form: crank and
    rod in line), and the brake's share of the mean torque is −5 N·m times the part of the
    turn where the slider's speed exceeds the zero-speed band, 1e-9·|ω|·L_ref
    (docs/conventions.md; L_ref = 0.35 m, the rod; on 4.8e-9 rad past each dead centre):
    the cycle integral cuts there too, where the rows see the brake come on and go off."""
    a, b, e = 0.1, 0.35, -0.02
    # the dead centres: B = (a ± b)·u on the guide, right of the crank pivot
    x_in, x_out = np.sqrt((b - a) ** 2 - e**2), np.sqrt((a + b) ** 2 - e**2)
    folded = np.degrees(np.arctan2(e / (a - b), x_in / (a - b))) % 360
    extended = np.degrees(np.arctan2(e, x_out)) % 360
    brake = (
        "loads:\n  brake: {type: torque, link: crank, value: 5,\n"
        "    active: [{moving: [1, 0], point: slider.B}, {moving: [1, 0], point: slider.P}]}\n"
    )
    r = ks.analyze(_slider_crank(brake))
    found = {ev.switch: np.degrees(ev.coordinate) % 360 for ev in r.events}
    assert len(r.events) == 2, r.events
    assert abs(found["on"] - folded) < 1e-9 and abs(found["off"] - extended) < 1e-9, found
    omega, band = 4 * np.pi, 1e-9 * 4 * np.pi * 0.35

    def speed(psi):  # of the slider along +x, closed form
        s = a * np.sin(psi) - e
        return omega * (-a * np.sin(psi) - a * np.cos(psi) * s / np.sqrt(b**2 - s**2))

    on = brentq(lambda x: speed(x) - band, np.radians(folded), np.radians(folded) + 1e-3)
    off = brentq(lambda x: speed(x) - band, np.radians(extended) - 1e-3, np.radians(extended))
    share = -5.0 * ((np.degrees(off - on)) % 360) / 360
    mean = cycle_stats(r, ["motor.torque"])["motor.torque"]["mean"]
    free = cycle_stats(ks.analyze(_slider_crank("")), ["motor.torque"])["motor.torque"]["mean"]
    assert abs(mean - free - share) <= 1e-12 * 10, (mean - free, share)


ROCKING = """
units: {length: m, angle: deg, speed: rpm, mass: kg, force: N, torque: N*m, inertia: kg*m^2}
links:
  ground: {points: {O: [0, 0]}}
  crank: {points: {O: [0, 0], A: [1, 0]}, mass: 2, com: [0.5, 0]}
joints: {O: {type: revolute, links: [ground, crank]}}
drivers:
  motor:
    joint: O
    points: [x, A]
    motion: {law: harmonic, centre: 10, amplitude: 40, period: 0.7, phase: 0.3}
loads: {T: {type: torque, link: crank, value: -10}}
drive: {reduction: {ratio: 5, efficiency: 0.8}}
gravity: [0, -9.81]
sketch: {crank.A: [1, 0]}
"""


def test_the_motor_torque_of_a_rocking_drive_is_cut_where_the_law_turns():
    """A harmonic motion law turns back twice a period: the power through the reduction
    changes sign there while the torque does not, so the motor's torque jumps from T/(iη)
    to T·η/i (the means were 1e-3 off).  Reference: 20-point Gauss on eight sub-pieces
    between the turning times (closed form: cos(ωt + φ) = 0) and the zeros of T (brentq
    on single-time analyses), T from the run at the nodes, T_M by the rule of
    docs/drive.md."""
    model = ks.loads(ROCKING)
    period, phase = 0.7, np.radians(0.3)  # the file's angles are in degrees
    omega = 2 * np.pi / period
    turns = np.sort(np.mod((np.pi / 2 - phase + np.pi * np.arange(2)) / omega, period))
    ends = np.concatenate(([0.0], turns, [period]))

    def torque(t):
        return np.asarray(ks.analyze(model, times=np.atleast_1d(t), events=False)["motor.torque"])

    # the pieces cut at the turning times and at the zeros of the torque
    nodes, weights, _ = _gauss_between_zeros(torque, ends, 201, 1e-15)
    tau = torque(nodes)
    psi_d = np.cos(omega * nodes + phase)  # the sign of ψ̇; the sense of motion is +
    tm = np.where(tau * psi_d >= 0, tau / (5 * 0.8), tau * 0.8 / 5)
    mean, rms = np.sum(weights * tm) / period, np.sqrt(np.sum(weights * tm**2) / period)
    d = size(ks.analyze(model)).motor["torque"]
    scale = float(np.max(np.abs(tm)))
    assert abs(d["mean"] - mean) <= 1e-12 * scale, d["mean"] - mean
    assert abs(d["rms"] - rms) <= 1e-12 * scale, d["rms"] - rms
