"""The instant centres (methods/centres.py) against independent truths.

- the defining property of a centre, from the pipeline's velocities alone: the two bodies'
  velocity fields agree at P_ij (at infinity along d: the same ω and a relative velocity
  normal to d), for every centre found in every motion-driven shipped file;
- closed forms written here: the four-bar's coupler centre is where the crank and rocker
  lines meet, the slider-crank's rod centre where the crank line meets the normal to the
  guide through the pin B;
- a class-III group whose outer pairs sit on three bodies, where Kennedy's theorem is known
  to fail: the centres of the group's bodies are reported not found;
- the velocities the record derives from the centres equal the pipeline's to 1e-12.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.analysis.pipeline import analyze
from kinetostatics.methods.centres import centres_at, instant_centres
from kinetostatics.outputs.labels import link_numbers
from tests.helpers import motion_driven, spread_rows

FILES = motion_driven()
TOL = 1e-12


@pytest.fixture(scope="module")
def results(kinematics):
    return kinematics


def _field(result, row: int, body: str):
    """(ω, centre of mass, its velocity) of ``body`` from the pipeline (the frame at rest)."""
    system = result.system
    if body == system.model.ground.name:
        return 0.0, np.zeros(2), np.zeros(2)
    k = 3 * system.link_index(body)
    q, qd = result.q[row], result.qd[row]
    return qd[k + 2], q[k : k + 2], qd[k : k + 2]


def _velocity(field, p):
    omega, com, v = field
    return v + omega * np.array([-(p[1] - com[1]), p[0] - com[0]])


def _scale(result, row: int) -> float:
    """The velocity scale: the largest speed of a centre of mass or of |ω| times the size."""
    qd = result.qd[row].reshape(-1, 3)
    size = float(np.max(result.system.l_ref))
    return max(np.max(np.hypot(qd[:, 0], qd[:, 1])), np.max(np.abs(qd[:, 2])) * size)


@pytest.mark.parametrize("name", FILES)
def test_every_centre_found_where_kennedy_can_and_the_pipeline_agrees(results, name):
    result = results[name]
    n_bodies = len(result.system.links) + 1
    for row in spread_rows(result):
        rec = instant_centres(result, row)
        assert len(rec.centres) == n_bodies * (n_bodies - 1) // 2
        assert not rec.not_found, [c.bodies for c in rec.not_found]
        scale = _scale(result, row)
        for c in rec.centres:
            fi, fj = (_field(result, row, b) for b in c.bodies)
            if c.at_infinity:  # a relative translation normal to the direction
                d = np.asarray(c.xy)
                assert abs(fi[0] - fj[0]) <= TOL * np.max(np.abs(result.qd[row][2::3]))
                dv = _velocity(fi, np.zeros(2)) - _velocity(fj, np.zeros(2))
                assert abs(dv @ d) <= 1e-11 * scale, (c, dv @ d)
            else:
                dv = _velocity(fi, np.asarray(c.xy)) - _velocity(fj, np.asarray(c.xy))
                # a centre far off is known to fewer digits: its error is the point's
                # error times |ω_i − ω_j|, on the scale of the point's distance
                far = max(1.0, float(np.hypot(*c.xy)) / float(np.max(result.system.l_ref)))
                assert np.hypot(*dv) <= 1e-11 * scale * far, (c, dv)


@pytest.mark.parametrize("name", FILES)
def test_the_velocities_from_the_centres_are_the_pipelines(results, name):
    result = results[name]
    for rec in centres_at(result, spread_rows(result)):
        assert rec.max_error <= TOL, rec.max_error
        w_scale = np.max(np.abs(result.qd[rec.row][2::3]))
        for check in rec.checks:
            assert check.error is not None, check
            # against the named column, not the record's own copy of the pipeline's value
            omega = result[f"{check.body}.omega"][rec.row]
            assert abs(check.omega - omega) <= TOL * w_scale, (check, omega)
            if check.ratio is not None:
                assert check.ratio == pytest.approx(check.omega / rec.omega_reference, rel=1e-14)


def _meet(p1, p2, p3, p4):
    """Where the line p1–p2 meets the line p3–p4 (Cramer's rule, written out)."""
    (x1, y1), (x2, y2), (x3, y3), (x4, y4) = p1, p2, p3, p4
    den = (x1 - x2) * (y3 - y4) - (y1 - y2) * (x3 - x4)
    a, b = x1 * y2 - y1 * x2, x3 * y4 - y3 * x4
    return np.array([(a * (x3 - x4) - (x1 - x2) * b) / den, (a * (y3 - y4) - (y1 - y2) * b) / den])


def _point(result, link: str, name: str, row: int) -> np.ndarray:
    return np.array([result[f"{link}.{name}.x"][row], result[f"{link}.{name}.y"][row]])  # m


def test_four_bar_coupler_centre_is_where_crank_and_rocker_lines_meet(results):
    result = results["fourbar_balancing"]
    for row in (40, 130, 250):
        rec = instant_centres(result, row)
        a0, b0 = np.array([0.0, 0.0]), np.array([0.3, 0.0])  # the frame's pivots (the file)
        a, b = _point(result, "crank", "A", row), _point(result, "rocker", "B", row)
        expected = _meet(a0, a, b0, b)
        c = rec.centre("ground", "coupler")
        assert c.how == "kennedy" and not c.at_infinity
        assert np.hypot(*(np.asarray(c.xy) - expected)) <= 1e-12 * 0.35
        # and the crank–rocker centre on the frame line and the coupler line
        assert np.allclose(rec.centre("crank", "rocker").xy, _meet(a0, b0, a, b), atol=1e-12)
        # its three lines: through ground–crank–coupler and ground–rocker–coupler
        assert {frozenset(map(frozenset, line)) for line in c.lines} == {
            frozenset({frozenset({"ground", "crank"}), frozenset({"crank", "coupler"})}),
            frozenset({frozenset({"ground", "rocker"}), frozenset({"rocker", "coupler"})}),
        }


def test_slider_crank_rod_centre_and_the_slide_at_infinity(results):
    result = results["slider_crank"]
    for row in (30, 100, 300):
        rec = instant_centres(result, row)
        o = _point(result, "crank", "O", row)
        a = _point(result, "crank", "A", row)
        b = _point(result, "rod", "B", row)
        normal = np.array([0.0, 1.0])  # the guide runs along x (the file)
        slide = rec.centre("ground", "slider")
        assert slide.at_infinity and slide.how == "joint" and slide.kind == "prismatic"
        assert abs(abs(np.dot(slide.xy, normal)) - 1.0) <= 1e-15
        expected = _meet(o, a, b, b + normal)
        got = np.asarray(rec.centre("ground", "rod").xy)
        assert np.hypot(*(got - expected)) <= 1e-12 * max(1.0, np.hypot(*expected))


TRIAD = """
name: four-bar with a class-III group on three bodies
units: {length: mm, angle: deg, speed: rpm}
links:
  ground: {points: {O2: [0, 0], O4: [80, 0], G: [40, -60]}}
  crank: {points: {O2: [0, 0], A: [30, 0], P: [-20, 10]}}
  coupler: {points: {A: [30, 0], B: [90, 60]}}
  rocker: {points: {O4: [80, 0], B: [90, 60], R: [70, 40]}}
  plate: {points: {D: [20, 80], E: [50, 100], F: [60, 70]}}
  b1: {points: {P: [-20, 10], D: [20, 80]}}
  b2: {points: {G: [40, -60], E: [50, 100]}}
  b3: {points: {R: [70, 40], F: [60, 70]}}
joints:
  O2: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, coupler]}
  B: {type: revolute, links: [coupler, rocker]}
  O4: {type: revolute, links: [ground, rocker]}
  P: {type: revolute, links: [crank, b1]}
  D: {type: revolute, links: [b1, plate]}
  G: {type: revolute, links: [ground, b2]}
  E: {type: revolute, links: [b2, plate]}
  R: {type: revolute, links: [rocker, b3]}
  F: {type: revolute, links: [b3, plate]}
drivers:
  motor: {joint: O2, motion: {speed: -60}, points: [O4, A]}
sketch: {B: [90, 60], D: [20, 80], E: [50, 100], F: [60, 70]}
analysis: {positions: 4, sweep: 15}
"""


@pytest.fixture(scope="module")
def triad():
    return analyze(ks.loads(TRIAD, file="triad.yaml"), kinematics_only=True)


def test_a_class_three_group_on_three_bodies_defeats_kennedy(triad):
    """The group {plate, b1, b2, b3} hangs on the crank, the frame and the rocker: every
    line Kennedy's theorem could draw for a centre of the plate needs another unknown
    centre of the group, so those are reported not found, the rest found."""
    assert [p.group.label for p in triad.system.plans][-1] == "triad {plate, b1, b2, b3}"
    rec = instant_centres(triad, 2)
    missing = {frozenset(c.bodies) for c in rec.not_found}
    four_bar = {"ground", "crank", "coupler", "rocker"}
    assert frozenset({"ground", "plate"}) in missing
    assert frozenset({"crank", "plate"}) in missing
    for c in rec.centres:
        if set(c.bodies) <= four_bar or c.how == "joint":
            assert c.xy is not None, c
        if c.xy is None:
            assert c.how == "not found" and set(c.bodies) & {"plate", "b1", "b2", "b3"}
            assert "triad {plate, b1, b2, b3}" in c.groups, c
    assert len(missing) == 16  # of 28: the other 12 are the 10 pins and two of the four-bar
    checked = {c.body: c for c in rec.checks}
    for body in ("crank", "coupler", "rocker"):
        assert checked[body].error is not None and checked[body].error <= TOL
    for body in ("plate", "b1", "b3"):
        assert checked[body].omega is None and checked[body].error is None


def test_the_record_is_json_safe_and_complete(results, triad):
    rec = instant_centres(triad, 1)
    data = json.loads(json.dumps(rec.to_dict(), allow_nan=False))
    assert data["total"] == 28 and data["found"] == 12
    assert data["bodies"][0] == "ground" and len(data["checks"]) == 7
    hows = {c["how"] for c in data["centres"]}
    assert hows == {"joint", "kennedy", "not found"}
    rec = instant_centres(results["cam_roller"], 50)
    cam = rec.to_dict()["centres"]
    # the cam pair gives only its common normal; Kennedy's theorem meets it with the frame's line
    normal = next(c for c in cam if set(c["bodies"]) == {"cam", "follower"})
    assert normal["how"] == "kennedy" and normal["kind"] == "cam" and normal["joint"]


def test_the_picture_marks_the_centres_inside_and_lists_the_others(triad, results):
    pytest.importorskip("matplotlib")
    from kinetostatics.outputs.plotting.centres import centres_figure

    for result, row in ((results["fourbar_balancing"], 40), (triad, 2)):
        rec = instant_centres(result, row)
        fig = centres_figure(result, rec.to_dict())
        ax = fig.axes[0]
        # centres at one point share one label ("P14, P16"): crowding.place_labels
        drawn = {
            name: t.xy
            for t in ax.texts
            if t.get_gid() == "instant-centre"
            for name in t.get_text().split(", ")
        }
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        notes = [t.get_text() for t in ax.texts if t.get_gid() == "instant-centres-note"]
        note = " ".join(notes).replace("\n", " ")
        numbers = link_numbers(result.system)
        for c in rec.centres:
            a, b = sorted(numbers[n] for n in c.bodies)
            label = f"P{a}{b}"
            listed = re.search(rf"\b{label}\b", note) is not None
            if c.xy is None or c.at_infinity:
                assert listed, label
            else:
                x, y = (1e3 * v for v in c.xy)
                if x0 <= x <= x1 and y0 <= y <= y1:  # at the point (or one 1.5 pt from it)
                    assert np.hypot(*np.subtract(drawn[label], (x, y))) <= 0.01 * (x1 - x0)
                else:
                    assert listed, label
