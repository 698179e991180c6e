"""Springs and dampers (``elements:``; kinetics/elements.py) against their contracts:
the force is minus the gradient of the stored energy (finite differences), a spring's power
is the rate of its energy, a damper's is c ṡ² ≥ 0, the power balance of ``run`` holds with
them, forward dynamics conserves the energy with springs and balances it with dampers, and
a stiffness may vary over the variants of a batch."""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.analysis.vectorised import analyze_stacked, as_result
from kinetostatics.dynamics import simulate
from kinetostatics.errors import ModelError
from kinetostatics.kinetics.elements import element_states
from kinetostatics.structure.system import build_system
from tests.helpers import ROOT

SLIDER = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
PENDULUM = (ROOT / "tests" / "dynamics" / "pendulum.yaml").read_text()
ELEMENTS = """elements:
  spring: {type: spring, between: [ground.O, slider.B], stiffness: k, free_length: 300,
           preload: 50}
  table: {type: spring, between: [crank.A, ground.guide],
          table: {length: [60, 100, 140], force: [-100, 20, 500]}}
  damper: {type: damper, between: [ground.O, slider.B], damping: 0.5}
  tors: {type: torsion_spring, joint: A, stiffness: 3, free_angle: 10, preload: 2}
  rd: {type: rotary_damper, joint: A, damping: 0.2}
"""


def slider(positions: int = 72, k: float = 2.0) -> ks.Model:
    text = SLIDER.replace("sketch:", ELEMENTS + "sketch:").replace(
        "positions: 360", f"positions: {positions}"
    )
    text = text.replace("parameters:\n", f"parameters:\n  k: {k}\n")
    return ks.loads(text)


@pytest.fixture(scope="module")
def result():
    return ks.analyze(slider())


def test_the_force_is_minus_the_gradient_of_the_energy(result):
    """Q = −∂E/∂q by central differences, in every coordinate of q (not only along the
    motion), for the linear, preloaded, table and torsion springs."""
    system = result.system
    rng = np.random.default_rng(7)
    q = result.q[::9] + 0.01 * rng.standard_normal(result.q[::9].shape)
    springs = [e for e in system.model.elements if e.spring]
    for e in springs:
        one = build_system(ks.Model(**{**vars(system.model), "elements": (e,)}))
        q_force = element_states(one, q, None).q
        h = 1e-7
        grad = np.empty_like(q)
        for n in range(q.shape[-1]):
            dq = np.zeros(q.shape[-1])
            dq[n] = h
            ep = element_states(one, q + dq, None).energy[e.name]
            em = element_states(one, q - dq, None).energy[e.name]
            grad[:, n] = (ep - em) / (2 * h)
        scale = np.max(np.abs(q_force))
        assert scale > 1.0
        assert np.max(np.abs(q_force + grad)) <= 1e-6 * scale, e.name


def test_spring_power_is_the_rate_of_its_energy():
    r = ks.analyze(slider(positions=3600))
    t = r["time"]
    for name in ("spring", "table", "tors"):
        rate = np.gradient(r[f"{name}.energy"], t)
        power = r[f"{name}.power"]
        inner = slice(2, -2)  # one-sided differences at the ends; the table's kinks
        err = np.abs(rate - power)[inner]
        assert np.median(err) <= 1e-4 * np.max(np.abs(power)), name
    assert np.allclose(r["power.elastic"], r["spring.power"] + r["table.power"] + r["tors.power"])


def test_damper_dissipation_is_c_times_speed_squared_and_not_negative(result):
    for name, c in (("damper", 500.0), ("rd", 0.2 * 180 / np.pi)):  # N·s/mm, N·m·s/deg
        p = result[f"{name}.power"]
        assert np.all(p >= 0.0)
        assert np.allclose(p, c * result[f"{name}.speed"] ** 2, rtol=1e-12, atol=0)
        assert np.max(p) > 1.0
    assert np.all(result["power.damping"] >= 0.0)
    # the rotary damper's speed is the relative rotation rate at A
    assert np.allclose(result["rd.speed"], result["rod.omega"] - result["crank.omega"])
    assert np.allclose(
        result["tors.angle"], result["rod.theta"] - result["crank.theta"], atol=1e-12
    )


def test_the_power_balance_holds_with_elements_in_run(result):
    checks = result.checks
    assert checks.power.value <= 1e-9
    assert checks.power_friction.value <= 1e-9
    assert np.max(np.abs(result["power.elastic"])) > 0.1 * np.max(np.abs(result["power.input"]))
    # the length column is the distance between the two points
    d = np.hypot(result["slider.B.x"], result["slider.B.y"])
    assert np.allclose(result["spring.length"], d, rtol=1e-14)
    assert np.allclose(result["spring.F"], 50 + 2000 * (d - 0.3), rtol=1e-12)


def _pendulum(elements: str) -> ks.Model:
    return ks.loads(PENDULUM.replace("sketch:", elements + "sketch:"))


def test_forward_dynamics_conserves_energy_with_springs():
    model = _pendulum(
        "elements:\n"
        "  s: {type: spring, between: [ground.O, arm.tip], stiffness: 0.05, free_length: 300,"
        " preload: 3}\n"
        "  t: {type: torsion_spring, joint: O, stiffness: 0.1, free_angle: 20}\n"
    )
    sim = simulate(model, 2.0, method="DOP853", rtol=1e-10)
    cols, units = sim.table(points=201)
    assert units["energy.elastic"] == "J"
    e = cols["energy.total"]
    assert np.allclose(
        e, cols["energy.kinetic"] + cols["energy.potential"] + cols["energy.elastic"]
    )
    assert np.ptp(cols["energy.elastic"]) > 0.1 * np.ptp(cols["energy.kinetic"])
    assert np.max(np.abs(e - e[0])) <= 1e-8 * np.ptp(cols["energy.kinetic"])


def test_forward_dynamics_balances_the_energy_with_a_damper():
    model = _pendulum(
        "elements:\n  d: {type: rotary_damper, joint: O, damping: 0.002}\n"
        "  s: {type: spring, between: [ground.O, arm.tip], stiffness: 0.05, free_length: 300}\n"
    )
    sim = simulate(model, 3.0, method="DOP853", rtol=1e-10)
    cols, _ = sim.table(points=201)
    lost = cols["work.dampers"]
    assert np.all(np.diff(lost) >= -1e-12) and lost[-1] > 0.1
    e = cols["energy.total"]
    assert np.max(np.abs(e - e[0] + lost - cols["work.drivers"])) <= 1e-8 * np.ptp(e)


def test_a_stiffness_varies_over_stacked_variants():
    models = [slider(positions=24, k=k) for k in (1.0, 2.0, 4.0)]
    st = as_result(analyze_stacked(models))
    for v, m in enumerate(models):
        one = ks.analyze(m)
        for col in ("spring.F", "motor.torque", "power.residual", "O.Fx"):
            scale = np.max(np.abs(one[col])) + 1e-300
            assert np.max(np.abs(st[col][v] - one[col])) <= 1e-9 * max(scale, 1.0), col


@pytest.mark.parametrize(
    "entry, message",
    [
        ("{type: sprung, between: [ground.O, slider.B]}", "unknown element type 'sprung'"),
        ("{type: spring, between: [ground.O, slider.B], stiffness: 1}", "missing: free_length"),
        (
            "{type: spring, between: [slider.B, slider.B], stiffness: 1, free_length: 1}",
            "both ends are on link 'slider'",
        ),
        (
            "{type: torsion_spring, joint: slide, stiffness: 1, free_angle: 0}",
            "'slide' is a prismatic joint",
        ),
        ("{type: damper, between: [ground.O, slider.Q], damping: 1}", "has no point 'Q'"),
        ("{type: damper, between: [ground.O, slider.B], damping: -1}", "zero or positive"),
        (
            "{type: spring, between: [ground.O, slider.B], stiffness: 1, free_length: 1, "
            "table: {length: [0, 1], force: [0, 1]}}",
            "not both",
        ),
        (
            "{type: spring, between: [ground.O, slider.B], table: {length: [1, 0], force: [0, 1]}}",
            "the lengths must increase",
        ),
    ],
)
def test_a_mistake_in_an_element_is_a_located_error(entry, message):
    text = SLIDER.replace("sketch:", f"elements:\n  e1: {entry}\nsketch:")
    with pytest.raises(ModelError) as info:
        ks.loads(text, file="m.yaml")
    assert message in str(info.value)
    assert "m.yaml:" in str(info.value) and "elements.e1" in str(info.value)


def _same_elements(a, b) -> None:
    assert [e.name for e in a] == [e.name for e in b]
    for x, y in zip(a, b):
        assert (x.kind, x.links, x.points, x.joint) == (y.kind, y.links, y.points, y.joint)
        for f in ("stiffness", "free", "preload", "damping"):
            assert getattr(y, f) == pytest.approx(getattr(x, f), rel=1e-15, abs=0), (x.name, f)
        assert (x.table is None) == (y.table is None), x.name
        if x.table is not None:
            for u, v in zip(x.table, y.table):
                np.testing.assert_allclose(v, u, rtol=1e-15, atol=0)


def test_dump_then_load_keeps_the_elements_and_the_analysis():
    """``io.dump`` writes ``elements:`` in SI; read back, every element (linear, preloaded,
    table, torsion, both dampers) is the same and so is the analysis, column by column.
    (The model is taken without its load: ``dump`` does not write ``loads:``.)"""
    from dataclasses import replace

    from kinetostatics.io import dump

    model = replace(slider(positions=36), loads=())
    back = ks.loads(dump(model))
    _same_elements(model.elements, back.elements)
    a, b = ks.analyze(model), ks.analyze(back)
    assert list(a.columns) == list(b.columns)
    names = [c for c in a.columns if "." in c and c.split(".")[0] in {"spring", "tors", "rd"}]
    assert len(names) >= 12  # the element columns are among those compared
    for c in a.columns:
        x, y = np.asarray(a[c], dtype=float), np.asarray(b[c], dtype=float)
        scale = max(1.0, float(np.nanmax(np.abs(x))) if np.any(np.isfinite(x)) else 1.0)
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-12 * scale, err_msg=c)


def test_dump_then_load_keeps_a_free_motion_with_a_spring():
    """The effort-driven Andrews squeezer (a spring, a constant torque): the same elements
    and the same motion over its first millisecond."""
    from kinetostatics.io import dump

    model = ks.load(ROOT / "mechanisms" / "andrews_squeezer.yaml")
    back = ks.loads(dump(model))
    _same_elements(model.elements, back.elements)
    assert model.elements
    a, _ = simulate(model, 1e-3).table(points=21)
    b, _ = simulate(back, 1e-3).table(points=21)
    for name in ("drive.angle", "drive.speed", "energy.elastic", "energy.kinetic"):
        x, y = np.asarray(a[name]), np.asarray(b[name])
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-12 * max(1.0, np.max(np.abs(x))))
