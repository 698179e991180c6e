"""Hard cases for positions: a change point, the edge of assembly, sketches
that select or fail to select a branch, and links that cannot reach."""

import re

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.errors import AssemblyError, ModelError
from tests.helpers import rel_err
from tests.oracles import slider_crank_closed_form as cf

CHANGE_POINT = "tests/hard/fourbar_change_point.yaml"


@pytest.fixture(scope="module")
def change_point():
    return ks.load(CHANGE_POINT)


def test_change_point_is_reported_and_crossed_smoothly(change_point):
    r = ks.analyze(change_point, positions=np.radians(90 + np.arange(0, 360, 0.5) + 0.1))
    assert len(r.singular) == 1
    s = r.singular[0]
    assert s.group == "RRR dyad {coupler, rocker}"
    assert np.degrees(s.coordinate) == pytest.approx(180.0, abs=1e-6)
    assert s.condition > 1e8
    # C¹ path: velocities agree with central differences of positions across 180°
    h = r.t[1] - r.t[0]
    fd = (r.q[2:] - r.q[:-2]) / (2 * h)
    assert np.max(np.abs(fd - r.qd[1:-1])) < 1e-3 * np.max(np.abs(r.qd))
    # the determinant's sign changes exactly there (the branch signature flips once)
    k = np.argmin(np.abs(r["angle"] - 180.1))
    assert r["coupler_rocker.cond"][k] > 1e3


def test_change_point_on_the_output_grid_gives_finite_results(change_point):
    with pytest.warns(ks.NearSingularWarning):
        r = ks.analyze(change_point)  # 90 + k°, so 180° is a row
    row = int(np.argmin(np.abs(r["angle"] - 180.0)))
    assert r["angle"][row] == pytest.approx(180.0)
    assert np.isfinite(r["rocker.omega"]).all()
    assert r["coupler_rocker.cond"][row] > 1e8


def test_edge_of_assembly_matches_closed_form():
    r = ks.analyze(ks.load("tests/hard/slider_crank_edge.yaml"))
    p = cf.SliderCrank(a=0.1, b=0.1201, e=-0.02)
    k = cf.kinematics(p, np.radians(r["angle"]))
    assert r.singular == ()
    cond = r["rod_slider.cond"]  # nearly singular at 90°: cos φ2 = 0.041
    assert r["angle"][np.argmax(cond)] == pytest.approx(90.0)
    assert cond[90] > 10 * cond[270]  # cos φ2 = 0.75 at 270°
    for ours, theirs in (("slider.x", "xB"), ("rod.omega", "omega2"), ("rod.alpha", "alpha2")):
        assert rel_err(r[ours], k[theirs]) < 1e-9


def _with_sketch(b: str) -> ks.Model:
    text = open(CHANGE_POINT).read().replace("B: [2.46, 1.4]", f"B: {b}")
    return ks.loads(text, file="fourbar.yaml")


def test_sketch_selects_the_branch():
    up = ks.analyze(_with_sketch("[2.46, 1.4]"), positions=[np.radians(90)])
    down = ks.analyze(_with_sketch("[1.73, -0.8]"), positions=[np.radians(90)])
    assert up["rocker.B.y"][0] == pytest.approx(1.40227038, abs=1e-7)
    assert down["rocker.B.y"][0] == pytest.approx(-0.80227038, abs=1e-7)


def test_ambiguous_sketch_names_the_group():
    # B sketched on the line A–D: coupler and rocker collinear, no branch chosen
    with pytest.raises(
        ModelError,
        match=r"sketch: the sketch does not decide the assembly "
        r"branch of RRR dyad \{coupler, rocker\}",
    ):
        ks.analyze(_with_sketch("[1.8, 0.4]"))


def test_links_that_cannot_reach_name_group_coordinate_and_miss():
    text = open("tests/hard/slider_crank_edge.yaml").read().replace("0.1201", "0.11")
    with pytest.raises(AssemblyError) as info:
        ks.analyze(ks.loads(text, file="short.yaml"))
    msg = str(info.value)
    assert msg.startswith("RRP dyad {rod, slider} cannot assemble at motor = ")
    angle = float(re.search(r"motor = ([\d.]+)°", msg).group(1))
    # the rod reaches the guide while a sin φ + |e| ≤ b: first failure past asin(0.09/0.1)
    assert np.degrees(np.arcsin(0.09 / 0.1)) - 0.01 < angle < 90.0
    miss = float(re.search(r"miss closing by ([\d.e+-]+) mm", msg).group(1))
    assert 0 < miss < 0.01 * 1e3


def test_near_singular_rows_are_warned_about(change_point):
    with pytest.warns(
        ks.NearSingularWarning,
        match=r"RRR dyad \{coupler, rocker\} is nearly "
        r"singular at 1 position\(s\), worst at motor = 180°",
    ):
        ks.analyze(change_point)


def test_regular_mechanisms_raise_no_near_singular_warning(recwarn):
    ks.analyze(ks.load("tests/hard/slider_crank_edge.yaml"))
    assert not [w for w in recwarn if issubclass(w.category, ks.NearSingularWarning)]


def test_crank_that_cannot_rotate_reports_its_reachable_range():
    """Rocker driven four-bar: its angle β is limited where crank and coupler are
    collinear, |OB| = 3.2 ± 1, i.e. cos β = (|OB|² − 3² − 2.5²)/(2·3·2.5)."""
    model = ks.load("tests/hard/crank_rocker_reversed.yaml")
    lo = np.degrees(np.arccos((4.2**2 - 15.25) / 15))
    hi = np.degrees(np.arccos((2.2**2 - 15.25) / 15))
    with pytest.raises(AssemblyError) as info:
        ks.analyze(model)
    np.testing.assert_allclose(np.degrees(info.value.reachable), [lo, hi], atol=1e-4)
    assert f"the reachable range is motor from {lo:.4f}° to {hi:.4f}°" in str(info.value)
    r = ks.analyze(model, reachable=True)
    assert [s.group for s in r.singular] == ["RRR dyad {crank, coupler}"] * 2
    np.testing.assert_allclose([np.degrees(s.coordinate) for s in r.singular], [lo, hi], atol=1e-4)
    assert len(r) == 180 and not r.full_cycle
    assert lo < r["angle"].min() < lo + 1e-3 and hi - 1e-3 < r["angle"].max() < hi
    # the effort to drive the rocker blows up towards the toggles
    torque = np.abs(r["motor.torque"])
    assert torque[0] > 1e3 * np.median(torque) and torque[-1] > 1e3 * np.median(torque)


TOGGLE = "tests/hard/rocker_into_toggle.yaml"
PSI_TOGGLE = np.degrees(np.arccos((4.2**2 - 3**2 - 2.5**2) / (2 * 3 * 2.5)))  # crank ∥ coupler
T_TOGGLE = 1.5  # ψ = ψ* + 20° + 20°·sin(π t) is lowest at t = 3/4 of the 2 s period


def test_rocker_driven_into_its_toggle_reports_the_singular_position_and_the_blow_up():
    """The motion law touches the toggle ψ* with zero speed at t* = 1.5 s.  Near the
    fold ψ − ψ* ∝ (θ_crank − θ*)², and ψ − ψ* = ½ψ̈(t*)(t − t*)², so the crank passes
    the dead centre at a finite speed (the C¹ path crosses to the other assembly) and
    the rocker torque τ = (power of the loads)/ψ̇ grows like 1/|t − t*|, i.e. like
    (ψ − ψ*)^(−1/2): log-slopes −1 and −1/2, independent of our solver."""
    model = ks.load(TOGGLE)
    r = ks.analyze(model)
    assert len(r.singular) == 1
    s = r.singular[0]
    assert s.group == "RRR dyad {crank, coupler}"
    assert np.degrees(s.coordinate) == pytest.approx(PSI_TOGGLE, abs=1e-6)
    assert s.t == pytest.approx(T_TOGGLE, abs=1e-6)
    assert s.condition > 1e6
    from kinetostatics.outputs.summary import summarize

    assert summarize(r)["singular_positions"] == [
        {
            "group": s.group,
            "angle": pytest.approx(PSI_TOGGLE),
            "time": pytest.approx(T_TOGGLE),
            "condition": s.condition,
        }
    ]
    # past the dead centre the linkage is in its other assembly: one period of the law
    # does not bring it back, so the run is not a cycle
    assert not r.full_cycle
    for name in r.columns:
        assert np.all(np.isfinite(r[name])), name  # no NaN, no inf
    # no branch jump: the crank keeps turning the same way through the dead centre
    omega = r["crank.omega"]
    near = np.abs(r.t - T_TOGGLE) < 0.2
    assert np.all(omega[near] < 0)
    assert np.max(np.abs(np.diff(omega[near]))) < 0.05 * np.max(np.abs(omega))  # a jump: ~4 rad/s
    # the blow-up and its growth rate, approached from both sides
    d = np.array([1e-2, 3e-3, 1e-3, 3e-4, 1e-4])
    for side in (-1.0, 1.0):
        t = T_TOGGLE + side * d
        tau = np.abs(ks.analyze(model, times=t)["motor.torque"])
        dpsi = np.radians(20.0) * (1.0 + np.sin(np.pi * t))  # ψ − ψ*, from the law
        assert np.polyfit(np.log(d), np.log(tau), 1)[0] == pytest.approx(-1.0, abs=0.02)
        assert np.polyfit(np.log(dpsi), np.log(tau), 1)[0] == pytest.approx(-0.5, abs=0.01)
        assert tau[-1] > 1e3 * np.median(np.abs(r["motor.torque"]))


def test_a_law_past_the_toggle_names_the_coordinate_and_the_reachable_range():
    text = open(TOGGLE).read().replace("amplitude: swing,", "amplitude: swing + 1,")
    with pytest.raises(AssemblyError) as info:
        ks.analyze(ks.loads(text, file="past.yaml"))
    msg = str(info.value)
    assert msg.startswith("RRR dyad {crank, coupler} cannot assemble at motor = ")
    angle = float(re.search(r"motor = ([\d.]+)°", msg).group(1))
    assert PSI_TOGGLE - 1.0 <= angle <= PSI_TOGGLE + 1e-4  # printed to 6 digits
    # ψ = ψ* + 20° + 21°·sin(π t) first passes ψ* at t = 1 + asin(20/21)/π
    t_cross = 1.0 + np.arcsin(20 / 21) / np.pi
    t_reached = float(re.search(r"the linkage assembles up to t = ([\d.]+) s", msg).group(1))
    assert t_cross - 1e-3 < t_reached <= t_cross
    hi = np.degrees(np.arccos((2.2**2 - 15.25) / 15))
    np.testing.assert_allclose(np.degrees(info.value.reachable), [PSI_TOGGLE, hi], atol=1e-4)
    assert (
        f"the law spans motor from {PSI_TOGGLE - 1:.4f}° to {PSI_TOGGLE + 41:.4f}°, the linkage "
        f"reaches only motor from {PSI_TOGGLE:.4f}° to {hi:.4f}°"
    ) in msg
