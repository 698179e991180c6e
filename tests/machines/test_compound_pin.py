"""A pin shared by three links (a compound hinge): the double-toggle jaw crusher.

Regression: written as two revolutes (B3: pitman–rear, B4: pitman–front) with
only B3 sketched, the front toggle's orientation was guessed and the group
{front, jaw} assembled on its mirror branch — C 580 mm from its sketch — with
no message, and peak toggle forces of 25.6/29.9 kN instead of 39.5/39.4 kN.
The expected values below come from plane geometry (circle intersections) and
from the statics of the jaw and the pitman with the toggles as two-force
members, not from the program's output.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics import ModelError
from kinetostatics.cli import main
from kinetostatics.io import dump

ROOT = Path(__file__).resolve().parents[2]
MIRRORED = ROOT / "tests" / "hard" / "jaw_crusher_mirrored.yaml"
SHIPPED = ROOT / "mechanisms" / "jaw_crusher.yaml"

# the file's dimensions (mm)
A0 = np.array([0.0, 15.0])  # eccentric at analysis.start = 90°
O3, O2 = np.array([290.0, -650.0]), np.array([-330.0, 250.0])
L_AB, L_T, L_O2C = 615.0, 294.3, 900.9
SKETCH_C = np.array([-290.0, -650.0])


def _circles(p, r, q, s):
    """The two intersections of the circles (p, r) and (q, s)."""
    d = np.linalg.norm(q - p)
    a = (r * r - s * s + d * d) / (2 * d)
    h = np.sqrt(r * r - a * a)
    u = (q - p) / d
    m = p + a * u
    n = np.array([-u[1], u[0]])
    return m + h * n, m - h * n


def _near(points, target):
    return min(points, key=lambda x: np.linalg.norm(x - target))


def _far(points, target):
    return max(points, key=lambda x: np.linalg.norm(x - target))


def _pin_text() -> str:
    """The shipped file with the pin written in the direct form."""
    text = SHIPPED.read_text()
    text = re.sub(
        r"  B3: \{type: revolute, links: \[pitman, rear\].*\n  B4: .*\n",
        "  B: {type: revolute, links: [pitman, rear, front], points: [B, B, B],\n"
        "      friction: {journal_radius: 30, coefficient: 0.1}}\n",
        text,
    )
    text = text.replace("  B3: [0, -600]\n  B4: [0, -600]\n", "  B: [0, -600]\n")
    assert "links: [pitman, rear, front]" in text and "  B: [0, -600]" in text
    return text


@pytest.fixture(scope="module")
def shipped():
    return ks.analyze(ks.load(SHIPPED))


@pytest.fixture(scope="module")
def pin():
    return ks.analyze(ks.loads(_pin_text(), file="jaw_pin.yaml"))


def test_the_regression_file_is_the_shipped_file_without_the_B4_sketch():
    a = MIRRORED.read_text().split("name:", 1)[1]
    b = SHIPPED.read_text().split("name:", 1)[1]
    assert b.replace("  B4: [0, -600]\n", "") == a


def test_mirrored_assembly_is_refused_naming_the_point_and_distance():
    # independent geometry: B from the {pitman, rear} dyad near its sketch, then C of
    # the {front, jaw} dyad on the branch away from its sketch (the mirror)
    b = _near(_circles(A0, L_AB, O3, L_T), np.array([0.0, -600.0]))
    c_mirror = _far(_circles(b, L_T, O2, L_O2C), SKETCH_C)
    expected = np.linalg.norm(c_mirror - SKETCH_C)
    assert 560 < expected < 600
    with pytest.raises(ModelError) as info:
        ks.analyze(ks.load(MIRRORED))
    ((where, message),) = info.value.problems
    assert where.path == "sketch.C" and where.line == 78 and where.col == 3
    assert str(MIRRORED) in str(info.value)
    distance = float(
        re.search(r"C is assembled ([\d.]+) mm from its sketched position", message).group(1)
    )
    assert distance == pytest.approx(expected, abs=0.1)
    assert "RRR dyad {front, jaw}" in message and "0.25 L_ref" in message


@pytest.mark.parametrize("command", ["run", "check"])
def test_cli_refuses_the_mirrored_file(command, tmp_path, capsys):
    args = [command, str(MIRRORED)] + (["--out", str(tmp_path)] if command == "run" else [])
    assert main(args) == 2
    err = capsys.readouterr().err
    assert f"{MIRRORED}:78:3: sketch.C: C is assembled" in err


def test_assembled_pose_matches_the_geometry_and_the_sketch(shipped):
    b = _near(_circles(A0, L_AB, O3, L_T), np.array([0.0, -600.0]))
    c = _near(_circles(b, L_T, O2, L_O2C), SKETCH_C)
    for name, exact in (
        ("pitman.B", b),
        ("rear.B", b),
        ("front.B", b),
        ("front.C", c),
        ("jaw.C", c),
    ):
        got = np.array([shipped[f"{name}.x"][0], shipped[f"{name}.y"][0]]) * 1e3
        assert np.linalg.norm(got - exact) < 1e-8, name
    assert np.linalg.norm(c - SKETCH_C) < 1.0  # within 1 mm of the sketch
    assert np.linalg.norm(b - np.array([0.0, -600.0])) < 30.0
    assert shipped.checks.ok, shipped.checks.line()


def _p(result, name, k):
    return np.array([result[f"{name}.x"][k], result[f"{name}.y"][k]])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def test_peak_toggle_forces_from_jaw_and_pitman_statics(shipped):
    """At the row of the largest front toggle force: the jaw's moment balance about
    O2 gives the front toggle's force (a two-force member along B–C), the pitman's
    about A the rear toggle's (along O3–B); the toggles' own weight and inertia
    (10 kg) are neglected there, 1 % covers them."""
    r = shipped
    k = int(np.argmax(np.hypot(r["B4.Fx"], r["B4.Fy"])))
    g = np.array([0.0, -9.81])
    b, c = _p(r, "pitman.B", k), _p(r, "jaw.C", k)
    a, o2, o3 = _p(r, "pitman.A", k), O2 * 1e-3, O3 * 1e-3
    qp = _p(r, "jaw.Qp", k)
    assert r["jaw.Qp.vx"][k] < 0  # closing: the resistance acts (+x)
    crush = np.array([50000.0, 0.0])

    def d_alembert(link, mass, inertia, about):
        s = np.array([r[f"{link}.x"][k], r[f"{link}.y"][k]])
        f = mass * (g - np.array([r[f"{link}.ax"][k], r[f"{link}.ay"][k]]))
        return _cross(s - about, f) - inertia * r[f"{link}.alpha"][k]

    u_f = (c - b) / np.linalg.norm(c - b)  # the front toggle pushes the jaw along B→C
    m_rest = _cross(qp - o2, crush) + d_alembert("jaw", 250.0, 20.0, o2)
    f_front = -m_rest / _cross(c - o2, u_f)
    u_r = (b - o3) / np.linalg.norm(b - o3)  # the rear toggle pushes the pitman along O3→B
    m_rest = _cross(b - a, -f_front * u_f) + d_alembert("pitman", 150.0, 5.0, a)
    f_rear = -m_rest / _cross(b - a, u_r)
    assert f_front == pytest.approx(39.4e3, rel=0.01)
    assert f_rear == pytest.approx(39.5e3, rel=0.01)
    peak_front = np.max(np.hypot(r["B4.Fx"], r["B4.Fy"]))
    peak_rear = np.max(np.hypot(r["B3.Fx"], r["B3.Fy"]))
    assert peak_front == pytest.approx(f_front, rel=0.01)
    assert peak_rear == pytest.approx(f_rear, rel=0.01)
    assert np.max(np.abs(r["power.residual"])) < 1e-9 * np.max(np.abs(r["power.input"]))


def test_direct_pin_form_equals_the_two_revolutes(shipped, pin):
    assert [j.name for j in pin.system.model.joints if j.name.startswith("B")] == [
        "B_rear",
        "B_front",
    ]
    assert np.array_equal(pin.q, shipped.q) or np.max(np.abs(pin.q - shipped.q)) < 1e-12
    for ours, theirs in (("B_rear", "B3"), ("B_front", "B4")):
        for col in ("Fx", "Fy", "friction_approx", "friction", "Fx_friction", "Fy_friction"):
            a, b = pin[f"{ours}.{col}"], shipped[f"{theirs}.{col}"]
            assert np.allclose(
                a, b, rtol=1e-12, atol=1e-12 * np.nanmax(np.abs(b)), equal_nan=True
            ), (ours, col)
    for col in ("motor.torque", "motor.torque_friction", "power.friction", "C.Fx"):
        assert np.allclose(pin[col], shipped[col], rtol=1e-12, atol=1e-9, equal_nan=True)
    assert pin.checks.ok


def test_pin_sketch_key_places_every_link_and_round_trips():
    model = ks.loads(_pin_text(), file="jaw_pin.yaml")
    assert set(model.sketch) >= {"B_rear", "B_front"}
    assert np.allclose(model.sketch["B_rear"], [0.0, -0.6])
    assert np.allclose(model.sketch["B_front"], [0.0, -0.6])
    rear = model.joint("B_rear")
    assert rear.links == ("pitman", "rear") and rear.rho == pytest.approx(0.003)
    assert model.joint("B_front").links == ("pitman", "front")
    again = ks.loads(dump(model))  # written back as its two revolutes
    assert [(j.name, j.links, getattr(j, "rho", None)) for j in again.joints] == [
        (j.name, j.links, getattr(j, "rho", None)) for j in model.joints
    ]
    assert all(np.array_equal(again.sketch[k], v) for k, v in model.sketch.items())


def _bad(old: str, new: str) -> str:
    text = _pin_text()
    assert old in text
    return text.replace(old, new)


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            "links: [pitman, rear, front]",
            "links: [pitman]",
            r"joints\.B\.links: a revolute connects two links, or three or more that share one "
            r"pin; got 1",
        ),
        (
            "links: [pitman, rear, front]",
            "links: [pitman, rear, rear]",
            r"joints\.B\.links\[2\]: link 'rear' is listed twice",
        ),
        ("points: [B, B, B]", "points: [B, B]", r"joints\.B\.points: expected a list of 3 names"),
        (
            "joint: O1, motion",
            "joint: B, motion",
            r"drivers\.motor\.joint: 'B' is a pin shared by 3 links, not one joint: name one of "
            r"its revolutes \(B_rear, B_front\)",
        ),
        (
            "  O3: {type: revolute, links: [ground, rear]",
            "  B_rear: {type: revolute, links: [ground, rear], points: [O3, O3]",
            r"joints\.B_rear: duplicate name 'B_rear': the pin 'B' at line \d+ names its revolute "
            r"pitman-rear so",
        ),
        (
            "  front:\n",
            "  B_front: {points: {P: [0, 0]}, mass: 1}\n  front:\n",
            r"joints\.B: the pin's revolute pitman-front is named 'B_front', but the link at "
            r"line \d+ has that name",
        ),
    ],
)
def test_pin_misuse_is_a_model_error(old, new, message):
    with pytest.raises(ModelError, match=message):
        ks.loads(_bad(old, new), file="jaw_pin.yaml")
