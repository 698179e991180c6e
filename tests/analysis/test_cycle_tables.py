"""Every corner of a table is a cut of the cycle integral (analysis/cycle.py), so the means,
RMS values, the flywheel's M_d and ΔW of a tabulated quantity are exact to round-off
(docs/conventions.md, *Means over the cycle*).

The expected values are closed forms: the integrals of a piecewise-linear function and of
its square over its pieces, and the largest swing of the integral of its deviation from
the mean (a piecewise quadratic, extreme at a corner or where the function crosses its
mean).  Tables of loads (corners on and off the position grid), of an effort, of a table
spring and of a motion law.
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.analysis.cycle import cycle_stats
from kinetostatics.dynamics.flywheel import design
from kinetostatics.dynamics.stages import full_summary

HEAD = """
units: {length: m, angle: deg, speed: rpm, mass: kg, force: N, torque: N*m, inertia: kg*m^2}
links: {ground: {points: {O: [0, 0]}}, crank: {points: {O: [0, 0], A: [1, 0]}, inertia: 10}}
joints: {O: {type: revolute, links: [ground, crank]}}
sketch: {crank.A: [1, 0]}
"""

# the issue's file: flywheel.design gave a mean torque of −138.87536 N·m, exact −138.888…
ISSUE = (
    HEAD
    + """
drivers: {motor: {joint: O, motion: {speed: 60}, points: [x, A]}}
loads: {T: {type: torque, link: crank, table: {at: [0, 33, 100], value: [0, 1000, 0]}}}
flywheel: {delta: 0.05}
"""
)


def _periodic(at_deg, values, lo: float = 0.0):
    """The periodic (over 360°) piecewise-linear function of a table as corners (x rad,
    y) over one turn [lo, lo + 2π], the ends included."""
    at = np.radians(np.asarray(at_deg, dtype=float))
    y = np.asarray(values, dtype=float)
    xs = np.concatenate((at - 2 * np.pi, at, at + 2 * np.pi))
    ys = np.tile(y, 3)
    inner = (xs > lo) & (xs < lo + 2 * np.pi)
    x = np.concatenate(([lo], xs[inner], [lo + 2 * np.pi]))
    return x, np.interp(x, xs, ys)


def _held(at, values, lo: float, hi: float):
    """The piecewise-linear function of a table held constant outside it, as corners over
    [lo, hi]."""
    at, y = np.asarray(at, dtype=float), np.asarray(values, dtype=float)
    x = np.concatenate(([lo], at[(at > lo) & (at < hi)], [hi]))
    return x, np.interp(x, at, y)


def _integrals(x, y):
    """(∫ y, ∫ y²) of the piecewise-linear function through the corners (x, y)."""
    h = np.diff(x)
    a, b = y[:-1], y[1:]
    return float(np.sum(h * (a + b) / 2)), float(np.sum(h * (a * a + a * b + b * b) / 3))


def _mean_rms(x, y):
    s1, s2 = _integrals(x, y)
    span = x[-1] - x[0]
    return s1 / span, np.sqrt(s2 / span)


def _swing(x, y):
    """max − min over the span of E(x) = ∫ (y − ȳ) from the start: E is quadratic on each
    piece, extreme at a corner or where y crosses ȳ inside a piece."""
    mean = _mean_rms(x, y)[0]
    d = y - mean
    points, energies, e = [x[0]], [0.0], 0.0
    for k in range(len(x) - 1):
        h, a, b = x[k + 1] - x[k], d[k], d[k + 1]
        if a * b < 0:  # the deviation crosses zero at u = a/(a − b) of the piece
            u = a / (a - b)
            points.append(x[k] + u * h)
            energies.append(e + h * (a * u + (b - a) * u * u / 2))
        e += h * (a + b) / 2
        points.append(x[k + 1])
        energies.append(e)
    return max(energies) - min(energies)


def _close(value, exact, scale):
    assert abs(value - exact) <= 1e-12 * abs(scale), (value, exact, value - exact)


def _torque_table_file(at, values, positions=360):
    return (
        HEAD
        + f"""
analysis: {{positions: {positions}}}
drivers: {{motor: {{joint: O, motion: {{speed: 60}}, points: [x, A]}}}}
loads: {{T: {{type: torque, link: crank, table: {{at: {list(at)}, value: {list(values)}}}}}}}
flywheel: {{delta: 0.05}}
"""
    )


LOAD_TABLES = [  # (at in degrees, values N·m, positions of the run)
    ([0, 33, 100], [0, 1000, 0], 360),  # the issue's
    ([12.345, 77.7, 200.01, 301.3], [150, -400, 820, 75], 360),  # corners off the grid
    ([5.5, 95.25, 181.125, 270.0625], [-30, 640, 640, 10], 37),  # few rows, a flat top
]


@pytest.mark.parametrize(("at", "values", "positions"), LOAD_TABLES)
def test_the_means_and_the_flywheel_of_a_load_table_are_exact(at, values, positions):
    r = ks.analyze(ks.loads(_torque_table_file(at, values, positions)))
    x, table = _periodic(at, values)
    torque = -table  # the motor balances the load (the crank at constant speed)
    mean, rms = _mean_rms(x, torque)
    scale = float(np.max(np.abs(torque)))
    s = cycle_stats(r, ["motor.torque"])["motor.torque"]
    _close(s["mean"], mean, scale)
    _close(s["rms"], rms, scale)
    summary = full_summary(r)["drivers"]["motor"]
    _close(summary["mean"], mean, scale)
    _close(summary["rms"], rms, scale)
    fw = design(r)
    _close(fw.mean_torque, mean, scale)
    _close(fw.work_per_cycle, 2 * np.pi * mean, 2 * np.pi * scale)
    _close(fw.energy_swing, _swing(x, torque), 2 * np.pi * scale)


def test_the_issue_file_gives_the_exact_mean_torque():
    fw = design(ks.analyze(ks.loads(ISSUE)))
    _close(fw.mean_torque, -0.5 * 1000 * 100 / 360, 1000)


# an effort table (periodic over the driver coordinate) and a table spring (held
# constant outside its table) on the crank: the motor balances both
ELEMENTS = (
    HEAD
    + """
drivers:
  motor: {joint: O, motion: {speed: 60}, points: [x, A]}
  brake:
    joint: O
    points: [x, A]
    effort: {table: {at: [10, 80.5, 200.25, 300], value: [50, -300, 120, 400]}}
elements:
  spring:
    type: torsion_spring
    joint: O
    table: {angle: [20.5, 100, 250.75, 330], torque: [-100, 300, 50, 250]}
"""
)


def test_an_effort_table_and_a_table_spring_are_integrated_exactly():
    r = ks.analyze(ks.loads(ELEMENTS))
    psi0, s0 = np.radians(r["angle"][0]), np.radians(r["spring.angle"][0])
    brake = ([10, 80.5, 200.25, 300], [50, -300, 120, 400])
    spring = (np.radians([20.5, 100, 250.75, 330]), [-100, 300, 50, 250])
    xb, _ = _periodic(*brake, lo=psi0)
    xs, _ = _held(*spring, s0, s0 + 2 * np.pi)
    x = np.unique(np.concatenate((xb, xs - s0 + psi0)))

    def torque(psi):  # the motor's: the brake's table and the spring's, both linear
        b = np.interp(psi, np.radians(brake[0]), brake[1], period=2 * np.pi)
        return -b + np.interp(s0 + psi - psi0, *spring)

    rows = np.radians(r["angle"])  # the integrand is that function (the run's own rows)
    assert np.max(np.abs(r["motor.torque"] - torque(rows))) <= 1e-12 * 700
    mean, rms = _mean_rms(x, torque(x))
    s = cycle_stats(r, ["motor.torque"])["motor.torque"]
    _close(s["mean"], mean, 700)
    _close(s["rms"], rms, 700)


MOTION = (
    HEAD
    + """
analysis: {positions: 97}
drivers:
  motor:
    joint: O
    points: [x, A]
    motion: {law: table, time: [0, 0.1, 0.25, 0.4, 0.55, 0.7], value: [0, 60, 200, 150, 170, 300]}
"""
)


def test_a_motion_table_is_integrated_exactly():
    """The crank's torque J·ψ̈ of a cubic-spline law: ψ̈ is linear between the knots, with
    a corner at each (the closed form: scipy's spline through the same points)."""
    from scipy.interpolate import CubicSpline

    r = ks.analyze(ks.loads(MOTION))
    t = np.array([0, 0.1, 0.25, 0.4, 0.55, 0.7])
    acc = CubicSpline(t, np.radians([0, 60, 200, 150, 170, 300]))
    assert np.max(np.abs(r["motor.torque"] - 10 * acc(r["time"], 2))) <= 1e-10 * 10 * np.max(
        np.abs(acc(t, 2))
    )
    torque = 10 * acc(t, 2)
    mean, rms = _mean_rms(t, torque)
    scale = float(np.max(np.abs(torque)))
    s = cycle_stats(r, ["motor.torque"])["motor.torque"]
    _close(s["mean"], mean, scale)
    _close(s["rms"], rms, scale)


@pytest.mark.parametrize("text", [ISSUE, ELEMENTS, MOTION], ids=["load", "effort_spring", "motion"])
def test_the_net_relation_cycle_means_holds_on_the_tables(text):
    """The net's ``cycle_means`` relation (tests/net/relations.py) on these files: the
    means, the flywheel and a drive's motor-side means (efficiency 0.85; the motion table
    turns back, where the motor's torque jumps) agree between the two orders to 1e-12."""
    import yaml

    from kinetostatics.io import dump
    from tests.net import relations as R

    doc = yaml.safe_load(dump(ks.loads(text)))
    assert R.relation_cycle_means(doc, 0) <= 1e-12, R.WORST
