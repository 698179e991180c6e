"""Drive sizing (dynamics/drive.py, docs/drive.md): the numbers of the slotting machine against
a direct integration of its torque column on a fine grid, the reduction rule against hand
algebra, the reflected inertia against a motion law's closed form, the motor check, the
loader's messages and the four-quadrant picture."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.integrate import trapezoid

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.dynamics.drive import quadrant_data, reduce, size
from kinetostatics.errors import ModelError
from tests.helpers import ROOT

DRIVE = ROOT / "tests" / "drive" / "slotting_machine_drive.yaml"
TEXT = DRIVE.read_text(encoding="utf-8")
RATIO, ETA = 24.0, 0.9  # the fixture's reduction
OMEGA = 2 * math.pi  # 60 rpm


def _variant(motor: str, flywheel: bool = True) -> str:
    text = TEXT.replace(
        "motor: {rated_torque: 1.6, peak_torque: 4.8, rated_speed: 1500, inertia: 0.0008}",
        f"motor: {motor}",
    )
    if not flywheel:
        text = "\n".join(line for line in text.splitlines() if not line.startswith("flywheel:"))
    return text


def _fine(friction: bool):
    """The crank torque in the sense of motion (CW) on 36,000 crank angles plus both sides of
    each load event, sorted by the travel φ ∈ [0, 2π): (φ, T)."""
    model = ks.load(DRIVE)
    base = ks.analyze(model, friction=False, events=True)
    start = model.analysis.start
    n = 36000
    phi = np.arange(n) * 2 * np.pi / n
    ev = np.sort(np.mod(-(np.array([e.coordinate for e in base.events]) - start), 2 * np.pi))
    phi = np.sort(np.concatenate((phi, ev - 1e-6, ev + 1e-6)))  # the conditions switch within 1e-9
    r = ks.analyze(model, positions=start - phi, friction=friction, events=False)
    column = "motor.torque_friction" if friction else "motor.torque"
    return phi, -np.asarray(r[column])


def _mean(phi, f):
    """Trapezoid rule over one period of the travel (periodic)."""
    x = np.append(phi, phi[0] + 2 * np.pi)
    y = np.append(f, f[0])
    return float(np.sum(0.5 * np.diff(x) * (y[1:] + y[:-1])) / (2 * np.pi))


@pytest.fixture(scope="module")
def sized():
    result = ks.analyze(ks.load(DRIVE))
    return result, size(result)


@pytest.mark.parametrize("friction", [False, True])
def test_slotting_machine_numbers_against_direct_integration(friction):
    model = ks.load(DRIVE)
    spec = model.drive.__class__(**{**vars(model.drive), "friction": friction})
    result = ks.analyze(model)
    d = size(result, spec)
    phi, t = _fine(friction)
    tm = np.where(t > 0, t / (RATIO * ETA), t * ETA / RATIO)  # the motor always turns forward
    # the integrator is exact between its cuts (tests/analysis/test_cycle.py); the tolerances
    # are the reference's: a trapezoid rule on the fine grid, not cut where a friction couple flips
    # or where the motor's torque has its kink (T = 0)
    tol = 1e-6 if not friction else 2e-5
    tol_m = 1e-5
    sh, mo = d.shaft, d.motor
    assert sh["torque"]["mean"] == pytest.approx(_mean(phi, t), rel=tol)
    assert sh["torque"]["rms"] == pytest.approx(math.sqrt(_mean(phi, t**2)), rel=tol)
    assert mo["torque"]["mean"] == pytest.approx(_mean(phi, tm), rel=tol_m)
    assert mo["torque"]["rms"] == pytest.approx(math.sqrt(_mean(phi, tm**2)), rel=tol_m)
    assert sh["power"]["mean"] == pytest.approx(_mean(phi, t) * OMEGA, rel=tol)
    assert mo["power"]["mean"] == pytest.approx(_mean(phi, tm) * RATIO * OMEGA, rel=tol_m)
    # peaks: the fine grid's largest value, to the spacing of the rows and nodes
    assert sh["torque"]["peak"] == pytest.approx(np.max(np.abs(t)), rel=2e-3)
    assert mo["torque"]["peak"] == pytest.approx(np.max(np.abs(tm)), rel=2e-3)
    assert mo["power"]["peak"] == pytest.approx(np.max(np.abs(tm)) * RATIO * OMEGA, rel=2e-3)
    assert mo["speed"]["max_rpm"] == pytest.approx(60 * RATIO, rel=1e-12)
    assert mo["inertia_torque"]["peak"] == 0.0  # constant crank speed
    if not friction:  # the cutting work Q·0.9H = 90 J per turn (docs/validation.md)
        assert sh["torque"]["mean"] == pytest.approx(90 / (2 * math.pi), rel=1e-9)


def test_reduction_rule_by_hand():
    # motoring forward and backward: T/(i·η); braking either way: T·η/i
    assert reduce(10.0, 2.0, 5.0, 0.8) == pytest.approx(2.5)
    assert reduce(-10.0, -2.0, 5.0, 0.8) == pytest.approx(-2.5)
    assert reduce(10.0, -2.0, 5.0, 0.8) == pytest.approx(1.6)
    assert reduce(-10.0, 2.0, 5.0, 0.8) == pytest.approx(-1.6)
    assert reduce(10.0, 0.0, 5.0, 0.8) == pytest.approx(2.5)  # holding: as motoring


CRANK = """
name: oscillating crank
units: {angle: deg, length: m}
gravity: [0, 0]
links:
  frame: {points: {O: [0, 0], X: [1, 0]}}
  crank: {points: {O: [0, 0], A: [0.1, 0]}, mass: 2, inertia: 0.01}
ground: frame
joints:
  O: {type: revolute, links: [frame, crank]}
drivers:
  motor: {joint: O, points: [X, A], motion: {law: harmonic, centre: 0, amplitude: 60, period: 0.5}}
drive:
  reduction: {ratio: 10, efficiency: 0.8, inertia: 0.001}
  motor: {inertia: 0.002}
"""


def test_reflected_inertia_against_the_motion_law():
    model = ks.loads(CRANK)
    result = ks.analyze(model, friction=False)
    a, w0 = math.radians(60), 2 * math.pi / 0.5
    t = np.asarray(result.t)
    psi_d, psi_dd = a * w0 * np.cos(w0 * t), -a * w0**2 * np.sin(w0 * t)
    tau = 0.01 * psi_dd  # the crank's torque about its centre of mass (the pivot)
    load = np.where(tau * psi_d >= 0, tau / (10 * 0.8), tau * 0.8 / 10)
    expect = load + (0.002 + 0.001) * 10 * psi_dd
    d = quadrant_data(result)
    order = np.argsort(t)
    assert np.allclose(d["torque"], expect[order], rtol=0, atol=1e-10)
    assert np.allclose(d["speed"], 10 * psi_d[order] * 30 / math.pi, rtol=0, atol=1e-9)
    # the RMS over the period, against the closed form on a fine grid of time
    s = size(result)
    tt = np.linspace(0, 0.5, 200001)
    pd, pdd = a * w0 * np.cos(w0 * tt), -a * w0**2 * np.sin(w0 * tt)
    ta = 0.01 * pdd
    tm = np.where(ta * pd >= 0, ta / 8, ta * 0.08) + 0.03 * pdd
    assert s.motor["torque"]["rms"] == pytest.approx(
        math.sqrt(trapezoid(tm**2, tt) / 0.5), rel=1e-8
    )
    assert s.motor["inertia_torque"]["peak"] == pytest.approx(0.03 * a * w0**2, rel=1e-6)
    assert s.motor["speed"]["max"] == pytest.approx(10 * a * w0, rel=1e-6)
    assert s.checks["rigid"]["verdict"] == "not checked" and s.flywheel is None


def test_the_check_flags_an_undersized_motor(tmp_path, capsys):
    # rigid drive (no flywheel): RMS about 1.07 N·m at the motor
    small = ks.loads(_variant("{rated_torque: 0.9, peak_torque: 3, rated_speed: 1500}", False))
    d = size(ks.analyze(small))
    assert d.verdict_from == "rigid" and d.verdict == "undersized"
    assert d.checks["rigid"]["items"]["rms_torque"]["ok"] is False
    assert d.checks["rigid"]["items"]["peak_torque"]["ok"] is True
    assert "RMS torque" in d.warning() and "rated torque 0.9 N*m" in d.warning()
    # the flywheel evens the torque to its mean, about 0.78 N·m: the same motor suffices
    with_fw = ks.loads(_variant("{rated_torque: 0.9, peak_torque: 3, rated_speed: 1500}"))
    d = size(ks.analyze(with_fw))
    assert d.verdict_from == "flywheel" and d.verdict == "adequate"
    assert d.checks["rigid"]["verdict"] == "undersized"
    assert d.flywheel["torque"] == pytest.approx(
        d.shaft["torque"]["mean"] / (RATIO * ETA), rel=1e-12
    )
    assert d.flywheel["speed_max_rpm"] == pytest.approx(60 * RATIO * 1.02, rel=1e-12)
    # too slow a motor: the speed check
    slow = ks.loads(_variant("{rated_torque: 2, peak_torque: 5, rated_speed: 1400}"))
    d = size(ks.analyze(slow))
    assert d.verdict == "undersized" and d.checks["flywheel"]["items"]["speed"]["ok"] is False
    # an adequate motor passes; no ratings: not checked
    assert size(ks.analyze(ks.load(DRIVE))).verdict == "adequate"
    bare = ks.loads(_variant("{inertia: 0.001}"))
    assert size(ks.analyze(bare)).verdict == "not checked"
    # run prints the checks, warns on stderr and writes summary.json's drive section
    path = tmp_path / "small.yaml"
    path.write_text(_variant("{rated_torque: 0.5, peak_torque: 1.5}", False), encoding="utf-8")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    out, err = capsys.readouterr()
    assert "drive check (rigid drive)" in out and ": undersized (the verdict)" in out
    assert "kinetostatics: warning: drive 'motor': motor undersized (rigid drive)" in err
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["drive"]["verdict"] == "undersized"
    assert (tmp_path / "out" / "drive.png").stat().st_size > 0


def test_no_drive_no_section():
    s = ks.analyze(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")).summary()
    assert "drive" not in s


@pytest.mark.parametrize(
    "old, new, where, words",
    [
        ("ratio: 24,", "ratio: -24,", "drive.reduction.ratio", "must be positive"),
        ("efficiency: 0.9", "efficiency: 1.2", "drive.reduction.efficiency", "(0, 1]"),
        ("  driver: motor\n", "  driver: motor\n  gear: 3\n", "drive", "gear"),
        ("peak_torque: 4.8", "peak_torque: 1", "drive.motor.peak_torque", "at least the rated"),
        ("driver: motor", "driver: crank", "drive.driver", "crank"),
    ],
)
def test_yaml_mistakes_name_the_key_and_line(old, new, where, words):
    assert old in TEXT
    text = TEXT.replace(old, new)
    with pytest.raises(ModelError) as info:
        ks.loads(text, file="d.yaml")
    message = str(info.value)
    lines = text.splitlines()
    top = lines.index(next(s for s in lines if s.startswith("drive:")))
    key = where.split(".")[-1] if where != "drive" else "gear"
    line = next(k + 1 for k in range(top, len(lines)) if f"{key}:" in lines[k])
    assert f"d.yaml:{line}:" in message and where in message and words in message, message


def test_dump_reads_back_the_drive():
    model = ks.load(DRIVE)
    again = ks.loads(ks.io.dump(model))
    assert again.drive == model.drive


def test_the_picture_does_not_clip(sized):
    pytest.importorskip("matplotlib")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    from kinetostatics.outputs.plotting.drive import torque_speed

    result, _ = sized
    for lang in ("en",):
        fig = torque_speed(result, dpi=60, lang=lang)
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        r = canvas.get_renderer()
        box = fig.bbox
        hidden = {  # tick labels beyond the view limits are not drawn (matplotlib < 3.11
            # still has them visible)
            id(label)
            for ax in fig.axes
            for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim()))
            for tick in axis.get_major_ticks()
            if not min(lo, hi) <= tick.get_loc() <= max(lo, hi)
            for label in (tick.label1, tick.label2)
        }
        texts = [
            t
            for t in fig.findobj(Text)
            if t.get_visible() and t.get_text().strip() and id(t) not in hidden
        ]
        assert texts
        for t in texts:
            e = t.get_window_extent(r)
            assert e.x0 >= box.x0 - 1 and e.x1 <= box.x1 + 1, t.get_text()
            assert e.y0 >= box.y0 - 1 and e.y1 <= box.y1 + 1, t.get_text()
        for ax in fig.axes:
            tight = ax.get_tightbbox(r)
            assert tight.x0 >= -1 and tight.x1 <= box.x1 + 1
        # the points drawn are the motor's torque and speed
        d = quadrant_data(result)
        line = [ln for ln in fig.axes[0].lines if ln.get_marker() == "."][0]
        assert np.array_equal(line.get_ydata(), d["torque"])
        assert np.allclose(d["speed"], 60 * RATIO)
