"""Hard cases: extreme scales, speeds and mass ratios of the offset slider-crank.

Each case is a YAML file (tests/hard/slider_crank_*.yaml, or the shipped
slider-crank at another speed or mass ratio) analysed over a full cycle of 360
positions, both by the closed-form fast path and by the general Newton path
(closed forms disabled), and compared with the independent closed form
tests/oracles/slider_crank_closed_form.py, whose data are read off the loaded
model.  Errors (the worst over the cycle):

- pose: max |Δx|, |Δy| / L_ref and |Δθ| (rad) of every moving link;
- q̇, q̈: per coordinate max|error| / max|exact| (coordinates ≡ 0 skipped);
- reactions: per joint max |ΔF| / max |F| (O, A, B as vectors, the slide's N);
- torque: the frictionless driving torque, and the approximate friction torque
  against the source's eq. 9, each relative to its largest magnitude.

Every error must stay ≤ ``LIMIT`` = 1e-12.  The measured worst is about 1e-15
(round-off; docs/accuracy.md, from ``python tests/benchmarks/accuracy_scales.py``):
the limit is tighter than the general 1e-9 so that a loss of more than three
digits at an extreme scale fails, with a thousandfold margin for other
platforms.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.kinematics import dyads
from tests.oracles import slider_crank_closed_form as cf

ROOT = Path(__file__).resolve().parents[2]
LIMIT = 1e-12


def _sub(path: str, *pairs: tuple[str, str]) -> tuple[str, str]:
    text = (ROOT / path).read_text()
    for old, new in pairs:
        assert old in text, (path, old)
        text = text.replace(old, new)
    return text, Path(path).name


CASES = {
    "micro (µm, 20,000 rpm)": ("tests/hard/slider_crank_micro.yaml",),
    "20 m (10 rpm)": ("tests/hard/slider_crank_20m.yaml",),
    "10 rpm": ("mechanisms/slider_crank.yaml", ("speed: 300", "speed: 10")),
    "20,000 rpm": ("mechanisms/slider_crank.yaml", ("speed: 300", "speed: 20000")),
    "heavy slider, light rod (1e6)": ("tests/hard/slider_crank_mass_ratio.yaml",),
    "light slider, heavy rod (1e6)": (
        "tests/hard/slider_crank_mass_ratio.yaml",
        ("m_rod: 1.0e-3", "m_rod: 1000"),
        ("J_rod: 1.0e-5", "J_rod: 10"),
        ("m_slider: 1000", "m_slider: 1.0e-3"),
    ),
}


def model(case: str) -> ks.Model:
    path, *pairs = CASES[case]
    text, name = _sub(path, *pairs)
    return ks.loads(text, file=name)


def oracle(system: ks.System) -> cf.SliderCrank:
    """The closed form's data, read off the model (points are stored relative to
    the centre of mass; the links' frames lie along O→A and A→B)."""
    m = system.model
    crank, rod, slider = m.link("crank"), m.link("rod"), m.link("slider")
    load = m.loads[0]
    return cf.SliderCrank(
        a=float(crank.points["A"][0] - crank.points["O"][0]),
        b=float(rod.points["B"][0] - rod.points["A"][0]),
        e=float(m.link(m.ground.name).points["guide"][1]),
        r1=float(-crank.points["O"][0]),
        r2=float(-rod.points["A"][0]),
        m1=crank.mass,
        m2=rod.mass,
        m3=slider.mass,
        J1=crank.inertia,
        J2=rod.inertia,
        omega1=float(m.drivers[0].motion.speed),
        g=tuple(float(x) for x in m.gravity),
        Fr=float(np.ravel(load.value)[0]),
        rho_O=m.joint("O").rho,
        rho_A=m.joint("A").rho,
        rho_B=m.joint("B").rho,
        f=m.joint("slide").f,
        L_ref=system.l_ref,
    )


def _columns(x, ref) -> float:
    scale = np.max(np.abs(ref), axis=0)
    keep = scale > 1e-12 * np.max(scale)
    return float(np.max(np.max(np.abs(x - ref), axis=0)[keep] / scale[keep]))


def _vector(x, ref) -> float:
    return float(np.max(np.linalg.norm(x - ref, axis=-1)) / np.max(np.linalg.norm(ref, axis=-1)))


@dataclass
class Errors:
    pose: float
    velocity: float
    acceleration: float
    reactions: float
    torque: float
    torque_friction: float

    @property
    def worst(self) -> float:
        return max(vars(self).values())


def errors(m: ks.Model, general: bool = False) -> Errors:
    """Errors of one analysis against the closed form (general: Newton path)."""
    saved = dyads.closed_form
    if general:
        dyads.closed_form = lambda *a, **k: None
    try:
        system = ks.build_system(m)
        r = ks.analyze(system)
    finally:
        dyads.closed_form = saved
    p = oracle(system)
    phi = r.coordinate
    q, qd, qdd = cf.state(p, phi)
    d = r.q - q
    d[:, 2::3] = (d[:, 2::3] + np.pi) % (2 * np.pi) - np.pi
    d[:, 0::3] /= system.l_ref
    d[:, 1::3] /= system.l_ref
    reac = cf.reactions(p, phi)
    rel = [_vector(np.stack([r[f"{j}.Fx"], r[f"{j}.Fy"]], -1), reac[f"F_{j}"]) for j in "OAB"]
    rel.append(float(np.max(np.abs(r["slide.N"] - reac["N"])) / np.max(np.abs(reac["N"]))))
    eq9 = cf.friction_approx_torque_eq9(p, phi)
    return Errors(
        pose=float(np.max(np.abs(d))),
        velocity=_columns(r.qd, qd),
        acceleration=_columns(r.qdd, qdd),
        reactions=max(rel),
        torque=float(np.max(np.abs(r["motor.torque"] - reac["M1"])) / np.max(np.abs(reac["M1"]))),
        torque_friction=float(
            np.max(np.abs(r["motor.torque_friction_approx"] - eq9)) / np.max(np.abs(eq9))
        ),
    )


@pytest.mark.parametrize("general", [False, True], ids=["fast path", "Newton path"])
@pytest.mark.parametrize("case", list(CASES))
def test_accuracy_against_the_closed_form(case, general):
    err = errors(model(case), general)
    assert err.worst <= LIMIT, err


def test_the_cases_are_extreme():
    """The files really are what the names say (so the accuracy claim covers them)."""
    sizes = {c: ks.build_system(model(c)).l_ref for c in CASES}
    assert sizes["micro (µm, 20,000 rpm)"] == pytest.approx(350e-6)
    assert sizes["20 m (10 rpm)"] == pytest.approx(20.0)
    speeds = {c: abs(model(c).drivers[0].motion.speed) * 60 / (2 * np.pi) for c in CASES}
    assert speeds["10 rpm"] == pytest.approx(10) and speeds["20,000 rpm"] == pytest.approx(20000)
    for c, heavy, light in (
        ("heavy slider, light rod (1e6)", "slider", "rod"),
        ("light slider, heavy rod (1e6)", "rod", "slider"),
    ):
        m = model(c)
        assert m.link(heavy).mass / m.link(light).mass == pytest.approx(1e6)


def test_general_path_really_runs_newton(monkeypatch):
    """With the closed forms disabled the solve iterates (the Newton path is tested)."""
    from kinetostatics.kinematics.positions import solve_positions
    from kinetostatics.kinematics.schedule import sample_times, schedule

    monkeypatch.setattr(dyads, "closed_form", lambda *a, **k: None)
    system = ks.build_system(model("micro (µm, 20,000 rpm)"))
    sched = schedule(system)
    sol = solve_positions(system, sample_times(system, sched, None)[0], sched)
    assert np.min(sol.iterations) >= 1


def _micro(scale: str) -> ks.Model:
    """The micro slider-crank with every length multiplied by ``scale``."""
    text, name = _sub(
        "tests/hard/slider_crank_micro.yaml",
        (
            "{a: 100, b: 350, e: -20, r1: 30, r2: 120}",
            f"{{s: {scale}, a: 100*s, b: 350*s, e: -20*s, r1: 30*s, r2: 120*s}}",
        ),
        ("{A: [100, 0], B: [440, -20]}", "{A: [100*s, 0], B: [440*s, -20*s]}"),
        ("radius: 1.5}", "radius: 1.5*s}"),
        ("radius: 1.2}", "radius: 1.2*s}"),
        ("radius: 1.0}", "radius: 1.0*s}"),
    )
    return ks.loads(text, file=name)


def test_condition_number_does_not_depend_on_scale(recwarn):
    base = ks.analyze(_micro("1"))["rod_slider.cond"]  # 350 µm rod
    small = ks.analyze(_micro("0.1"))["rod_slider.cond"]  # 35 µm rod
    assert not [w for w in recwarn if issubclass(w.category, ks.NearSingularWarning)]
    np.testing.assert_allclose(small, base, rtol=1e-6)
    tiny = errors(_micro("0.01"))  # 3.5 µm rod: must assemble
    assert tiny.worst <= LIMIT
