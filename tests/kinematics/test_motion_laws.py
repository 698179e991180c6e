"""Motion laws other than constant speed (harmonic, polynomial, table), against
the closed-form slider-crank and the laws' own formulas.

The oracle gives q̇ = J(φ)·ω and q̈ = J(φ)·α + H(φ)·ω² with J, H from its
constant-speed solution at ω = 1 (kinematics is linear in α and quadratic in
ω at a given crank angle), so any law ψ(t) is checked independently.
"""

import re

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.model.motion import HarmonicLaw, PolynomialLaw
from tests.oracles import slider_crank_closed_form as cf

BASE = open("mechanisms/slider_crank.yaml").read()
MOTOR = "motor: {joint: O, motion: {speed: 300}}"
LAWS = {
    # ψ = 90° + 120°·sin(2π t / 0.3 s + 10°): the crank swings back and forth
    "harmonic": "{law: harmonic, centre: 90, amplitude: 120, period: 0.3, phase: 10}",
    # ψ = 10° + 200 t + 900 t² − 1500 t³ (deg, s): speeds up, turns back at t ≈ 0.68 s
    "polynomial": "{law: polynomial, coefficients: [10, 200, 900, -1500], duration: 0.8}",
    "table": "{law: table, time: [0, 0.1, 0.25, 0.4, 0.5], value: [0, 60, 200, 150, 300]}",
}


def _model(law: str, analysis: str = "{positions: 121}") -> ks.Model:
    text = BASE.replace(MOTOR, f"motor: {{joint: O, motion: {law}}}")
    text = re.sub(r"analysis: \{[^}]*\}", f"analysis: {analysis}", text)
    return ks.loads(text, file="law.yaml")


def _oracle(phi, w, a):
    p = cf.SliderCrank()
    unit = cf.SliderCrank(**{**p.__dict__, "omega1": 1.0})
    q, jac, hess = cf.state(unit, phi)  # at ω = 1, α = 0: q̇ = J, q̈ = H
    return q, jac * w[:, None], jac * a[:, None] + hess * (w * w)[:, None]


@pytest.mark.parametrize("law", sorted(LAWS))
def test_law_kinematics_match_the_closed_form(law):
    r = ks.analyze(_model(LAWS[law]), friction=False)
    psi, w, a = r.system.motion_drivers[0].driver.motion.value(0.0, r.t)
    q, qd, qdd = _oracle(psi, w, a)
    assert np.degrees(np.ptp(psi)) > 100  # the law really moves the crank
    assert np.any(np.diff(np.sign(w)) != 0) or law == "table"  # and (mostly) turns back
    for ours, ref in ((r.q, q), (r.qd, qd), (r.qdd, qdd)):
        d = ours - ref
        d[:, 2::3] = (d[:, 2::3] + np.pi) % (2 * np.pi) - np.pi
        assert np.max(np.abs(d)) < 1e-9 * np.max(np.abs(ref))
    # power balance closes with the law's ψ̈ (the inertia loads use q̈)
    assert np.max(np.abs(r["power.residual"])) < 1e-9 * np.max(np.abs(r["power.input"]))


def test_harmonic_law_values_are_exact():
    law = _model(LAWS["harmonic"]).drivers[0].motion
    assert isinstance(law, HarmonicLaw)
    t = np.linspace(0.0, 0.3, 7)
    x = 2 * np.pi * t / 0.3 + np.radians(10)
    psi, w, a = law.value(0.0, t)
    np.testing.assert_allclose(psi, np.radians(90 + 120 * np.sin(x)), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(
        w, np.radians(120) * 2 * np.pi / 0.3 * np.cos(x), rtol=1e-14, atol=1e-12
    )
    np.testing.assert_allclose(
        a, -np.radians(120) * (2 * np.pi / 0.3) ** 2 * np.sin(x), rtol=1e-14, atol=1e-10
    )


def test_polynomial_and_table_derivatives_agree_with_differences():
    for text in (LAWS["polynomial"], LAWS["table"]):
        law = _model(text).drivers[0].motion
        t, h = np.linspace(0.01, law.duration - 0.01, 50), 1e-5
        psi = lambda s, law=law: law.value(0.0, s)[0]  # noqa: E731
        _, w, a = law.value(0.0, t)
        np.testing.assert_allclose(w, (psi(t + h) - psi(t - h)) / (2 * h), rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(
            a, (psi(t + h) - 2 * psi(t) + psi(t - h)) / h**2, rtol=1e-3, atol=1e-2
        )
    poly = _model(LAWS["polynomial"]).drivers[0].motion
    assert isinstance(poly, PolynomialLaw)
    np.testing.assert_allclose(np.degrees(poly.coefficients), [10, 200, 900, -1500])


def test_a_harmonic_run_covers_one_period_and_a_polynomial_its_duration():
    r = ks.analyze(_model(LAWS["harmonic"], "{positions: 30}"), friction=False)
    assert r.full_cycle and len(r) == 30
    np.testing.assert_allclose(r["time"], np.arange(30) * 0.3 / 30, atol=1e-15)
    r = ks.analyze(_model(LAWS["polynomial"], "{positions: 9}"), friction=False)
    assert not r.full_cycle
    np.testing.assert_allclose(r["time"], np.linspace(0, 0.8, 9), atol=1e-15)
    periodic = "{law: table, time: [0, 0.1, 0.2, 0.3], value: [0, 90, 30, 0], periodic: true}"
    r = ks.analyze(_model(periodic, "{positions: 12}"), friction=False)
    assert r.full_cycle and len(r) == 12  # the crank swings back to its start
    law = r.system.motion_drivers[0].driver.motion
    # ψ, ψ̇, ψ̈ of a periodic spline agree at both ends (C² across the period)
    np.testing.assert_allclose(
        *(np.array(law.value(0.0, [x]))[:, 0] for x in (0.0, 0.3)), atol=1e-9
    )
    r = ks.analyze(_model(LAWS["polynomial"]), times=[0.2, 0.7], friction=False)
    np.testing.assert_allclose(r["time"], [0.0, 0.5])


def test_constant_speed_is_still_the_default_and_law_constant_is_the_same():
    a = ks.analyze(ks.loads(BASE, file="s.yaml"), friction=False)
    b = ks.analyze(
        ks.loads(
            BASE.replace("motion: {speed: 300}", "motion: {law: constant, speed: 300}"),
            file="s.yaml",
        ),
        friction=False,
    )
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a["motor.torque"], b["motor.torque"])


@pytest.mark.parametrize(
    "law, analysis, message",
    [
        (
            "{law: harmonc, centre: 0, amplitude: 1, period: 1}",
            "{positions: 9}",
            r"law\.yaml:\d+:\d+: drivers\.motor\.motion\.law: unknown motion law 'harmonc' "
            r"\(did you mean 'harmonic'\?\)",
        ),
        (
            "{law: harmonic, centre: 0, amplitude: 0, period: 1}",
            "{positions: 9}",
            r"drivers\.motor\.motion\.amplitude: the amplitude must not be zero",
        ),
        (
            "{law: harmonic, centre: 0, amplitude: 10, period: -1}",
            "{positions: 9}",
            r"drivers\.motor\.motion\.period: must be positive",
        ),
        (
            "{law: harmonic, centre: 0, amplitude: 10}",
            "{positions: 9}",
            r"drivers\.motor\.motion: missing required key 'period'",
        ),
        (
            "{law: polynomial, coefficients: [5], duration: 1}",
            "{positions: 9}",
            r"drivers\.motor\.motion\.coefficients: give from 2 to 11 coefficients",
        ),
        (
            "{law: polynomial, coefficients: [5, 0, 0], duration: 1}",
            "{positions: 9}",
            r"drivers\.motor\.motion\.coefficients: the coefficients c1, c2, … are all zero",
        ),
        (
            "{law: table, time: [0, 0.2, 0.1], value: [0, 1, 2]}",
            "{positions: 9}",
            r"drivers\.motor\.motion\.time: the times must increase",
        ),
        (
            "{law: table, time: [0, 0.1, 0.2], value: [0, 1, 2], periodic: true}",
            "{positions: 9}",
            r"drivers\.motor\.motion\.value: a periodic table must end where it starts",
        ),
        (
            LAWS["harmonic"],
            "{start: 30, positions: 9}",
            r"law\.yaml:\d+:\d+: analysis\.start: start does not apply: driver 'motor' follows a "
            r"harmonic motion law",
        ),
    ],
)
def test_bad_laws_name_the_key_and_line(law, analysis, message):
    with pytest.raises(ks.ModelError, match=message):
        _model(law, analysis)


def test_driver_coordinates_are_refused_for_a_law():
    with pytest.raises(
        ValueError,
        match=r"follows a harmonic motion law: give the positions as "
        r"times, analyze\(\.\.\., times=\.\.\.\)",
    ):
        ks.analyze(_model(LAWS["harmonic"]), positions=np.radians([10.0, 20.0]))


def test_a_law_round_trips_through_dump():
    from kinetostatics.io import dump

    for law in LAWS.values():
        model = _model(law)
        again = ks.loads(dump(model), file="again.yaml")
        t = np.linspace(0, model.drivers[0].motion.duration, 11)
        np.testing.assert_allclose(
            again.drivers[0].motion.value(0.0, t),
            model.drivers[0].motion.value(0.0, t),
            rtol=1e-12,
            atol=1e-12,
        )


def _boom(motion: str, analysis: str) -> ks.Model:
    """The luffing boom of docs/yaml.md (prismatic driver `extend`) with another motion."""
    doc = open("docs/yaml.md").read()
    text = re.search(r"```yaml\n(name: luffing boom.*?)```", doc, re.S).group(1)
    text = text.replace(
        "extend: {joint: cyl, motion: {speed: 50}}", f"extend: {{joint: cyl, motion: {motion}}}"
    )
    text = re.sub(r"analysis: \{[^}]*\}", f"analysis: {analysis}", text)
    return ks.loads(text.replace("speed: mm/s, ", ""), file="boom.yaml")


def test_a_law_on_a_prismatic_driver_follows_the_chain_rule():
    """s = 450 mm + 50 mm/s² · t² over 2 s against the constant-speed run at the same
    strokes: same poses, q̇ = J ṡ and q̈ = J s̈ + H ṡ² with J, H from the run at 50 mm/s."""
    law = ks.analyze(
        _boom("{law: polynomial, coefficients: [450, 0, 50], duration: 2}", "{positions: 11}"),
        friction=False,
    )
    s = law["stroke"]
    np.testing.assert_allclose(s, 0.450 + 0.050 * law.t**2, atol=1e-15)
    const = ks.analyze(
        _boom("{speed: 0.05}", "{start: 450, sweep: 200, positions: 2}"),
        positions=s,
        friction=False,
    )
    sd, sdd = 0.1 * law.t, np.full_like(law.t, 0.1)
    jac, hess = const.qd / 0.05, const.qdd / 0.05**2
    np.testing.assert_allclose(law.q, const.q, atol=1e-12)
    np.testing.assert_allclose(law.qd, jac * sd[:, None], atol=1e-12)
    np.testing.assert_allclose(law.qdd, jac * sdd[:, None] + hess * (sd**2)[:, None], atol=1e-10)


def test_the_reference_speed_is_a_field_taken_from_the_law_at_construction():
    """ψ = t − 2t² on [0, 1]: ψ̇ = 1 − 4t, largest |ψ̇| = 3 at t = 1, first motion forwards
    (+3); over [0, 2] the largest is 7.  A table through (0, 0), (1, 1), (2, 0): the
    not-a-knot spline is the parabola t(2 − t), ψ̇ = 2 − 2t, largest |ψ̇| = 2, forwards.
    The value is kept as a field (no cache filled on first use): it is in the law's
    ``__dict__`` as built, and a replaced law has its own."""
    import dataclasses
    import pickle

    from kinetostatics.model.motion import TableLaw

    law = PolynomialLaw((0.0, 1.0, -2.0), 1.0)
    assert "speed" in vars(law)
    assert law.speed == pytest.approx(3.0, rel=1e-12)
    assert dataclasses.replace(law, duration=2.0).speed == pytest.approx(7.0, rel=1e-12)
    assert pickle.loads(pickle.dumps(law)).speed == pytest.approx(3.0, rel=1e-12)
    table = TableLaw((0.0, 1.0, 2.0), (0.0, 1.0, 0.0))
    assert "speed" in vars(table)
    assert table.speed == pytest.approx(2.0, rel=1e-12)
    assert {f.name for f in dataclasses.fields(law) if not f.init} == {"speed"}
    # a batch stacks variants whose law differs (model/stacking.py): the stacked law is
    # built, and left to the per-variant analysis
    from kinetostatics.model.stacking import stack

    m = ks.load("mechanisms/slider_crank.yaml")
    laws = (law, PolynomialLaw((0.0, 1.5, -2.0), 1.0))
    models = [
        dataclasses.replace(m, drivers=(dataclasses.replace(m.drivers[0], motion=x),)) for x in laws
    ]
    stacked = stack(models).drivers[0].motion
    assert stacked.speed is None and np.shape(stacked.coefficients[1]) == (2, 1)
