"""Hostile numbers: values whose products overflow (or underflow) are refused when the
file is read, a NaN that no status explains never leaves ``analyze`` unflagged, and the
API refuses positions/times that are not finite real numbers in range (docs/errors.md,
"Input limits" and "Calls from Python").

The truth for the boundary cases is dimensional analysis: a slider-crank whose lengths
are scaled by λ and masses by μ (the speed kept) has its positions scaled by λ, its
forces by μλ (gravity and the resistance scaled to match) and its torques by μλ².
"""

from __future__ import annotations

import dataclasses
import re
import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.errors import ModelError, NonFiniteResultError

SLIDER = "mechanisms/slider_crank.yaml"
TEXT = open(SLIDER).read()


def _where(text: str, needle: str, offset: int = 0) -> tuple[int, int]:
    """1-based line and column of ``needle`` (+ ``offset`` characters) in ``text``."""
    k = text.index(needle) + offset
    return text.count("\n", 0, k) + 1, k - (text.rfind("\n", 0, k) + 1) + 1


def _refused(text: str) -> str:
    with pytest.raises(ModelError) as info:
        ks.loads(text, file="hostile.yaml")
    return str(info.value)


# -- the loader ------------------------------------------------------------------
@pytest.mark.parametrize(
    "old, new, written, path, value",
    [
        ("gravity: [0, -9.81]", "gravity: [0, -1e308]", "-1e308", "gravity[1]", "-1e+308 m/s^2"),
        ("gravity: [0, -9.81]", "gravity: [0, -2e12]", "-2e12", "gravity[1]", "-2e+12 m/s^2"),
        ("B: [b, 0]", "B: [1e300, 0]", "1e300", "links.rod.points.B[0]", "1e+300 mm (1e+297 m)"),
        ("B: [b, 0]", "B: [1e-300, 0]", "1e-300", "links.rod.points.B[0]", "1e-300 mm"),
        ("mass: 3", "mass: 1e300", "1e300", "links.rod.mass", "1e+300 kg"),
        ("mass: 3", "mass: 1e-300", "1e-300", "links.rod.mass", "1e-300 kg"),
        ("inertia: 0.031", "inertia: 1e40", "1e40", "links.rod.inertia", "1e+40 kg*m^2"),
        ("value: 1000", "value: 1e300", "1e300", "loads.resistance.value", "1e+300 N"),
        ("radius: 1.2", "radius: 1e300", "1e300", "joints.A.friction.radius", "1e+300 mm"),
        (
            "coefficient: 0.10",
            "coefficient: 1e300",
            "1e300",
            "joints.slide.friction.coefficient",
            "1e+300",
        ),
    ],
)
def test_the_loader_refuses_magnitudes_that_overflow_or_underflow(old, new, written, path, value):
    """FILE:LINE:COL (at the number as written): key.path: the value, in the file's unit."""
    assert old in TEXT
    text = TEXT.replace(old, new, 1)
    message = _refused(text)
    line, col = _where(text, new, new.index(written))
    assert message.startswith(f"hostile.yaml:{line}:{col}: {path}: {value}"), message
    assert ("too large" in message) != ("too small" in message)
    assert len(message.splitlines()) == 1


def test_a_parameter_that_overflows_is_reported_where_it_is_used():
    """Link lengths of 1e300 mm given as a parameter: each use is a located problem."""
    message = _refused(TEXT.replace("  b: 350 ", "  b: 1e300 ", 1))
    assert "links.rod.points.B[0]: 1e+300 mm (1e+297 m) is too large" in message


def test_a_mass_from_a_weight_is_checked_after_the_conversion():
    text = TEXT.replace("gravity: [0, -9.81]", "gravity: [0, -1e-25]").replace(
        "    mass: 3\n", "    weight: 1e20\n", 1
    )
    message = _refused(text)
    line, col = _where(text, "weight: 1e20", len("weight: "))
    assert message.startswith(
        f"hostile.yaml:{line}:{col}: links.rod.weight: a weight of "
        "1e+20 N with |gravity| = 1e-25 m/s^2 gives a mass of 1e+45 kg"
    )


def test_a_motion_law_that_reaches_an_absurd_speed_is_refused():
    text = TEXT.replace(
        "motor: {joint: O, motion: {speed: 300}}",
        "motor: {joint: O, motion: {law: polynomial, coefficients: [0, 1, 1e300], duration: 1}}",
    )
    text = text.replace("analysis: {start: 0, sweep: 360, positions: 360}", "")
    message = _refused(text)
    assert "drivers.motor.motion: the polynomial law reaches a speed of" in message
    assert "its peak speed must be from 1e-09 to 1e+09 rad/s" in message


def test_the_limits_keep_the_products_of_the_analysis_far_from_overflow():
    """The documented claim: with every input at its limit, m·ω²·L, J·ω², m·g·L, F·L and
    the powers stay below 1e60 (and their squares far from the 1.8e308 overflow)."""
    from kinetostatics.base.limits import MAGNITUDE, MAX_LAW_ACCELERATION, SPEED_RANGE

    L, m, J = MAGNITUDE["length"][1], MAGNITUDE["mass"][1], MAGNITUDE["inertia"][1]
    F, T, g = MAGNITUDE["force"][1], MAGNITUDE["torque"][1], MAGNITUDE["acceleration"][1]
    w, alpha = SPEED_RANGE[1], MAX_LAW_ACCELERATION
    a = (w * w + alpha) * L  # a point's acceleration
    products = {
        "m·a": m * a,
        "m·a·L": m * a * L,
        "J·(ω²+α)": J * (w * w + alpha),
        "m·g·L": m * g * L,
        "F·L": F * L,
        "T·ω": T * w,
        "F·v": F * w * L,
        "(m·a)·v": m * a * w * L,
        "J·α·ω": J * alpha * w,
    }
    assert max(products.values()) < 1e60, products
    assert 1e60**2 < 1e308


# -- the last guard of analyze ----------------------------------------------------------
def test_analyze_raises_rather_than_return_an_unflagged_nan():
    """A model built in Python (no loader limits) whose gravity overflows: every reaction
    was NaN, every row 'self-locking', and analyze returned it."""
    model = dataclasses.replace(ks.load(SLIDER), gravity=np.array([0.0, -1e308]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        with pytest.raises(NonFiniteResultError) as info:
            ks.analyze(model, positions=np.radians([0.0, 30.0, 90.0]))
    message = str(info.value)
    assert "the reaction of joint O (O.Fx, O.Fy) at row 0 (motor = 0°" in message
    assert info.value.row == 0 and isinstance(info.value, ks.KinetostaticsError)


# -- the API -------------------------------------------------------------------------
@pytest.fixture(scope="module")
def slider():
    return ks.load(SLIDER)


@pytest.mark.parametrize(
    "kwargs, text",
    [
        (dict(positions=[float("nan")]), "positions[0] = nan"),
        (dict(positions=[0.0, 1.0, float("inf")]), "positions[2] = inf"),
        (dict(positions=[-1e300]), "positions[0] = -1e+300"),
        (dict(positions=[]), "positions is empty"),
        (dict(positions=[[0.0, 1.0]]), "positions must be a 1-D sequence"),
        (dict(positions=[1j]), "positions must be a 1-D sequence of real numbers"),
        (dict(positions=["0"]), "positions must be a 1-D sequence of real numbers"),
        (dict(times=[float("nan")]), "times[0] = nan"),
        (dict(times=[0.0, -20.5]), "times[1] = -20.5"),
        (dict(times=[1e300]), "times[0] = 1e+300"),
        (dict(times=[]), "times is empty"),
    ],
)
def test_analyze_refuses_positions_and_times_that_are_not_finite_real_numbers(slider, kwargs, text):
    with pytest.raises(ValueError) as info:
        ks.analyze(slider, **kwargs)
    assert text in str(info.value)
    assert not isinstance(info.value, ks.KinetostaticsError)  # a call, not a file error


def test_times_up_to_the_limit_are_analysed(slider):
    """100 turns at 300 rpm take 20 s; the last allowed time is a pose of the cycle."""
    r = ks.analyze(slider, times=[0.0, 20.0], friction=False)
    assert np.allclose(r["motor.torque"][1], r["motor.torque"][0], rtol=1e-9, atol=1e-9)
    with pytest.raises(ValueError, match=r"times\[0\] = 20\.1"):
        ks.analyze(slider, times=[20.1])


def test_simulate_and_flywheel_refuse_hostile_arguments(slider):
    from kinetostatics.dynamics import simulate
    from kinetostatics.dynamics.flywheel import design

    for kwargs, text in (
        (dict(until=float("nan")), "until = nan"),
        (dict(until=-1.0), "until = -1.0"),
        (dict(until=1.0, rtol=0.0), "rtol = 0.0"),
        (dict(until=1.0, rtol=float("inf")), "rtol = inf"),
    ):
        with pytest.raises(ValueError, match=re.escape(text)):
            simulate(slider, **kwargs)
    for delta in (float("nan"), 0.0, 2.0):
        with pytest.raises(ValueError, match="delta = "):
            design(slider, delta)


# -- boundary values just inside the limits ------------------------------------------------
SCALED = """
name: scaled slider-crank
units: {length: mm, angle: deg, speed: rpm, mass: kg, force: N, inertia: kg*m^2}
parameters: {L: %r, M: %r, a: 100 * L, b: 350 * L, e: -20 * L, r1: 30 * L, r2: 120 * L}
gravity: [0, -9.81 * L]
links:
  ground: {points: {O: [0, 0], guide: [0, e]}}
  crank: {points: {O: [0, 0], A: [a, 0]}, com: [r1, 0], mass: 2 * M, inertia: 0.006 * M * L**2}
  rod: {points: {A: [0, 0], B: [b, 0]}, com: [r2, 0], mass: 3 * M, inertia: 0.031 * M * L**2}
  slider: {points: {B: [0, 0]}, mass: 4 * M}
joints:
  O: {type: revolute, links: [ground, crank], friction: {radius: 1.5 * L}}
  A: {type: revolute, links: [crank, rod], friction: {radius: 1.2 * L}}
  B: {type: revolute, links: [rod, slider], friction: {radius: 1.0 * L}}
  slide: {type: prismatic, links: [ground, slider], axis: {point: guide, direction: [1, 0]},
          point: B, friction: {coefficient: 0.10}}
drivers:
  motor: {joint: O, motion: {speed: 300}}
loads:
  resistance: {type: resistance, link: slider, point: B, value: 1000 * M * L, axis: [1, 0],
               active: [{moving: [1, 0]}]}
sketch: {A: [100 * L, 0], B: [440 * L, -20 * L]}
analysis: {start: 0, sweep: 360, positions: 24}
"""


def _scaled(lam: float, mu: float):
    """The slider-crank of mechanisms/ with lengths × lam, masses × mu (gravity, the
    resistance and the inertias scaled to match)."""
    return ks.analyze(ks.loads(SCALED % (lam, mu)))


@pytest.fixture(scope="module")
def base():
    return _scaled(1.0, 1.0)


@pytest.mark.parametrize("lam, mu", [(1e6, 1e6), (2e9, 2e11), (1e-6, 1e-6)])
def test_scaled_mechanisms_give_the_scaled_results(base, lam, mu):
    """Near the limits (lam = 2e9: the sketch reaches 8.8e8 m of the 1e9 m limit; mu =
    2e11: the slider 8e11 kg of 1e12) the results are finite and are the originals
    scaled: positions × λ, forces × μλ, torques × μλ², powers × μλ²."""
    r = _scaled(lam, mu)
    assert np.all(np.isfinite(r["motor.torque_friction"]))
    scale = {
        "m": lam,
        "N": mu * lam,
        "N*m": mu * lam**2,
        "W": mu * lam**2,
        "m/s": lam,
        "m/s^2": lam,
    }
    names = [
        n for n in base.names if base.units[n] in scale and not n.startswith("power.residual")
    ]  # round-off, not a quantity
    size: dict[str, float] = {}  # round-off is judged per unit
    for name in names:
        unit = base.units[name]
        v = np.abs(base[name] * scale[unit])
        size[unit] = max(size.get(unit, 0.0), float(np.max(v[np.isfinite(v)], initial=0.0)))
    checked = 0
    for name in names:
        unit = base.units[name]
        ref, got = base[name] * scale[unit], r[name]
        assert np.allclose(got, ref, rtol=0.0, atol=1e-8 * size[unit], equal_nan=True), name
        checked += 1
    assert checked > 80
    np.testing.assert_array_equal(r["friction.status"], base["friction.status"])


# -- the report on a flagged NaN column -------------------------------------------------
@pytest.fixture(scope="module")
def locked():
    """The near-self-locking slider-crank with 30 times its friction: the consistent
    friction solution self-locks at every position (friction.status 2, empty columns)."""
    text = open("tests/hard/slider_crank_self_locking.yaml").read()
    text = re.sub(r"\n  s: 3 ", "\n  s: 90 ", text)
    text = re.sub(r"positions: 360", "positions: 12", text)
    return ks.analyze(ks.loads(text, file="locked.yaml"))


def test_the_summary_and_report_of_an_all_self_locked_result_do_not_crash(locked):
    from kinetostatics.dynamics.stages import full_summary
    from kinetostatics.outputs.report import _summary_blocks

    assert np.all(locked["friction.status"] == 2)
    assert np.all(np.isnan(locked["motor.force_friction"]))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no "All-NaN slice encountered"
        summary = full_summary(locked)
    d = summary["drivers"]["motor"]
    assert np.isnan(d["mean_friction"]) and np.isfinite(d["mean"])
    items = _summary_blocks(locked, summary)[1].items
    assert any("self-locking at 12 of 12 positions" in item for item in items)
    assert any("no consistent solution at any position" in item for item in items)


def test_polar_diagrams_of_an_all_self_locked_friction_solution_do_not_crash(locked):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from kinetostatics.outputs.plotting import polar_diagrams

    fig = polar_diagrams(locked, friction=True)
    assert any("no consistent friction solution" in ax.get_title() for ax in fig.axes)
    plt.close(fig)


def test_docs_state_the_limits_of_the_code():
    from kinetostatics.base.limits import MAGNITUDE, MAX_LAW_ACCELERATION

    doc = open("docs/errors.md", encoding="utf-8").read()
    stated = {
        "length": (1e9, "length 10⁹ m"),
        "mass": (1e12, "mass 10¹² kg"),
        "inertia": (1e30, "inertia 10³⁰ kg·m²"),
        "force": (1e24, "force 10²⁴ N"),
        "torque": (1e33, "torque 10³³ N·m"),
        "acceleration": (1e12, "gravity (each component) 10¹² m/s²"),
        "time": (1e9, "time 10⁹ s"),
        "angle": (1e6, "angle 10⁶ rad"),
        "speed": (1e9, "speed (effort curves) 10⁹ rad/s"),
        None: (1e18, "directions, ratios) 10¹⁸"),
    }
    assert set(stated) == set(MAGNITUDE)
    for kind, (upper, text) in stated.items():
        assert MAGNITUDE[kind][1] == upper and text in doc, kind
        assert MAGNITUDE[kind][0] in ((0.0,) if kind == "angle" else (1e-30,))
    assert "at least 1e-30 in magnitude" in doc
    assert MAX_LAW_ACCELERATION == 1e18 and "peak \\|ψ̈\\| ≤ 1e+18" in doc
    assert "`NonFiniteResultError`" in doc


def test_negative_times_are_refused_for_a_motion_law_and_run_backwards_at_constant_speed(
    slider, root
):
    """A motion law is not defined before its start; a constant-speed crank is: t = -1/60 s at
    300 rpm is the pose 30° before the start, the same row as ``positions=`` gives there."""
    law = ks.load(root / "tests" / "hard" / "rocker_into_toggle.yaml")
    with pytest.raises(ValueError, match=r"times\[0\] = -0\.1: .*motion law"):
        ks.analyze(law, times=[-0.1])
    before = ks.analyze(slider, times=[-1.0 / 60.0], friction=False)
    start = np.radians(slider.analysis.start)
    same = ks.analyze(slider, positions=[start - np.radians(30.0)], friction=False)
    for name in ("rod.theta", "slider.x", "rod.omega", "slider.ax", "motor.torque", "B.Fx"):
        assert np.allclose(before[name], same[name], rtol=1e-12, atol=1e-9), name
