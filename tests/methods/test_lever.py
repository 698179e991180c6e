"""The balancing moment three ways (methods/lever.py): Joukowski's lever and the power
method against the kinetostatic solution, on every shipped motion-driven file, at course
positions with their labels, for a prismatic driver's balancing force, and against the
closed form of an offset slider-crank with massless links."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.methods.lever import BalancingMoment, lever_stage
from kinetostatics.outputs.plotting.rows import analyze_for_pictures, course_positions
from tests.helpers import MECHANISMS, ROOT, motion_driven, variant

TOL = 1e-9  # the brief's: the three agree to 1e-9 relative
MOTION_DRIVEN = set(motion_driven())


def _analyze(model):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ks.analyze(model)


def _agree(record: BalancingMoment) -> None:
    for p in record.positions:
        assert math.isfinite(p.solution), (record.effort, p.row)
        for got in (p.lever, p.power):
            assert abs(got - p.solution) <= TOL * p.scale, (record.effort, p.row, got, p.solution)
        # the lever's moments and the driver's balance: Σ moments + M_b·ċ + others = 0
        total = sum(t.moment for t in p.terms) + p.lever * p.speed + p.others
        assert abs(total) <= TOL * p.scale * abs(p.speed)


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_lever_power_and_solution_agree_on_every_shipped_file(path):
    if path.stem not in MOTION_DRIVEN:
        pytest.skip("effort-driven: analyze refuses it (it is simulated, not analysed)")
    result = _analyze(ks.load(path))
    n = len(result)
    rows = [n // 8, 3 * n // 8, 5 * n // 8, 7 * n // 8]
    record = lever_stage(result, rows)
    assert [p.row for p in record.positions] == rows
    _agree(record)
    assert record.max_difference <= TOL
    json.dumps(record.to_dict(), allow_nan=False)  # JSON-safe
    # each force's image is its point's velocity: the crank's weight sits at its CoM
    for p in record.positions:
        for t in p.terms:
            if t.kind == "force":
                # zero on the scale of its two factors (N²): the sum of two products
                # cancels to round-off, exactly or not as the CPU fuses them (FMA)
                turned, force = np.array(t.turned), np.array(t.force)
                scale = np.linalg.norm(turned) * np.linalg.norm(force)
                assert abs(turned @ force) <= 1e-12 * scale
                assert t.moment == pytest.approx(
                    np.dot(t.image, t.force), rel=1e-12, abs=1e-12 * p.scale
                )


def test_course_positions_keep_their_labels_and_the_friction_note():
    """The slotting machine at its 12 course positions and its load events (1′, 8′): the
    labels pass through, the three agree; with friction in the file the record says it
    compared the frictionless column."""
    model = ks.load(MECHANISMS[0].parent / "slotting_machine.yaml")
    result = analyze_for_pictures(model, course=True)
    asked = course_positions(result)
    record = lever_stage(result, asked)
    assert [(p.label, p.row) for p in record.positions] == asked
    assert {"1′", "8′"} <= {p.label for p in record.positions}
    _agree(record)
    assert record.effort == "motor.torque" and record.unit == "N*m"
    assert "frictionless column motor.torque" in record.friction
    data = record.to_dict()
    assert data["frictionless"] is True
    assert data["positions"][1]["label"] == "1′"


def test_a_model_without_friction_has_no_note():
    record = lever_stage(_analyze(ks.load(MECHANISMS[0].parent / "fourbar_balancing.yaml")), [5])
    assert record.friction == ""


def test_a_prismatic_driver_has_a_balancing_force():
    """The slider-crank driven from its slide: the balancing effort is a force (N), the
    same identities with the slide's speed."""
    model = variant(
        "slider_crank",
        units=(r"speed: rpm", "speed: mm/s"),
        driver=(r"motor: \{joint: O, .*\}\}", "motor: {joint: slide, motion: {speed: -100}}"),
        analysis=(r"analysis: .*", "analysis: {start: 440, sweep: 150, positions: 16}"),
    )
    result = _analyze(model)
    record = lever_stage(result, [2, 6, 10, 14])
    assert (record.effort, record.unit, record.joint) == ("motor.force", "N", "slide")
    for p in record.positions:
        assert p.speed == pytest.approx(-0.1, rel=1e-12)  # the slide's speed, m/s
    _agree(record)


OFFSET_SLIDER_CRANK = """
name: massless offset slider-crank
units: {length: mm, angle: deg, speed: rpm, mass: kg, force: N, inertia: kg*m^2}
parameters: {r: 80, l: 300, e: 25, P: 500}
links:
  ground: {points: {O: [0, 0], guide: [0, e]}}
  crank: {points: {O: [0, 0], A: [r, 0]}}
  rod: {points: {A: [0, 0], B: [l, 0]}}
  slider: {points: {B: [0, 0]}}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, rod]}
  B: {type: revolute, links: [rod, slider]}
  slide:
    {type: prismatic, links: [ground, slider], axis: {point: guide, direction: [1, 0]}, point: B}
drivers:
  motor: {joint: O, motion: {speed: 120}}
loads:
  push: {type: force, link: slider, point: B, value: [-P, 0]}
sketch: {A: [r, 0], B: [r + l - 5, e]}
analysis: {start: 0, sweep: 360, positions: 36}
"""


def test_offset_slider_crank_closed_form():
    """Massless links, a force −P·x̂ on the slider: M_b·ω + F·v_B = 0, so M_b = P·v_B/ω with
    x_B = r cos φ + √(l² − (r sin φ − e)²) (l the rod) and, differentiated by hand,
    v_B = −r ω sin φ − (r sin φ − e)·r ω cos φ / √(l² − (r sin φ − e)²)."""
    r, rod, e, p_load = 0.080, 0.300, 0.025, 500.0
    omega = 120 * 2 * math.pi / 60
    result = _analyze(ks.loads(OFFSET_SLIDER_CRANK, file="massless.yaml"))
    rows = [3, 11, 20, 29]
    record = lever_stage(result, rows)
    for p in record.positions:
        phi = math.radians(p.coordinate)
        s = r * math.sin(phi) - e
        v_b = -r * omega * math.sin(phi) - s * r * omega * math.cos(phi) / math.sqrt(rod**2 - s**2)
        m_b = p_load * v_b / omega
        scale = p_load * r  # the effort's scale, N·m
        for got in (p.lever, p.power, p.solution):
            assert got == pytest.approx(m_b, rel=TOL, abs=TOL * scale)
        (push,) = [t for t in p.terms if t.name == "push"]  # the only load: no mass
        assert len(p.terms) == 1
        assert push.image == pytest.approx((v_b, 0.0), abs=1e-12 * r * omega)
        assert push.turned == pytest.approx((0.0, -p_load))


def test_rows_out_of_range_and_results_without_efforts_are_refused():
    result = _analyze(ks.loads(OFFSET_SLIDER_CRANK, file="massless.yaml"))
    with pytest.raises(IndexError, match="not among"):
        lever_stage(result, [len(result)])


def test_the_docs_example_runs(monkeypatch, capsys):
    """docs/methods.md's example of this section runs and prints the three M_b."""
    text = (ROOT / "docs" / "methods.md").read_text(encoding="utf-8")
    section = text.split("## The balancing moment, three ways", 1)[1].split("\n## ", 1)[0]
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(ROOT)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        exec(compile(code, "docs/methods.md (the lever)", "exec"), {})
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 4
    for line in lines:
        _, lever, power, solution, err = (float(x) for x in line.split())
        assert lever == pytest.approx(solution, rel=TOL, abs=TOL) and err <= TOL


def test_springs_dampers_and_an_effort_driver_are_on_the_lever():
    """Springs and dampers (their power −f·ṡ) and an ``effort:`` driver beside the motion
    driver are loads on the lever; the three still agree."""
    from tests.kinetics.test_elements import slider

    record = lever_stage(_analyze(slider()), [3, 20, 40, 60])
    powered = {t.name for t in record.positions[0].terms if t.kind == "power"}
    assert powered == {"spring", "table", "damper", "tors", "rd"}
    _agree(record)
    model = variant(
        "slider_crank",
        brake=(r"(motor: \{joint: O, .*\}\}\n)", r"\1  brake: {joint: A, effort: 5}\n"),
    )
    record = lever_stage(_analyze(model), [3, 100, 200, 300])
    assert [t.name for t in record.positions[0].terms if t.kind == "power"] == ["efforts"]
    _agree(record)


def test_two_motors_each_balanced_with_the_others_power_from_the_solution():
    """The five-bar without its gears, driven by two motors: each driver's M_b with the
    other's power (from the solution) counted as a load."""
    model = variant(
        "geared_fivebar",
        mesh=(r"  mesh:\n(    .*\n)+", ""),
        motor2=(
            r"(motor: \{joint: O1.*\n)",
            r"\1  motor2: {joint: O2, motion: {speed: -120}, points: [x, B]}\n",
        ),
    )
    result = _analyze(model)
    first, second = (lever_stage(result, [10, 100, 200, 300], driver=i) for i in (0, 1))
    assert (first.effort, second.effort) == ("motor.torque", "motor2.torque")
    for record in (first, second):
        _agree(record)
    for a, b in zip(first.positions, second.positions):  # each is the other's "others"
        assert a.others == pytest.approx(b.solution * b.speed, rel=1e-12)
        assert b.others == pytest.approx(a.solution * a.speed, rel=1e-12)


def test_a_kinematics_only_result_is_refused():
    result = ks.analyze(ks.loads(OFFSET_SLIDER_CRANK, file="m.yaml"), kinematics_only=True)
    with pytest.raises(ValueError, match="efforts"):
        lever_stage(result, [0])
