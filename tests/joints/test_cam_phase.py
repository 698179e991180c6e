"""Issue 36: a cam must run in phase with its law, and its profile checks must see every
segment; its separation warning is one line; a large friction coefficient is solved fast.

The files in ``tests/cases/`` are the issue's reproducers."""

from __future__ import annotations

import math

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.errors import ModelError
from tests.helpers import ROOT

CASES = ROOT / "tests" / "cases"
RB, RR, D, L = 40.0, 15.0, 120.0, 100.0  # the rocker cam's base circle, roller, pivot, arm
XC = ((RB + RR) ** 2 - L**2 + D**2) / (2 * D)  # the roller centre at zero lift
YC = math.sqrt((RB + RR) ** 2 - XC**2)


def _message(name):
    with pytest.raises(ModelError) as info:
        ks.analyze(ks.load(CASES / name))
    assert len(info.value.problems) == 1
    return str(info.value)


def test_a_roller_sketched_on_the_mirror_side_is_a_model_error():
    """The arm reaches the prime circle at (xc, ±yc); the rise (cw) moves the roller
    outwards from (xc, +yc) only, so that is where the law puts it at cam angle 0."""
    text = _message("cam_sketch_mirror.yaml")
    assert "joints.contact: cam joint 'contact': the follower is out of phase" in text
    assert "while the cam is at 0°" in text and "instead of 0°" in text
    x, y = (float(v) for v in text.split("near [")[1].split("]")[0].split(","))
    assert abs(x - XC) <= 1e-4 and abs(y - YC) <= 1e-4  # printed to 6 digits
    assert "sketch the follower point arm.C" in text


def test_a_rise_of_the_wrong_sense_is_a_model_error():
    """With ``rise: ccw`` the law puts the roller at (xc, −yc) at cam angle 0, the
    mirror of where it is sketched and assembled."""
    text = _message("cam_rise_wrong_sense.yaml")
    assert "out of phase with its law" in text and "while the cam is at 0°" in text
    x, y = (float(v) for v in text.split("near [")[1].split("]")[0].split(","))
    assert abs(x - XC) <= 1e-4 and abs(y + YC) <= 1e-4
    assert "reverse `oscillating.rise`" in text


def test_the_cli_refuses_an_out_of_phase_cam_in_one_line(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["run", str(CASES / "cam_sketch_mirror.yaml"), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "out of phase" in err[0] and "Traceback" not in err[0]
    assert not out.exists()


@pytest.mark.filterwarnings("ignore::kinetostatics.errors.JointWarning")
def test_the_intended_rocker_cam_runs_in_phase():
    """Its contact's cam angle is the cam's rotation at every row; at the law's zero the
    roller centre is at (xc, yc), on the prime circle."""
    r = ks.analyze(ks.load(CASES / "cam_rocker_right.yaml"))
    np.testing.assert_allclose(
        np.mod(r["contact.cam_angle"] - r["cam.theta"] + 180, 360) - 180, 0, atol=1e-9
    )
    row = int(np.argmin(np.abs(np.mod(r["cam.theta"] + 180, 360) - 180)))
    assert abs(r["cam.theta"][row]) <= 1e-12
    assert math.hypot(r["arm.C.x"][row] - XC / 1e3, r["arm.C.y"][row] - YC / 1e3) <= 1e-12


def test_an_offset_that_is_not_the_guides_is_a_model_error():
    """The guide at 15 mm from the cam centre, ``offset: 10``: refused, naming both."""
    text = (ROOT / "mechanisms" / "cam_roller.yaml").read_text()
    text = text.replace("points: {O: [0, 0], G: [e, 0]}", "points: {O: [0, 0], G: [15, 0]}")
    with pytest.raises(ModelError) as info:
        ks.analyze(ks.loads(text))
    assert "the follower point runs 15 mm from the cam centre across its guide, not at " in str(
        info.value
    ) and "`translating.offset: 10` mm" in str(info.value)


# -- item 16: every segment is checked, however narrow ---------------------------------
def _load_error(text):
    with pytest.raises(ModelError) as info:
        ks.loads(text)
    return str(info.value)


def test_a_rise_over_1e_9_degrees_is_refused_by_the_loader():
    text = _load_error((CASES / "cam_rise_over_1e-9.yaml").read_text())
    assert "joints.contact.motion: cam joint 'contact': the pitch point does not turn" in text
    assert "in motion[0] (rise 20 mm over 1e-09°)" in text


def test_a_narrow_spike_is_refused_by_the_loader_naming_its_segment():
    text = _load_error((CASES / "cam_narrow_spike_undercut.yaml").read_text())
    assert "in motion[1] (rise 2 mm over 0.1°)" in text


def test_a_spike_between_the_uniform_samples_is_undercut():
    """A 0.01 mm spike over 100.05°–100.17°, between two of the 2048 uniform samples
    (100.02° and 100.20°): at its crest a cycloidal rise's s'' = −h(2π/β)² (β = 0.06°)
    bends the pitch curve with a radius far under the 12 mm roller's."""
    src = (CASES / "cam_narrow_spike_undercut.yaml").read_text()
    src = src.replace("{rise: 2, over: 0.1,", "{rise: 0.01, over: 0.06,")
    src = src.replace("{return: 2, over: 0.1,", "{return: 0.01, over: 0.06,")
    src = src.replace("{dwell: 259.75}", "{dwell: 259.83}")
    text = _load_error(src)
    assert "the profile is undercut at cam angle 10" in text and "in motion[" in text
    ang = float(text.split("cam angle ")[1].split("°")[0])
    assert 100.05 <= ang <= 100.17


# -- item 17: one separation warning, its angles as ranges ------------------------------
def test_a_separation_is_warned_once_with_its_angles_as_ranges():
    """The run and its summary (whose cycle integral analyses the quadrature nodes again)
    warn once; the ranges are the runs of consecutive rows with status 1, from the run's
    own columns, each listed once."""
    import warnings

    from kinetostatics.errors import JointWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = ks.analyze(ks.load(CASES / "cam_leaves_duplicate_warning.yaml"))
        r.summary()
    joint = [str(w.message) for w in caught if issubclass(w.category, JointWarning)]
    assert len(joint) == 1, joint
    status = np.asarray(r["contact.status"]) == 1
    rows = np.flatnonzero(status)
    runs = np.split(rows, np.flatnonzero(np.diff(rows) > 1) + 1)
    angle = np.asarray(r["contact.cam_angle"])
    ranges = [f"{angle[g[0]]:.4g}°–{angle[g[-1]]:.4g}°" for g in runs]
    assert len(runs) == 2  # the rise's second half and the return's first (61°–119°, 181°–239°)
    assert (
        f"at {rows.size} of {len(angle)} positions, cam angles {', '.join(ranges)}:" in (joint[0])
    )


def test_a_large_friction_coefficient_inverts_the_profile_once_per_pose(monkeypatch):
    """f = 266: the fixed point diverges and the friction solution follows its homotopy,
    hundreds of iterations, each asking the cam for its contact normal at the same pose.
    The normal (an inversion of the profile by Newton over the law) is computed once per
    pose, not once per iteration: fewer inversions than friction iterations.  The result:
    rows solved by the homotopy (status 1) and self-locked rows (status 2, their
    consistent friction columns empty)."""
    import warnings

    from kinetostatics.joints._camprofile import Synthesis

    calls = [0]
    invert = Synthesis.invert

    def counted(self, *args):
        calls[0] += 1
        return invert(self, *args)

    monkeypatch.setattr(Synthesis, "invert", counted)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = ks.analyze(ks.load(CASES / "cam_friction_266_slow.yaml"))
    status = np.asarray(r["friction.status"])
    iterations = float(np.nansum(r["friction.iterations"]))
    assert np.any(status == 1) and np.any(status == 2)
    assert np.all(np.isnan(np.asarray(r["motor.torque_friction"])[status == 2]))
    assert np.all(np.isfinite(np.asarray(r["motor.torque_friction"])[status == 1]))
    assert iterations > 10 * len(status)  # the homotopy's work
    assert calls[0] < iterations / 2, (calls[0], iterations)


def test_a_guide_that_leaves_the_laws_phase_is_warned():
    """The guide through the follower's start point F(0) but tilted (direction [0.05, 1]
    where the joint says [0, 1]): in phase at the start, out of it wherever the lift is
    not zero — the rise, dwell and return (0°–300° but for round-off at the ends), back
    in it in the last dwell."""
    import warnings

    from kinetostatics.errors import JointWarning

    text = (ROOT / "mechanisms" / "cam_roller.yaml").read_text()
    text = text.replace("points: {O: [0, 0], G: [e, 0]}", "points: {O: [0, 0], G: [e, y0]}")
    text = text.replace("direction: [0, 1]}\n    point: C", "direction: [0.05, 1]}\n    point: C")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = ks.analyze(ks.loads(text))
    phase = [str(w.message) for w in caught if "phase" in str(w.message)]
    assert len(phase) == 1 and issubclass(caught[0].category, JointWarning)
    assert "the follower leaves its law's phase at" in phase[0]
    assert "`translating` (its direction)" in phase[0]
    lo, hi = phase[0].split("cam angles ")[1].split(":")[0].split("–")
    assert 0 < float(lo.rstrip("°")) <= 3 and 297 <= float(hi.rstrip("°")) < 300
    assert np.asarray(r["contact.lift"]).max() > 0  # it ran


@pytest.mark.parametrize("name", ["cam_roller.yaml", "cam_flat_oscillating.yaml"])
def test_the_shipped_cams_stay_in_phase(name):
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ks.analyze(ks.load(ROOT / "mechanisms" / name))
    assert not [w for w in caught if "phase" in str(w.message)]


def test_the_stacked_start_takes_out_a_variant_whose_joint_refuses_its_start(monkeypatch):
    """The vectorised analysis (batch) asks each variant's joints as one analysis does:
    a variant whose joint refuses its start pose is left out with that model error."""
    from kinetostatics.analysis.vectorised import analyze_stacked
    from kinetostatics.joints.revolute import Revolute

    text = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
    models = [ks.loads(text.replace("r1: 30 ", f"r1: {r} ")) for r in (28, 30, 32)]
    assert analyze_stacked(models).failed == {}

    def refuse(self, qi, qj):  # the crank's pin, in the third variant only (its centre of mass)
        return "refused" if self.name == "O" and abs(qj[0] - 0.032) < 1e-9 else ""

    monkeypatch.setattr(Revolute, "start_problem", refuse, raising=False)
    st = analyze_stacked(models)
    assert list(st.failed) == [2] and "refused" in str(st.failed[2])
    assert list(st.members) == [0, 1]
