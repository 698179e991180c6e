"""docs/validation.md stays in step with docs/scripts/slotting_validation.py, and
the exact slotting-machine values it tabulates pass independent hand checks."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.helpers import load_script

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "docs" / "scripts" / "slotting_validation.py"
DOC = ROOT / "docs" / "validation.md"


@pytest.fixture(scope="module")
def sv():
    return load_script(SCRIPT)


@pytest.fixture(scope="module")
def run(sv):
    model = sv.ks.load(sv.YAML)
    r, labels = sv.run(model)
    return model, r, labels


def test_doc_tables_equal_script_output(sv):
    doc = sv.doc_blocks(DOC.read_text(encoding="utf-8"))
    out = sv.blocks()
    assert list(doc) == list(out), "the blocks of docs/validation.md differ from the script's"
    stale = [name for name in out if doc[name] != out[name]]
    assert not stale, (
        f"docs/validation.md is stale in {stale}: run "
        f"`python docs/scripts/slotting_validation.py --update` and re-check the text"
    )


def test_printed_output_is_the_blocks(sv, capsys):
    assert sv.main([]) == 0
    printed = capsys.readouterr().out
    assert sv.doc_blocks(printed) == sv.blocks()


def test_rows_and_events(sv, run):
    model, r, labels = run
    assert labels == ["1", "1′", "2", "3", "4", "5", "6", "7", "8", "8′", "9", "10", "11", "12"]
    ev = sv.event_angles(r)
    assert ev["1′"] == pytest.approx(270.422, abs=5e-4)
    assert ev["8′"] == pytest.approx(88.632, abs=5e-4)
    # the same events from a full 1° cycle
    full = sv.ks.analyze(model, events=True, friction=False)
    assert sv.event_angles(full) == pytest.approx(ev, abs=1e-9)
    # 0.05H and 0.95H below the top (H = 0.1 m); the top is position 1, the bottom 9
    y = r["ram.C.y"]
    top, bottom = y[labels.index("1")], y[labels.index("9")]
    assert top - bottom == pytest.approx(0.1, abs=1e-12)
    assert top - y[labels.index("1′")] == pytest.approx(0.005, abs=1e-9)
    assert top - y[labels.index("8′")] == pytest.approx(0.095, abs=1e-9)


def test_ram_at_rest_at_the_extremes(run):
    _, r, labels = run
    for pos in ("1", "9"):
        i = labels.index(pos)
        assert abs(r["ram.vy"][i]) < 1e-12
        assert abs(r["bar.omega"][i]) < 1e-12
    # position 1 is O2A ⊥ O3A (the crank along the block's sliding direction)
    i = labels.index("1")
    a = np.array([r["crank.A.x"][i] - r["crank.O2.x"][i], r["crank.A.y"][i] - r["crank.O2.y"][i]])
    b = np.array([r["crank.A.x"][i] - r["bar.O3.x"][i], r["crank.A.y"][i] - r["bar.O3.y"][i]])
    assert abs(a @ b) < 1e-15


def test_velocities_by_hand(run):
    """ω3 and V_C from the geometry alone, against the library, to 1e-9."""
    _, r, labels = run
    a, l_o2o3, l_o3b, l_bc = 0.075, 0.150, 0.100, 0.100
    x_ram = l_o3b * (1 + np.cos(np.radians(30))) / 2
    w1 = -2 * np.pi  # 60 rpm clockwise
    phi = np.radians(r["angle"])
    ax, ay = -l_o2o3 + a * np.cos(phi), a * np.sin(phi)  # A, with O3 at the origin
    th3 = np.arctan2(ay, ax)  # direction O3→A
    L = np.hypot(ax, ay)
    w3 = a * w1 * np.cos(phi - th3) / L
    bx, by = -l_o3b * np.cos(th3), -l_o3b * np.sin(th3)  # B opposite A
    vbx, vby = -w3 * by, w3 * bx
    th4 = np.arccos((x_ram - bx) / l_bc)  # C above B on the line x = X
    vc = vby + vbx * np.cos(th4) / np.sin(th4)  # from v_Cx = 0
    assert np.max(np.abs(w3 - r["bar.omega"])) < 1e-9
    assert np.max(np.abs(vc - r["ram.vy"])) < 1e-9
    assert np.max(np.abs(by + l_bc * np.sin(th4) - r["ram.C.y"])) < 1e-12


def test_tangential_equation_with_coriolis(sv, run):
    """α3·L = a_A2·t − 2ω3·ṙ (the formula of the doc) against the library's α3."""
    _, r, labels = run
    k = sv.kinematics(r, labels)
    L = k["L_O3A"] / 1e3
    assert np.max(np.abs(k["a_A2t"] - 2 * r["bar.omega"] * k["rdot"] - r["bar.alpha"] * L)) < 1e-9
    # and V_A2·t = ω3·L: the block and the bar turn together
    A = np.stack([r["crank.A.x"], r["crank.A.y"]], -1)
    t = np.stack([-A[:, 1], A[:, 0]], -1) / L[:, None]
    v = np.stack([r["crank.A.vx"], r["crank.A.vy"]], -1)
    assert np.max(np.abs(np.sum(v * t, -1) - r["bar.omega"] * L)) < 1e-12


def test_reactions_by_hand(sv, run):
    """Free bodies written out by hand, frictionless, at every row."""
    model, r, labels = run
    f = sv.forces(r, model)
    m3, m5, J3, g = 16.0, 32.0, 0.14, 10.0
    assert model.link("bar").mass == m3 and model.link("ram").mass == m5
    cutting = np.array([lab in ("1′", "2", "3", "4", "5", "6", "7", "8", "8′") for lab in labels])
    assert np.allclose(f["Q"], np.where(cutting, 1000.0, 0.0), atol=1e-9)
    assert np.allclose(r["guide.M"], np.where(cutting, -120.0, 0.0), atol=1e-9)
    # massless block and crank: F61 = F12 = F23; massless rod: F34 = F45
    for a, b in (("O2", "A"), ("B", "C")):
        assert np.allclose(r[f"{a}.Fx"], r[f"{b}.Fx"], atol=1e-9)
        assert np.allclose(r[f"{a}.Fy"], r[f"{b}.Fy"], atol=1e-9)
    assert np.allclose(r["A.Fx"], f["F23x"], atol=1e-9) and np.allclose(
        r["A.Fy"], f["F23y"], atol=1e-9
    )

    def cross(p, q):
        return p[..., 0] * q[..., 1] - p[..., 1] * q[..., 0]

    def vec(name):
        return np.stack([r[name + ".x"] - r["bar.O3.x"], r[name + ".y"] - r["bar.O3.y"]], -1)

    # bar + rod about O3: F54 at B, G3 and F_I3 at S3, M_I3, F23 at A
    F54 = -np.stack([r["C.Fx"], r["C.Fy"]], -1)
    F23 = np.stack([f["F23x"], f["F23y"]], -1)
    G3 = np.array([0.0, -m3 * g])
    FI3 = -m3 * np.stack([r["bar.ax"], r["bar.ay"]], -1)
    moment = (
        cross(vec("bar.B"), F54)
        + cross(vec("bar.S3"), G3 + FI3)
        - J3 * r["bar.alpha"]
        + cross(vec("crank.A"), F23)
    )
    assert np.max(np.abs(moment)) < 1e-9
    # F23 is normal to the bar (no friction)
    e = vec("crank.A") / np.hypot(*vec("crank.A").T)[:, None]
    assert np.max(np.abs(np.sum(F23 * e, -1))) < 1e-9
    # crank about O2: M_b + (A − O2) × F21 = 0
    arm = np.stack([r["crank.A.x"] - r["crank.O2.x"], r["crank.A.y"] - r["crank.O2.y"]], -1)
    assert np.max(np.abs(r["motor.torque"] + cross(arm, -F23))) < 1e-9
    # ram vertical: F45y + Q − G5 − m5·a = 0 (Q from the cutting flags, not from the library)
    assert np.max(np.abs(r["C.Fy"] + 1000.0 * cutting - m5 * g - m5 * r["ram.ay"])) < 1e-9


def test_report_reconstruction_position_7(sv, run):
    """The report's position-7 numbers follow from the Coriolis term reversed."""
    model, r, labels = run
    k = sv.kinematics(r, labels)
    i = labels.index("7")
    w = sv.reversed_coriolis(r, k, i)
    printed = sv.REPORT["7"]
    for key in ("a_t_A3", "a_A3", "a_B", "a_t_CB", "a_C", "a_S3"):
        assert round(w[key], 2) == pytest.approx(printed[key], abs=1e-9), key
    # exact values (frictionless) quoted in the text
    f = sv.forces(r, model)
    assert f["F23"][i] == pytest.approx(402.37, abs=5e-3)
    assert f["M_b"][i] == pytest.approx(-22.813, abs=5e-4)
    assert -r["ram.ay"][i] == pytest.approx(-0.4685, abs=5e-5)
