"""Course-design quantities: the swing, limit positions and time ratio of rockers and of
the file's named output, against the closed forms of the Grashof four-bar and the
crank-guide-bar; the CLI for effort-driven files and cranks that cannot turn fully."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.dynamics.stages import cycle_stage, full_summary
from kinetostatics.errors import ModelError


def fourbar(a=100.0, b=350.0, c=250.0, d=300.0, start=0.0, speed=120.0, extra="") -> str:
    """A crank-rocker (crank a, coupler b, rocker c, frame d, mm), B sketched above."""
    phi = math.radians(start)
    ax, ay = a * math.cos(phi), a * math.sin(phi)
    # B: circle about A (b) and about D (c), the intersection above the line A-D
    dx, dy = d - ax, -ay
    dist = math.hypot(dx, dy)
    along = (b * b - c * c + dist * dist) / (2 * dist)
    h = math.sqrt(b * b - along * along)
    ux, uy = dx / dist, dy / dist
    bx, by = ax + along * ux - h * uy, ay + along * uy + h * ux
    return f"""
name: four-bar
units: {{length: mm, angle: deg, speed: rpm}}
links:
  ground: {{points: {{O: [0, 0], D: [{d}, 0]}}}}
  crank: {{points: {{O: [0, 0], A: [{a}, 0]}}, com: [{a / 2}, 0], mass: 1, inertia: 0.001}}
  coupler: {{points: {{A: [0, 0], B: [{b}, 0]}}, com: [{b / 2}, 0], mass: 2, inertia: 0.02}}
  rocker: {{points: {{D: [0, 0], B: [{c}, 0]}}, com: [{c / 2}, 0], mass: 1.5, inertia: 0.008}}
joints:
  O: {{type: revolute, links: [ground, crank]}}
  A: {{type: revolute, links: [crank, coupler]}}
  B: {{type: revolute, links: [coupler, rocker]}}
  D: {{type: revolute, links: [ground, rocker]}}
drivers:
  motor: {{joint: O, motion: {{speed: {speed}}}}}
sketch: {{A: [{ax:.6f}, {ay:.6f}], B: [{bx:.6f}, {by:.6f}]}}
analysis: {{start: {start}, sweep: 360, positions: 72}}
{extra}"""


def grashof_limits(a, b, c, d):
    """The closed form: at the limit positions crank and coupler are collinear, B at
    a distance b + a (extended) or b − a (folded) from O; the law of cosines gives the
    rocker angle (B above the frame) and the crank angle at each."""

    def at(r):
        rocker = math.pi - math.acos((c * c + d * d - r * r) / (2 * c * d))
        towards_b = math.acos((r * r + d * d - c * c) / (2 * r * d))
        return towards_b, rocker

    phi_ext, psi_ext = at(b + a)
    phi_fold, psi_fold = at(b - a)
    crank_ext, crank_fold = phi_ext, phi_fold + math.pi  # folded: the crank points away
    theta = abs(phi_fold - phi_ext)  # the crank angle between the limit positions
    return {
        "swing": math.degrees(abs(psi_fold - psi_ext)),
        "K": (math.pi + theta) / (math.pi - theta),
        "crank": sorted(math.degrees(x) % 360 for x in (crank_ext, crank_fold)),
        "rocker": sorted(math.degrees(x) % 360 for x in (psi_ext, psi_fold)),
        "theta": math.degrees(theta),
    }


@pytest.mark.parametrize(
    "dims", [(100, 350, 250, 300), (80, 260, 200, 240), (60, 300, 180, 280)], ids=str
)
def test_crank_rocker_swing_limits_and_time_ratio_match_the_closed_form(dims):
    a, b, c, d = dims
    s = full_summary(ks.analyze(ks.loads(fourbar(a, b, c, d))))
    ref = grashof_limits(a, b, c, d)
    out = s["outputs"]["D"]
    assert out["kind"] == "swing" and out["link"] == "rocker"
    assert out["swing"] == pytest.approx(ref["swing"], abs=1e-8)
    assert out["time_ratio"] == pytest.approx(ref["K"], rel=1e-9)
    assert out["theta_extreme"] == pytest.approx(ref["theta"], abs=1e-7)
    lim = out["limit_positions"]
    crank = sorted([lim["min"]["angle"], lim["max"]["angle"]])
    rocker = sorted([lim["min"]["theta"], lim["max"]["theta"]])
    np.testing.assert_allclose(crank, ref["crank"], atol=1e-7)
    np.testing.assert_allclose(rocker, ref["rocker"], atol=1e-7)
    # min is where the counter-clockwise swing starts: the rocker's least angle here
    assert lim["min"]["theta"] == pytest.approx(min(rocker), abs=1e-7)
    # the crank (driven) is no output
    assert "O" not in s["outputs"]


def test_time_ratio_sense_follows_the_crank():
    """Turning the crank the other way swaps which swing is slow, not K."""
    ccw = full_summary(ks.analyze(ks.loads(fourbar())))["outputs"]["D"]
    cw = full_summary(ks.analyze(ks.loads(fourbar(speed=-120))))["outputs"]["D"]
    assert cw["time_ratio"] == pytest.approx(ccw["time_ratio"], rel=1e-9)
    assert cw["time_increasing_s"] == pytest.approx(ccw["time_decreasing_s"], rel=1e-9)


def test_relative_slide_is_never_an_output():
    """The slotting machine's block slides in the guide bar (two moving links): not an
    output; the bar's swing and the ram's stroke are, each with K = 2 (the file's K)."""
    s = full_summary(ks.analyze(ks.load("mechanisms/slotting_machine.yaml")))
    assert "slot" not in s["outputs"]
    assert s["outputs"]["guide"]["time_ratio"] == pytest.approx(2.0, rel=1e-9)
    bar = s["outputs"]["O3"]
    assert bar["time_ratio"] == pytest.approx(2.0, rel=1e-9)
    # the guide bar's swing: 2·asin(L_O2A/L_O2O3) = θ = 60°
    assert bar["swing"] == pytest.approx(60.0, abs=1e-8)


def test_output_key_names_the_member():
    s = full_summary(ks.analyze(ks.loads(fourbar(extra="output: rocker"))))
    assert s["output"] == "rocker"
    # the named link alone; its swing is the rocker's pair's
    ref = grashof_limits(100, 350, 250, 300)
    assert list(s["outputs"]) == ["D"]  # the rocker's pair on the frame
    out = next(iter(s["outputs"].values()))
    assert out["swing"] == pytest.approx(ref["swing"], abs=1e-8)
    s = full_summary(ks.analyze(ks.loads(fourbar(extra="output: coupler"))))
    assert list(s["outputs"]) == ["coupler"]  # the coupler's own swing (absolute angle)
    assert 0 < s["outputs"]["coupler"]["swing"] < 180


@pytest.mark.parametrize(
    "value, words",
    [
        ("ground", "frame"),
        ("O", "motion driver"),
        ("rockr", "did you mean 'rocker'"),
    ],
)
def test_output_key_refuses_what_is_not_an_output(value, words):
    with pytest.raises(ModelError, match=words) as info:
        ks.loads(fourbar(extra=f"output: {value}"), file="f.yaml")
    assert "output" in str(info.value)


def test_output_key_refuses_a_relative_slide():
    text = open("mechanisms/slotting_machine.yaml").read() + "\noutput: slot\n"
    with pytest.raises(ModelError, match="two moving links"):
        ks.loads(text)
    ram = ks.loads(open("mechanisms/slotting_machine.yaml").read() + "\noutput: guide\n")
    s = ks.analyze(ks.loads(open("mechanisms/slotting_machine.yaml").read() + "\noutput: ram\n"))
    assert list(full_summary(s)["outputs"]) == ["guide"]
    from kinetostatics.io import dump

    assert dump(ram).count("output: guide") == 1


def test_run_prints_the_swing(tmp_path, capsys):
    f = tmp_path / "fourbar.yaml"
    f.write_text(fourbar())
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 0
    out = capsys.readouterr().out
    ref = grashof_limits(100, 350, 250, 300)
    assert f"swing {ref['swing']:.4f}°" in out and f"K {ref['K']:.4f}" in out
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert s["outputs"]["D"]["swing"] == pytest.approx(ref["swing"], abs=1e-8)


# -- item: effort-driven files and cranks that cannot turn fully --------------------------
def test_run_on_an_effort_driven_file_says_simulate(capsys):
    assert main(["run", "mechanisms/ammunition_swing.yaml", "--out", "/nonexistent/x"]) == 2
    err = capsys.readouterr().err
    assert "effort-driven" in err and "kinetostatics simulate" in err
    assert len(err.strip().splitlines()) == 1


def test_run_reachable_analyses_the_range_of_a_crank_that_cannot_turn(tmp_path, capsys):
    a, b, c, d = 230.0, 350.0, 250.0, 300.0
    f = tmp_path / "nonfull.yaml"
    f.write_text(fourbar(a, b, c, d, start=90))
    # the closed form: A at least |b − c| from D: cos φ ≤ (a² + d² − (b − c)²)/(2ad)
    lo = math.degrees(math.acos((a * a + d * d - (b - c) ** 2) / (2 * a * d)))
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "reachable range is motor from" in err and "run --reachable" in err
    assert f"{lo:.4f}°" in err and f"{360 - lo:.4f}°" in err
    assert main(["run", str(f), "--out", str(tmp_path / "o"), "--reachable"]) == 0
    capsys.readouterr()
    rows = np.genfromtxt(tmp_path / "o" / "results.csv", delimiter=",", names=True, skip_header=1)
    assert rows["angle"].min() == pytest.approx(lo, abs=1e-3)
    assert rows["angle"].max() == pytest.approx(360 - lo, abs=1e-3)


# -- one mean over the cycle for run, report, plot and flywheel ---------------------------
def _means(path):
    from kinetostatics.dynamics.flywheel import design
    from kinetostatics.outputs import plotting as pl
    from kinetostatics.outputs.plotting.curves import _cycle_mean

    model = ks.load(path)
    run = ks.analyze(model)  # what `kinetostatics run` analyses
    pictures = pl.analyze_for_pictures(model, course=True, events=True)  # the report's
    return (
        {
            "run": full_summary(run)["drivers"]["motor"]["mean"],
            "report": full_summary(pictures)["drivers"]["motor"]["mean"],
            "plot": _cycle_mean(cycle_stage(pictures), "motor.torque"),
            "plot_run": _cycle_mean(cycle_stage(run), "motor.torque"),
        },
        run,
        design,
    )


def test_slotting_machine_mean_torque_is_the_cutting_work_over_two_pi_everywhere():
    """docs/validation.md: Q = 1000 N over the band [0.05H, 0.95H] of H = 100 mm is
    90 J per turn; gravity and inertia do no work over a cycle, so the frictionless mean
    driving torque is 90 J/2π, clockwise (the crank turns clockwise: negative)."""
    means, run, design = _means("mechanisms/slotting_machine.yaml")
    exact = -1000.0 * 0.9 * 0.100 / (2 * math.pi)
    for where, value in means.items():
        assert value == pytest.approx(exact, rel=1e-9), where
    fw = design(run)
    assert fw.mean_torque == pytest.approx(-exact, rel=1e-9)  # in the sense of motion
    assert design(ks.load("mechanisms/slotting_machine.yaml")).mean_torque == pytest.approx(
        -exact, rel=1e-9
    )
    assert fw.work_per_cycle == pytest.approx(90.0, rel=1e-9)


def test_fivebar_means_agree_and_balance_the_load_power():
    means, run, _ = _means("mechanisms/geared_fivebar.yaml")
    values = list(means.values())
    assert max(values) - min(values) <= 1e-9 * max(1.0, abs(values[0]))
    # power balance over a cycle: mean(M·ω) = mean(P_external), the power the loads take
    # (T and V periodic: their rates average to zero)
    from kinetostatics.analysis.cycle import cycle_stats

    omega = run.system.motion_drivers[0].driver.motion.speed
    ext = cycle_stats(run, ["power.external"])["power.external"]["mean"]
    assert values[0] * omega == pytest.approx(ext, rel=1e-9, abs=1e-9)


def test_cycle_stats_are_exact_for_a_known_function():
    """The quadrature of the crank angle's sine and square: mean 0, RMS 1/√2, peak 1."""
    from kinetostatics.analysis.cycle import cycle_stats

    r = ks.analyze(ks.loads(fourbar()))
    s = cycle_stats(r, {"sin": lambda res: np.sin(np.radians(res["angle"]))})["sin"]
    assert abs(s["mean"]) < 1e-14
    assert s["rms"] == pytest.approx(1 / math.sqrt(2), rel=1e-13)
    assert s["peak"] == pytest.approx(1.0, rel=1e-12)
    assert s["covered"] == 1.0


# -- the instantaneous efficiency is an efficiency where it is defined -------------------
@pytest.mark.parametrize("name", ["slotting_machine", "slider_crank", "jaw_crusher"])
def test_efficiency_is_defined_where_the_drive_delivers_power_and_bounded(name):
    r = ks.analyze(ks.load(f"mechanisms/{name}.yaml"))
    d = r.system.motion_drivers[0]
    eta = r[f"{d.name}.efficiency"]
    # the driver's input power with and without friction from the power balance
    p_f = r["power.kinetic"] + r["power.potential"] + r["power.external"] + r["power.friction"]
    p_0 = r["power.input"]
    defined = np.isfinite(eta)
    expect = (p_f > 1e-9 * np.max(np.abs(p_f))) & (p_0 >= -1e-9 * np.max(np.abs(p_0)))
    # away from the two boundaries (where round-off decides) the definition holds
    clear = np.abs(p_f) > 1e-6 * np.max(np.abs(p_f))
    clear &= np.abs(p_0) > 1e-6 * np.max(np.abs(p_0))
    clear &= r["friction.status"] != 2
    np.testing.assert_array_equal(defined[clear], expect[clear])
    assert np.all((eta[defined] >= 0.0) & (eta[defined] <= 1.0 + 1e-9))
    # η = P₀/P_f there, P_f from the power balance with friction (independent of the column)
    np.testing.assert_allclose(eta[defined & clear], (p_0 / p_f)[defined & clear], rtol=1e-7)
    assert (~defined).any() and defined.any()


# -- the horizontal shaper -----------------------------------------------------------------
def test_shaper_stroke_time_ratio_and_cutting_work_match_the_crank_guide_bar_closed_form():
    """Crank r = 110 mm, centre distance L = 380 mm, lever 540 mm: the lever's limit
    positions are tangent to the crank circle, θ = 2·asin(r/L), K = (180+θ)/(180−θ), the
    lever swings θ and the ram's stroke is H = 2·L_O3B·sin(θ/2) (the ram line through
    the middle of B's sagitta: the link has the same slope at both limits).  The mean
    frictionless driving torque is the cutting work P·0.9H over 2π."""
    r, big_l, lever, p = 110.0, 380.0, 540.0, 7000.0
    theta = 2 * math.asin(r / big_l)
    k_ratio = (math.pi + theta) / (math.pi - theta)
    stroke = 2 * lever * math.sin(theta / 2)
    result = ks.analyze(ks.load("mechanisms/shaper.yaml"))
    s = full_summary(result)
    assert s["output"] == "ram"
    ram = s["outputs"]["guide"]
    assert ram["stroke"] * 1e3 == pytest.approx(stroke, rel=1e-9)
    assert ram["time_ratio"] == pytest.approx(k_ratio, rel=1e-9)
    assert ram["theta_extreme"] == pytest.approx(math.degrees(theta), abs=1e-7)
    # the slow stroke is the working stroke (the ram moving left), where it cuts
    lo, hi = ram["limit_positions"]["min"], ram["limit_positions"]["max"]
    assert ram["time_decreasing_s"] > ram["time_increasing_s"]
    # the limit positions: O3A tangent to the crank circle, a right angle at A, so the
    # crank points 270° ± acos(r/L) (O3 straight below O2)
    expect = sorted(270 + s * math.degrees(math.acos(r / big_l)) for s in (-1, 1))
    np.testing.assert_allclose(sorted([lo["angle"], hi["angle"]]), expect, atol=1e-7)
    mean = s["drivers"]["motor"]["mean"]
    assert mean == pytest.approx(p * 0.9 * stroke * 1e-3 / (2 * math.pi), rel=1e-9)
    lever_swing = full_summary(
        ks.analyze(
            ks.loads(open("mechanisms/shaper.yaml").read().replace("output: ram", "output: lever"))
        )
    )["outputs"]["O3"]
    assert lever_swing["swing"] == pytest.approx(math.degrees(theta), abs=1e-8)
    assert lever_swing["time_ratio"] == pytest.approx(k_ratio, rel=1e-9)


# -- the resisting torque -------------------------------------------------------------------
PUMP = """
loads:
  pump: {type: resisting_torque, link: rocker, value: 20}
"""


def test_resisting_torque_power_balance_and_the_work_of_two_swings():
    """−M·sign(ω) on the rocker consumes M·|ω| (power.external), the power balance holds,
    and per turn it takes the work M·2ψ (ψ the swing, Grashof closed form): the mean
    driving torque on a massless linkage is M·2ψ/2π, integrated exactly across the
    rocker's reversals."""
    text = fourbar().replace("mass: 1, inertia: 0.001", "mass: 0, inertia: 0")
    text = text.replace("mass: 2, inertia: 0.02", "mass: 0, inertia: 0")
    text = text.replace("mass: 1.5, inertia: 0.008", "mass: 0, inertia: 0") + PUMP
    r = ks.analyze(ks.loads(text))
    w = r["rocker.omega"]
    np.testing.assert_allclose(r["power.external"], 20.0 * np.abs(w), rtol=1e-12, atol=1e-12)
    assert r.checks.ok
    # the driving torque balances it at every row: M_drive·ω_crank = M·|ω_rocker|
    np.testing.assert_allclose(
        r["motor.torque"] * 4 * math.pi, 20.0 * np.abs(w), rtol=1e-9, atol=1e-9
    )
    psi = math.radians(grashof_limits(100, 350, 250, 300)["swing"])
    mean = full_summary(r)["drivers"]["motor"]["mean"]
    assert mean == pytest.approx(20.0 * 2 * psi / (2 * math.pi), rel=1e-9)


def test_resisting_torque_flips_with_the_rockers_direction():
    r = ks.analyze(ks.loads(fourbar() + PUMP))
    base = ks.analyze(ks.loads(fourbar()))
    w = r["rocker.omega"]
    # the couple it adds to the rocker: −20·sign(ω); its effect on the driving torque is
    # that couple's virtual power over the crank speed
    extra = r["motor.torque"] - base["motor.torque"]
    np.testing.assert_allclose(extra * 4 * math.pi, 20.0 * np.abs(w), rtol=1e-9, atol=1e-9)
    assert (w > 0).any() and (w < 0).any()
    rev = ks.analyze(ks.loads(fourbar(speed=-120) + PUMP))
    # the crank turned the other way: the rocker's ω reverses, the couple with it
    np.testing.assert_allclose(
        rev["power.external"] - ks.analyze(ks.loads(fourbar(speed=-120)))["power.external"],
        20.0 * np.abs(rev["rocker.omega"]),
        rtol=1e-9,
        atol=1e-9,
    )


def test_resisting_torque_equals_two_torques_switched_by_moving():
    """B on the rocker (θ between 70° and 127°) moves left exactly when ω > 0, so the
    resisting torque is −20 while B moves left and +20 while it moves right."""
    two = """
loads:
  against_ccw: {type: torque, link: rocker, value: -20,
                active: [{moving: [-1, 0], point: rocker.B}]}
  against_cw: {type: torque, link: rocker, value: 20,
               active: [{moving: [1, 0], point: rocker.B}]}
"""
    a = ks.analyze(ks.loads(fourbar() + PUMP))
    b = ks.analyze(ks.loads(fourbar() + two))
    for col in ("motor.torque", "D.Fx", "D.Fy", "B.Fx", "power.external"):
        np.testing.assert_allclose(a[col], b[col], rtol=1e-12, atol=1e-9)


def test_resisting_torque_at_a_joint_acts_on_both_links():
    """At the coupler–rocker pin B: −M·sign(ω_rocker − ω_coupler) on the rocker and the
    reaction on the coupler; it consumes M·|ω_rel|."""
    rel = """
loads:
  hinge: {type: resisting_torque, link: rocker, joint: B, value: 5}
"""
    r = ks.analyze(ks.loads(fourbar() + rel))
    base = ks.analyze(ks.loads(fourbar()))
    w_rel = r["rocker.omega"] - r["coupler.omega"]
    np.testing.assert_allclose(
        r["power.external"] - base["power.external"], 5.0 * np.abs(w_rel), rtol=1e-9, atol=1e-9
    )
    assert r.checks.ok


@pytest.mark.parametrize(
    "load, words",
    [
        (
            "{type: resisting_torque, link: rocker, joint: O, value: 5}",
            "must be a revolute that holds",
        ),
        ("{type: torque, link: rocker, joint: D, value: 5}", "resisting_torque only"),
        ("{type: resisting_torque, link: rocker, point: B, value: 5}", "not at a point"),
        ("{type: resisting_torque, link: rocker, joint: Q, value: 5}", "unknown joint"),
    ],
)
def test_resisting_torque_mistakes_are_named(load, words):
    with pytest.raises(ModelError, match=words):
        ks.loads(fourbar() + f"\nloads:\n  pump: {load}\n", file="f.yaml")


# -- units in force, a note without units:, implausible magnitudes --------------------------
def test_run_without_units_notes_it_and_warns_naming_the_keys(tmp_path, capsys):
    f = tmp_path / "nounits.yaml"
    f.write_text(fourbar().replace("units: {length: mm, angle: deg, speed: rpm}", ""))
    assert main(["run", str(f), "--out", str(tmp_path / "o")]) == 0
    out, err = capsys.readouterr()
    assert "units: length m, angle rad" in out and "(SI)" in out
    assert err.count("no units: key") == 1
    # the crank of 100 "mm" is 100 m: named with its key and line
    assert f"{f}:" in err and "links.crank: link 'crank' is 100 m long" in err
    # the driving torque of a 300 m machine is implausible: named by the driver
    assert "drivers.motor" in err and "peak driving torque" in err


def test_check_prints_the_units_in_force_and_no_note_when_given(capsys):
    assert main(["check", "mechanisms/shaper.yaml"]) == 0
    out, err = capsys.readouterr()
    assert "units: length mm, angle deg, speed rpm" in out
    assert "no units" not in err and "warning" not in err


@pytest.mark.parametrize(
    "edit, key",
    [
        (("speed: 120", "speed: 20000"), "drivers.motor"),
        (
            ("\nsketch:", "\nloads: {brake: {type: torque, link: rocker, value: 2e6}}\nsketch:"),
            "loads.brake",
        ),
    ],
)
def test_implausible_speed_and_torque_are_named(edit, key, tmp_path, capsys):
    from kinetostatics.io.plausible import magnitude_warnings

    text = fourbar().replace("speed: 120.0", "speed: 120").replace(*edit)
    lines = magnitude_warnings(ks.loads(text, file="f.yaml"))
    assert len(lines) == 1 and key in lines[0] and lines[0].startswith("f.yaml:")


@pytest.mark.parametrize("rpm", [10, 300, 20000])
def test_slider_crank_extreme_angle_is_its_closed_form_at_any_speed(rpm):
    """θ_extreme of the offset slider-crank (a = 100, b = 350, e = −20 mm) against
    asin(e/(b − a)) − asin(e/(b + a)) at 10, 300 and 20,000 rpm: its limit positions are
    refined until Newton's step is 1e-14 of the time the crank takes to turn 1 rad (it was
    of 1 s: 7.3e-12 of θ at 300 and at 20,000 rpm; 1.1e-12 now, at 10 rpm as before)."""
    a, b, e = 100.0, 350.0, -20.0
    theta = math.degrees(abs(math.asin(e / (b - a)) - math.asin(e / (b + a))))
    text = open("mechanisms/slider_crank.yaml", encoding="utf-8").read()
    model = ks.loads(text.replace("speed: 300", f"speed: {rpm}"))
    assert model.drivers[0].motion.speed == pytest.approx(rpm * math.pi / 30)
    slide = full_summary(ks.analyze(model))["outputs"]["slide"]
    assert slide["theta_extreme"] == pytest.approx(theta, rel=2e-12)
