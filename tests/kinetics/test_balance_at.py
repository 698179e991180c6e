"""Where the effort is taken (``balance_at``) changes the effort, not the machine.

With the motion prescribed at the driver's joint, the balancing effort may be
asked at another joint (the pinion shaft of a gear drive, the slide of a
slider-crank).  By virtual power the input power is the same wherever the effort
is taken: τ_k·(relative speed of joint k) = τ_driver·ψ̇ at every position.  So the
power balance, the balancing moment referred to the crank, the energy swing, the
machine's equivalent (reduced) inertia and the flywheel may not depend on it.

Truth used here, independent of the code under test: the relative speeds from the
links' exact angular and point velocities (result columns); the gear ratio from
the teeth (z2/z1, an external mesh reverses the sense); the reduced inertia as a
kinetic energy 2T/ω² = (Σ m v_S² + J ω²)/ω² from the masses and inertias of the
file and the exact velocities; the slider-crank's closed-form kinematics; and the
speed fluctuation of a simulation with the designed flywheel.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.analysis.pipeline import kinetics
from kinetostatics.batch.variants import summary_row
from kinetostatics.dynamics import equivalent, simulate
from kinetostatics.dynamics.flywheel import design, verify
from kinetostatics.kinematics.positions import derivatives
from tests.helpers import ROOT
from tests.oracles import slider_crank_closed_form as cf

JAW = ROOT / "tests" / "hard" / "jaw_crusher_geared.yaml"  # crank at O1, effort at the pinion Om


def at(model: ks.Model, joint: str | None) -> ks.Model:
    """The model with its (single) driver's effort taken at ``joint`` (None: its own)."""
    return replace(model, drivers=tuple(replace(d, balance_at=joint) for d in model.drivers))


def _omega(result, link: str) -> np.ndarray:
    return np.zeros(len(result)) if link == "ground" else result[f"{link}.omega"]


def relative_speed(result, joint: str) -> np.ndarray:
    """The joint's relative speed from the link velocities: ω_j − ω_i for a revolute,
    the sliding speed of its point along the (ground-fixed) axis for a prismatic."""
    j = result.system.model.joint(joint)
    i_, j_ = j.links
    if j.angular:
        return _omega(result, j_) - _omega(result, i_)
    assert i_ == "ground"  # the slides used here: on the frame, point B on link j
    u = np.asarray(j.u, dtype=float)
    return result[f"{j_}.B.vx"] * u[0] + result[f"{j_}.B.vy"] * u[1]


# (file, the driver's own joint, admissible joints to take the effort at): joints whose
# relative speed does not vanish on the analysed rows (there the joint cannot drive).
CASES = [
    (ROOT / "mechanisms" / "slider_crank.yaml", "O", ("slide", "A")),
    (JAW, "O1", ("Om", "A")),
    (ROOT / "mechanisms" / "geared_fivebar.yaml", "O1", ("O2", "C")),
    (ROOT / "mechanisms" / "rack_rocker.yaml", "O", ("guide", "O3")),
]
PAIRS = [(f, own, j) for f, own, joints in CASES for j in joints]
IDS = [f"{f.stem}-{j}" for f, _, j in PAIRS]


def _effort(result) -> np.ndarray:
    name = result.system.motion_drivers[0].name
    return (
        result[f"{name}.torque"] if f"{name}.torque" in result.columns else result[f"{name}.force"]
    )


@pytest.mark.parametrize("path,own,joint", PAIRS, ids=IDS)
def test_the_input_power_is_the_same_wherever_the_effort_is_taken(path, own, joint):
    model = ks.load(path)
    ref = ks.analyze(at(model, None), friction=False)
    alt = ks.analyze(at(model, joint), friction=False)
    speed = relative_speed(alt, joint)
    assert np.min(np.abs(speed)) > 1e-3 * np.max(np.abs(speed))  # admissible here
    p_ref = _effort(ref) * relative_speed(ref, own)
    p_alt = _effort(alt) * speed
    scale = np.max(np.abs(p_ref))
    assert np.max(np.abs(p_alt - p_ref)) <= 1e-12 * scale
    assert np.max(np.abs(alt["power.input"] - p_ref)) <= 1e-12 * scale
    for r in (ref, alt):  # the power balance closes
        assert np.max(np.abs(r["power.residual"])) <= 1e-12 * scale


@pytest.mark.parametrize("path,own,joint", PAIRS, ids=IDS)
def test_the_flywheel_does_not_depend_on_where_the_effort_is_taken(path, own, joint):
    model = ks.load(path)
    ref = design(at(model, None), delta=0.03, ratio=4, positions=720)
    alt = design(at(model, joint), delta=0.03, ratio=4, positions=720)
    for name in (
        "work_per_cycle",
        "mean_torque",
        "energy_swing",
        "inertia",
        "inertia_net",
        "motor_inertia",
        "motor_inertia_net",
    ):
        assert getattr(alt, name) == pytest.approx(getattr(ref, name), rel=1e-9, abs=1e-12), name
    for name in ("mean", "min", "max"):
        assert alt.machine_inertia[name] == pytest.approx(ref.machine_inertia[name], rel=1e-9)
    # where ΔW peaks is a root of M_d − M_b: the moments' round-off (1e-10 of their scale,
    # below) moves it by that over the moment's slope there (~1e-9 rad on the rack rocker)
    assert alt.at_max == pytest.approx(ref.at_max, abs=1e-8)
    np.testing.assert_allclose(
        alt.curve["moment"],
        ref.curve["moment"],
        rtol=0,
        atol=1e-10 * np.max(np.abs(ref.curve["moment"])),
    )


def test_the_pinion_turns_four_times_faster_the_other_way_and_carries_a_quarter():
    """Jaw crusher: pinion z = 20 on the crank's gear z = 80, external mesh."""
    ref = ks.analyze(at(ks.load(JAW), None), friction=False)
    alt = ks.analyze(ks.load(JAW), friction=False)  # the file: balance_at Om
    np.testing.assert_allclose(alt["pinion.omega"] / alt["crank.omega"], -80 / 20, rtol=1e-12)
    np.testing.assert_allclose(
        alt["motor.torque"],
        ref["motor.torque"] / -4.0,
        rtol=0,
        atol=1e-12 * np.max(np.abs(ref["motor.torque"])),
    )


def _kinetic_inertia(result) -> np.ndarray:
    """(Σ m |v_S|² + J ω²)/ψ̇² from the file's masses and inertias and the exact velocities."""
    total = np.zeros(len(result))
    for link in result.system.model.links:
        if link.name == "ground":
            continue
        total += link.mass * (result[f"{link.name}.vx"] ** 2 + result[f"{link.name}.vy"] ** 2)
        total += link.inertia * result[f"{link.name}.omega"] ** 2
    return total / result.system.motion_drivers[0].driver.motion.speed ** 2


@pytest.mark.parametrize(
    "path,joint",
    [(JAW, "Om"), (JAW, None), (ROOT / "mechanisms" / "slider_crank.yaml", "slide")],
    ids=["jaw-Om", "jaw-O1", "slider_crank-slide"],
)
def test_the_machine_inertia_is_its_kinetic_energy(path, joint):
    fw = design(at(ks.load(path), joint), delta=0.03, positions=360)
    j_e = fw.curve["inertia"]
    expected = _kinetic_inertia(fw.curve["result"])
    assert np.all(j_e > 0)
    np.testing.assert_allclose(j_e, expected, rtol=1e-10)
    assert fw.machine_inertia["min"] > 0


def test_the_jaw_crusher_machine_inertia_by_hand():
    """The crank with its gear (3.0) and the pinion seen through 4:1 (0.05·4²) make
    almost all of it; the linkage adds a little, over the cycle."""
    fw = design(ks.load(JAW), positions=360)
    assert 3.8 < fw.machine_inertia["min"] <= fw.machine_inertia["max"] < 3.9
    assert fw.mean_torque > 0  # the motor drives: positive in the sense of motion
    assert fw.motor_inertia == pytest.approx(fw.inertia / 16, rel=1e-15)


def test_equivalent_quantities_refer_an_effort_at_the_slide_to_the_crank():
    """J_e ψ̈ + ½ J_e′ ψ̇² − torque = F_slide·dx_B/dφ, and dx_B/dφ from the closed form."""
    system = ks.build_system(at(ks.load(ROOT / "mechanisms" / "slider_crank.yaml"), "slide"))
    base = ks.analyze(system, friction=False)
    k = np.arange(0, 360, 11)
    q, phi = base.q[k], base.coordinate[k]
    w, alpha = 31.4, -120.0
    eq = equivalent(system, q, phi, speed=w, extremes=base.extremes)
    c = cf.kinematics(cf.SliderCrank(omega1=1.0), phi)
    np.testing.assert_allclose(eq["effort_ratio"], c["vB"], rtol=1e-10)
    qd, qdd, lu = derivatives(system, q, np.full((len(k), 1), w), np.full((len(k), 1), alpha))
    force = kinetics(system, q, qd, qdd, phi[:, None], ref_speed=w, extremes=base.extremes).x0[
        :, -1
    ]
    lhs = eq["inertia"] * alpha + 0.5 * eq["inertia_derivative"] * w**2 - eq["torque"]
    np.testing.assert_allclose(
        lhs, force * c["vB"], rtol=1e-9, atol=1e-10 * np.max(np.abs(force * c["vB"]))
    )
    assert np.all(eq["inertia"] > 0)


def test_simulated_fluctuation_with_the_effort_at_the_pinion():
    """The file (effort at the pinion, δ = 0.03): the designed flywheel under the
    constant mean moment keeps δ within 10 % of the design value — on the crank
    shaft, and on the pinion shaft (J/ratio² added to the pinion, which turns four
    times faster)."""
    model = ks.load(JAW)
    fw = design(model)
    assert verify(model, fw)["delta"] == pytest.approx(0.03, rel=0.10)
    pinion = replace(
        model,
        links=tuple(
            replace(link, inertia=link.inertia + fw.motor_inertia_net)
            if link.name == "pinion"
            else link
            for link in model.links
        ),
    )
    assert verify(pinion, fw, inertia=0.0)["delta"] == pytest.approx(0.03, rel=0.10)


def test_the_batch_row_carries_the_same_flywheel():
    model = ks.load(JAW)
    rows = [
        summary_row(ks.analyze(at(model, j), friction=False), flywheel=True) for j in (None, "Om")
    ]
    assert rows[1]["flywheel.inertia"] == pytest.approx(rows[0]["flywheel.inertia"], rel=1e-9)
    assert rows[1]["flywheel.inertia_net"] == pytest.approx(
        rows[0]["flywheel.inertia_net"], rel=1e-9
    )


def test_simulated_work_of_a_prescribed_driver_with_its_effort_at_a_pinion():
    """A pendulum on a crank pin, the crank turned at 60 rpm through a pinion
    (z = 20 on z = 80) with the effort taken at the pinion, the arm free: without
    friction or loads the drivers' work is the change of the machine's energy."""
    text = (ROOT / "tests" / "dynamics" / "driven_pendulum.yaml").read_text()
    for old, new in (
        (
            "    points: {O: [0, 0]}\n",
            "    points: {O: [0, 0], Om: [0, 100]}\n"
            "  pinion:\n    points: {Om: [0, 0]}\n    inertia: 0.0002\n",
        ),
        (
            "  A: {type: revolute, links: [crank, arm]}\n",
            "  A: {type: revolute, links: [crank, arm]}\n"
            "  Om: {type: revolute, links: [ground, pinion]}\n"
            "  mesh: {type: gear, links: [pinion, crank], centres: [Om, O], teeth: [20, 80],"
            " module: 2, mesh: external}\n",
        ),
        ("motion: {speed: 60}}", "motion: {speed: 60}, points: [x, A], balance_at: Om}"),
    ):
        assert old in text
        text = text.replace(old, new)
    sim = simulate(ks.loads(text, file="geared_pendulum.yaml"), 1.0, method="DOP853", rtol=1e-10)
    cols, _ = sim.table(points=21)
    energy, work = cols["energy.total"], cols["work.drivers"]
    assert np.ptp(energy) > 1.0  # the crank does work
    assert np.max(np.abs((work - work[0]) - (energy - energy[0]))) <= 1e-5 * np.ptp(energy)
