"""Tabulated loads, and the difference-quotient comparison mode."""

import numpy as np
import pytest

import kinetostatics as ks
from tests.helpers import rel_err, variant

TORQUE_TABLE = """
  brake:
    type: torque
    link: crank
    table: {at: [0, 90, 270], value: [5, 20, -10]}
"""


def test_torque_table_on_the_crank_shifts_the_driving_torque_by_its_value():
    base = ks.analyze(ks.load("mechanisms/slider_crank.yaml"), friction=False)
    model = variant("slider_crank", load=(r"\nloads:\n", "\nloads:\n" + TORQUE_TABLE.lstrip("\n")))
    r = ks.analyze(model, friction=False)
    # periodic linear interpolation written out by hand: 0→90: 5→20, 90→270: 20→−10, 270→360: −10→5
    a = r["angle"]
    table = np.where(
        a <= 90,
        5 + 15 * a / 90,
        np.where(a <= 270, 20 - 30 * (a - 90) / 180, -10 + 15 * (a - 270) / 90),
    )
    np.testing.assert_allclose(r["motor.torque"], base["motor.torque"] - table, atol=1e-9)
    assert np.max(np.abs(r["power.residual"])) < 1e-9 * np.max(np.abs(r["power.input"]))


def test_constant_table_equals_constant_value():
    base = ks.analyze(ks.load("mechanisms/slider_crank.yaml"))
    model = variant(
        "slider_crank", v=(r"value: 1000", "table: {at: [0, 180], value: [1000, 1000]}")
    )
    r = ks.analyze(model)
    for name in ("motor.torque", "motor.torque_friction", "B.Fx", "slide.N_friction"):
        np.testing.assert_allclose(r[name], base[name], rtol=1e-13, atol=1e-10)


def test_table_and_value_together_is_an_error():
    with pytest.raises(ks.ModelError, match="give exactly one of value"):
        variant(
            "slider_crank",
            v=(r"value: 1000", "value: 1000\n    table: {at: [0, 1], value: [1, 1]}"),
        )


@pytest.mark.parametrize("scheme, order", [("forward", 1), ("central", 2)])
def test_difference_quotients_converge_at_their_order(scheme, order):
    model = ks.load("mechanisms/slotting_machine.yaml")
    exact = ks.analyze(model, friction=False)
    errs = []
    for step in (1.0, 0.1):
        r = ks.analyze(model, friction=False, derivatives_by=scheme, step=np.radians(step))
        errs.append(max(rel_err(r[c], exact[c]) for c in ("ram.vy", "ram.ay", "bar.alpha")))
    assert 10**order / 2 < errs[0] / errs[1] < 10**order * 2
    assert errs[1] > 1e-12  # a real approximation, not the exact solve


def test_unknown_scheme_is_refused():
    with pytest.raises(ValueError, match="unknown difference scheme 'backward'"):
        ks.analyze(ks.load("mechanisms/slider_crank.yaml"), derivatives_by="backward")


def test_effort_driver_is_an_applied_load():
    """A constant effort of 10 N·m applied by the crank on the rod at A changes the
    driving torque by the power it delivers: Δτ ω₁ = −e (ω_rod − ω_crank)."""
    from tests.oracles import slider_crank_closed_form as cf

    base = ks.analyze(ks.load("mechanisms/slider_crank.yaml"), friction=False)
    model = variant(
        "slider_crank", d=(r"\ndrivers:\n", "\ndrivers:\n  helper: {joint: A, effort: 10}\n")
    )
    r = ks.analyze(model, friction=False)
    w1 = cf.SliderCrank().omega1
    k = cf.kinematics(cf.SliderCrank(), np.radians(r["angle"]))
    np.testing.assert_allclose(
        (r["motor.torque"] - base["motor.torque"]) * w1, -10.0 * (k["omega2"] - w1), atol=1e-9
    )
    assert np.max(np.abs(r["power.residual"])) < 1e-9 * np.max(np.abs(r["power.input"]))


def test_angle_band_runs_in_the_sense_of_motion():
    """Slotting machine, crank clockwise from 300°: [300, 60] is the 240° cutting arc."""
    model = variant(
        "slotting_machine",
        load=(
            r"\nloads:\n",
            "\nloads:\n  brake:\n    type: torque\n    link: crank\n    value: 5\n"
            "    active: [{angle: [300, 60]}]\n",
        ),
    )
    base = ks.analyze(ks.load("mechanisms/slotting_machine.yaml"), friction=False)
    r = ks.analyze(model, friction=False)
    on = np.abs(r["motor.torque"] - base["motor.torque"]) > 1e-9
    expected = np.arange(360) <= 240  # rows 0…240: 300° down to 60°
    np.testing.assert_array_equal(on, expected)
    events = [
        (e.switch, round(float(np.degrees(e.coordinate)) % 360, 9))
        for e in r.events
        if e.load == "brake"
    ]
    assert events == [("on", 300.0), ("off", 60.0)]


def test_every_load_and_condition_kind_the_loader_accepts_has_its_entry():
    """Each kind a file may name is one entry of kinetics/kinds.py, and what the entry says
    of itself agrees with what it does: a couple kind applies a couple only, a force kind a
    force only, a kind that opposes a rate has one.  A resisting torque of 5 N·m on the
    crank turning at +2 and −3 rad/s is −5 and +5 N·m; held on a piece where the crank
    turns forwards it is a torque of −5 N·m without conditions."""
    from kinetostatics.io.loads import CONDITION_TYPES, LOAD_TYPES
    from kinetostatics.kinetics.kinds import CONDITION_KINDS, LOAD_KINDS
    from kinetostatics.model import Condition, Load

    assert sorted(LOAD_KINDS) == sorted(LOAD_TYPES)
    assert sorted(CONDITION_KINDS) == sorted(CONDITION_TYPES)
    r = ks.analyze(ks.load("mechanisms/slider_crank.yaml"), positions=[0.3, 0.3])
    system, q, qd = r.system, r.q, r.qd.copy()
    k = system.link_index("crank")
    qd[:, 3 * k + 2] = [2.0, -3.0]
    axis = np.array([1.0, 0.0])
    for name, kind in LOAD_KINDS.items():
        load = Load("L", name, "crank", 5.0 if kind.couple else axis, "A", axis)
        force, couple = kind.applied(system, load, q, qd, load.value_at(r.coordinate, None), 1.0)
        assert (couple is not None) == kind.couple, name
        assert (force is None) == kind.couple, name
        assert (kind.rate(system, load, q, qd)[0] is not None) == kind.opposes, name
    for name, kind in CONDITION_KINDS.items():  # switches by level, or by the schedule
        cond = Condition(name, "crank", "A", axis, (0.0, 1.0))
        assert bool(kind.levels(cond)) != kind.scheduled, name
    rt = LOAD_KINDS["resisting_torque"]
    load = Load("M", "resisting_torque", "crank", 5.0)
    np.testing.assert_array_equal(rt.applied(system, load, q, qd, 5.0, 1.0)[1], [-5.0, 5.0])
    (held,) = rt.held(system, load, 1.0)
    assert (held.kind, held.value, held.active) == ("torque", -5.0, ())


def test_a_point_that_conditions_and_a_load_share_is_evaluated_once(monkeypatch):
    """The slotting machine's cutting force is a resistance at the ram's tool point, on
    while the ram moves and within its travel band: the loads' evaluation computes that
    point's state once (not once per condition and once for the resistance), and the
    forces are those of three evaluations."""
    from kinetostatics.kinematics.schedule import schedule
    from kinetostatics.kinetics import forces, kinds

    model = ks.load("mechanisms/slotting_machine.yaml")
    r = ks.analyze(model, friction=False)
    ref = schedule(r.system).reference
    args = (r.system, r.q, r.qd, r.coordinate, r.extremes, ref)
    calls = []
    counted = kinds.point_state

    def counting(*a, **kw):
        calls.append(1)
        return counted(*a, **kw)

    monkeypatch.setattr(kinds, "point_state", counting)
    once = forces.external_forces(*args)
    assert len(calls) == 1
    monkeypatch.setattr(kinds, "points_once", _nothing_kept)
    monkeypatch.setattr(forces, "points_once", _nothing_kept)
    calls.clear()
    np.testing.assert_array_equal(forces.external_forces(*args), once)
    assert len(calls) == 3


def _nothing_kept(system):
    import contextlib

    return contextlib.nullcontext()
