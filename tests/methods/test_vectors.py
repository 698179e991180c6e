"""The vector equations in textbook form (methods/vectors.py) against independent truths.

- every equation of every motion-driven shipped file closes, at three positions, to 1e-12
  of its largest term (the terms are each link's own velocities, the pairs' own relative
  terms: the closure is the kinematics' consistency, not an identity);
- each dyad's velocity and acceleration equations have two unknown magnitudes, the two a
  textbook polygon solves for, and each term marked ⊥XY is normal to the line XY;
- the slotting machine at position 2, by hand: v_A = ω·l_O2A with l_O2A = 150·sin 30° mm,
  v_A3 = ω3·l_O3A, the sliding velocity v_A2A3 along the bar, the Coriolis magnitude
  2·|ω3|·|v_A2A3| from the result's columns;
- a gear pair closes a one-link group at its pitch point (v_P = ω·r by hand, the normal
  term of rolling ω1²r + ω2²r by hand); a cam's follower through its guide and the contact;
  every group of every shipped file writes its accelerations; methods.json holds the
  equations, JSON-safe.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.analysis.pipeline import analyze
from kinetostatics.methods.stage import methods_stage
from kinetostatics.methods.vectors import vector_equations
from kinetostatics.outputs.plotting import course_positions
from tests.helpers import motion_driven, spread_rows

FILES = motion_driven()
TOL = 1e-12


@pytest.fixture(scope="module")
def results(kinematics):
    return kinematics


def _terms(equation):
    return (*equation.lhs, *equation.rhs)


@pytest.mark.parametrize("name", FILES)
def test_every_equation_closes_to_its_largest_term(results, name):
    result = results[name]
    positions = vector_equations(result, spread_rows(result))
    assert len(positions) == 3
    for position in positions:
        assert [g.links for g in position.groups] == [p.group.links for p in result.system.plans]
        for group in position.groups:
            for eq in group.equations:
                total = sum(np.array(t.vector) for t in eq.lhs) - sum(
                    np.array(t.vector) for t in eq.rhs
                )
                largest = max(t.value for t in _terms(eq))
                if largest == 0.0:  # a follower on a dwell: its group at rest, every term 0
                    assert all(abs(v) <= 1e-9 for _, v, _ in group.solved), eq.text
                    continue
                assert np.hypot(*total) <= TOL * largest, (group.label, eq.text)
                assert eq.residual <= TOL
        json.dumps(position.to_dict(), allow_nan=False)


@pytest.mark.parametrize("name", FILES)
def test_a_dyad_has_two_unknown_magnitudes_and_its_normals_are_normal(results, name):
    result = results[name]
    row = spread_rows(result)[1]
    (position,) = vector_equations(result, [row])
    points, normals = _points(result, row), 0
    for group in position.groups:
        for eq in group.equations:
            unknown = [t for t in _terms(eq) if not t.known]
            if group.label.split()[1:2] == ["dyad"]:
                assert len(unknown) == 2, (group.label, eq.text)
            for t in _terms(eq):
                if t.direction.startswith("⊥") and t.direction[1:] in points:
                    line = points[t.direction[1:]]
                    assert abs(np.dot(t.vector, line)) <= TOL * t.value * np.hypot(*line)
                    normals += 1
    assert normals or not any(g.equations for g in position.groups)


def _points(result, row) -> dict[str, np.ndarray]:
    """XY -> the vector from X to Y, for the links' named points in the result's columns."""
    where = {}
    for name in result.names:
        parts = name.split(".")
        if len(parts) == 3 and parts[2] == "x":
            where[parts[1]] = np.array([result[name][row], result[".".join(parts[:2]) + ".y"][row]])
    return {a + b: where[b] - where[a] for a in where for b in where if a != b}


def test_the_slotting_machine_at_position_2_by_hand(results):
    result = results["slotting_machine"]
    row = dict(course_positions(result))["2"]
    (position,) = vector_equations(result, [("2", row)])
    assert position.label == "2" and position.row == row
    crank, dyad, _ = position.groups
    assert dyad.links == ("block", "bar")
    velocity = next(e for e in dyad.equations if e.kind == "velocity")
    acceleration = next(e for e in dyad.equations if e.kind == "acceleration")
    terms = {t.symbol: t for t in _terms(velocity)}
    assert set(terms) == {"v_A1", "v_A3", "v_A2A3"}

    omega = 60 * 2 * math.pi / 60  # 60 rpm
    l_o2a = 0.150 * math.sin(math.radians(30))  # L_O2O3·sin(θ/2), θ = 60°: 75 mm
    v_a = terms["v_A1"]
    assert v_a.known and v_a.direction == "⊥O2A" and v_a.magnitude == "ω1·l_O2A"
    assert v_a.value == pytest.approx(omega * l_o2a, rel=1e-12)

    c = {k: result[k][row] for k in result.names if k.startswith(("bar.", "crank.A."))}
    a = np.array([c["crank.A.x"], c["crank.A.y"]])
    w3 = c["bar.omega"]
    v_a3 = np.array([c["bar.vx"], c["bar.vy"]]) + w3 * np.array(
        [-(a[1] - c["bar.y"]), a[0] - c["bar.x"]]
    )
    v_r = np.array([c["crank.A.vx"], c["crank.A.vy"]]) - v_a3
    l_o3a = math.hypot(a[0] - c["bar.O3.x"], a[1] - c["bar.O3.y"])
    assert not terms["v_A3"].known and terms["v_A3"].direction == "⊥O3A"
    assert terms["v_A3"].value == pytest.approx(abs(w3) * l_o3a, rel=1e-12)
    slide = terms["v_A2A3"]
    assert not slide.known and slide.direction.startswith("∥")
    np.testing.assert_allclose(slide.vector, v_r, rtol=0, atol=1e-12 * v_a.value)
    bar = np.array([c["bar.B.x"] - c["bar.O3.x"], c["bar.B.y"] - c["bar.O3.y"]])
    cross = slide.vector[0] * bar[1] - slide.vector[1] * bar[0]
    assert abs(cross) <= 1e-12 * slide.value * np.hypot(*bar)

    coriolis = next(t for t in _terms(acceleration) if t.symbol == "a^k_A2A3")
    assert coriolis.known and coriolis.magnitude == "2·ω3·v_A2A3"
    assert coriolis.value == pytest.approx(2 * abs(w3) * np.hypot(*v_r), rel=1e-12)
    assert abs(np.dot(coriolis.vector, bar)) <= 1e-12 * coriolis.value * np.hypot(*bar)
    solved = {s: v for s, v, _ in dyad.solved}
    assert solved["ω3"] == pytest.approx(w3, rel=1e-12)
    assert solved["v_A2A3"] == pytest.approx(np.hypot(*v_r), rel=1e-12)
    assert crank.equations[0].text == "v_A1 = v_AO2"


def test_a_gear_pair_rolls_at_its_pitch_point_with_the_normal_term_of_rolling(results):
    """The geared five-bar's second crank is closed by the mesh: v_P(2) = v_P(1) at the
    pitch point P, one unknown (ω of crank2), |v_P| = |ω1|·l_O1P by hand; its acceleration
    equation adds the normal term of rolling, ω1²·r + ω2²·r by hand (gears on the frame),
    with one unknown, the tangential term of crank2."""
    result = results["geared_fivebar"]
    row = len(result.t) // 4
    (position,) = vector_equations(result, [row])
    group = next(g for g in position.groups if g.links == ("crank2",))
    assert group.notes == ()
    velocity, acceleration = group.equations
    assert velocity.kind == "velocity" and velocity.text == "v_mesh(crank2) = v_mesh(crank1)"
    assert [t.known for t in _terms(velocity)] == [False, True]
    r1 = 5e-3 * 30 / 2  # m·z/2: module 5 mm, 30 teeth (the file's comment): 75 mm
    w1, w2 = result["crank1.omega"][row], result["crank2.omega"][row]
    assert velocity.rhs[0].value == pytest.approx(abs(w1) * r1, rel=1e-12)
    assert velocity.lhs[0].value == pytest.approx(abs(w2) * r1, rel=1e-12)
    assert acceleration.kind == "acceleration" and acceleration.residual <= TOL
    rolling = acceleration.rhs[-1]
    assert rolling.symbol == "a^n_mesh(crank2)mesh(crank1)" and rolling.known
    assert rolling.value == pytest.approx(w1**2 * r1 + w2**2 * r1, rel=1e-9)
    assert [t.symbol for t in _terms(acceleration) if not t.known] == ["a^t_mesh(crank2)"]


def test_a_cams_follower_is_written_through_its_guide_and_the_contact(results):
    """The roller cam: the follower's base is its guide on the frame (a lower pair before
    the cam), and the contact closes the group: v_C(follower) = v_C(cam) + v_r (two
    unknowns: the follower's slide and the roller centre's speed along the pitch curve),
    the acceleration with the relative path's normal and Coriolis terms known."""
    cam = results["cam_roller"]
    (position,) = vector_equations(cam, [len(cam.t) // 3])
    assert [n for g in position.groups for n in g.notes] == []
    group = next(g for g in position.groups if g.links == ("follower",))
    velocity, acceleration = group.equations
    assert velocity.joint == acceleration.joint == "contact"
    assert sum(not t.known for t in _terms(velocity)) == 2
    assert sum(not t.known for t in _terms(acceleration)) == 2
    assert {t.symbol for t in _terms(acceleration) if t.known} >= {
        "a^n_C(follower)C(cam)",
        "a^k_C(follower)C(cam)",
    }


@pytest.mark.parametrize("name", FILES)
def test_every_group_writes_its_accelerations(results, name):
    """Every pair type writes its terms (revolute, prismatic, gear, rack, cam): no group of
    a shipped file has a note, and each has as many acceleration equations as velocity
    equations."""
    result = results[name]
    for position in vector_equations(result, spread_rows(result)):
        for group in position.groups:
            kinds = [e.kind for e in group.equations]
            assert group.notes == (), (name, group.label)
            assert kinds.count("velocity") == kinds.count("acceleration"), (name, group.label)


def test_methods_json_holds_the_equations(results):
    result = results["geared_fivebar"]
    rows = [("1", 0), ("4", len(result.t) // 4)]
    data = methods_stage(result, rows, parts=["vector_equations"])
    assert list(data["vector_equations"]) == ["1", "4"]
    text = json.dumps(data["vector_equations"], allow_nan=False)
    position = json.loads(text)["4"]
    eq = position["groups"][-1]["equations"][0]
    assert {"symbol", "vector", "direction", "magnitude", "known", "value"} <= set(eq["lhs"][0])
    assert position["max_residual"] <= TOL
    unknown = [t for g in position["groups"] for e in g["equations"] for t in e["lhs"] + e["rhs"]]
    assert any(t["magnitude"] == "?" and not t["known"] for t in unknown)


def test_a_class_three_group_closes_with_its_unreached_points_unknown():
    """A triad's plate has no pair with a known body: its points' velocities are written
    as unknowns ("?", no direction), and the equations still close."""
    from tests.methods.test_centres import TRIAD

    result = analyze(ks.loads(TRIAD, file="triad.yaml"), kinematics_only=True)
    (position,) = vector_equations(result, [2])
    triad = position.groups[-1]
    assert triad.links == ("plate", "b1", "b2", "b3")
    assert len(triad.equations) == 6  # three pairs of the plate, velocities and accelerations
    for eq in triad.equations:
        assert eq.residual <= TOL
        plate = eq.lhs[0]
        assert plate.symbol.endswith("(plate)") and not plate.known and plate.direction == "?"
