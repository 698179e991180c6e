"""The free body and force polygon of each Assur group (methods/polygons.py): on every
shipped motion-driven file at two positions every polygon closes and every group's
moments balance about a point (two checks independent of each other), the groups come in
the order of the solution, the reactions are the result's ``<joint>.Fx/.Fy`` columns, the
driving link carries the solution's M_b; and the slotting machine's last group by hand."""

from __future__ import annotations

import io
import json
import math
import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.methods.polygons import POLYGON_SIZE_MM, ForcePolygons, force_polygons
from kinetostatics.methods.stage import methods_stage
from kinetostatics.outputs.plotting.rows import analyze_for_pictures, course_positions
from tests.helpers import MECHANISMS, ROOT, motion_driven

TOL = 1e-9  # the brief's: |Σ F| ≤ 1e-9 of the largest force
MOTION_DRIVEN = set(motion_driven())
SLOTTING = ROOT / "mechanisms" / "slotting_machine.yaml"


def _analyze(model):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ks.analyze(model)


def _moment_about(group, o) -> float:
    """Σ (p − o) × F + Σ couples of a group's free body about point ``o``."""
    total = 0.0
    for f in group.forces:
        (x, y), (fx, fy) = f.point, f.vector
        total += (x - o[0]) * fy - (y - o[1]) * fx + f.couple
    return total


def _check_balance(record: ForcePolygons) -> None:
    for p in record.positions:
        for g in p.groups:
            forces = [np.array(f.vector) for f in g.forces]
            largest = max(float(np.hypot(*v)) for v in forces)
            assert largest > 0, (p.row, g.name)
            # the polygon: its last vertex is Σ F, chained from the origin
            assert np.allclose(g.vertices[-1], np.sum(forces, axis=0), rtol=0, atol=1e-12 * largest)
            assert g.closure <= TOL * largest, (p.row, g.name, g.closure, largest)
            assert g.closure_error <= TOL
            # the moments, apart from the polygon: about a point away from every force
            o = np.mean([f.point for f in g.forces], axis=0) + np.array([0.37, -0.21])
            arms = sum(
                abs((f.point[0] - o[0]) * f.vector[1] - (f.point[1] - o[1]) * f.vector[0])
                + abs(f.couple)
                for f in g.forces
            )
            assert abs(_moment_about(g, o)) <= TOL * arms, (p.row, g.name)
            assert g.moment_error <= TOL


def _check_reactions(result, record: ForcePolygons) -> None:
    """Each reaction is the result's column: of i on j on link j, its opposite on i."""
    joints = {j.name: j for j in result.system.model.joints}
    for p in record.positions:
        for g in p.groups:
            for f in (*g.forces, *g.inner):
                if f.kind != "reaction" or f"{f.joint}.Fx" not in result.columns:
                    continue
                i, j = joints[f.joint].links
                sign = 1.0 if f.link == j else -1.0
                assert f.link in (i, j) and f.by in (i, j) and f.by != f.link
                col = np.array([result[f"{f.joint}.Fx"][p.row], result[f"{f.joint}.Fy"][p.row]])
                scale = max(np.hypot(*col), 1e-9)
                assert np.allclose(f.vector, sign * col, rtol=0, atol=1e-9 * scale), f


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_every_polygon_closes_and_every_group_balances_on_every_shipped_file(path):
    if path.stem not in MOTION_DRIVEN:
        pytest.skip("effort-driven: analyze refuses it (it is simulated, not analysed)")
    result = _analyze(ks.load(path))
    n = len(result)
    record = force_polygons(result, [("a", n // 5), ("b", 3 * n // 5)])
    _check_balance(record)
    _check_reactions(result, record)
    system = result.system
    for p in record.positions:
        # the order of the solution: the last group first, the driving link last
        assert [g.name for g in p.groups] == [pl.group.name for pl in system.plans[::-1]]
        assert p.groups[-1].driving
        # the driving link's polygon carries the solution's effort M_b (with balance_at,
        # the group of the joint that carries it)
        driver = system.motion_drivers[0]
        own = driver.driver.balance_at in (None, driver.joint.name)
        efforts = [(g, f) for g in p.groups for f in g.forces if f.kind == "balancing"]
        assert len(efforts) == 1 and efforts[0][1].status == "solved"
        col = f"{driver.name}.torque" if driver.joint.angular else f"{driver.name}.force"
        if own:
            assert efforts[0][0] is p.groups[-1]
        if own and driver.joint.angular:  # +τ on j, −τ on i: the driving link is one
            got = abs(efforts[0][1].couple)
            assert got == pytest.approx(abs(result[col][p.row]), rel=1e-9, abs=1e-9)
        # a group's known reactions are the ones of the groups already solved
        solved_before = set()
        for g in p.groups:
            for f in g.forces:
                if f.kind == "reaction" and f.status == "known":
                    assert f.by in solved_before, (g.name, f.name)
                assert f.status == "known" or f.kind in ("reaction", "balancing")
            solved_before.update(g.links)
        for g in p.groups:
            mantissa = g.mu_F / 10 ** math.floor(math.log10(g.mu_F) + 1e-12)
            assert any(abs(mantissa - r) < 1e-9 for r in (1, 2, 2.5, 4, 5)), g.mu_F
            span = np.ptp(np.array(g.vertices), axis=0).max()
            assert span / g.mu_F <= POLYGON_SIZE_MM + 1e-9  # drawn at most 60 mm across
    json.dumps(record.to_dict(), allow_nan=False)


def test_slotting_machine_last_group_by_hand():
    """The RRP dyad {rod, ram} at a cutting position: the rod is massless (a two-force
    member along BC), the ram carries its weight G5 = 320 N, its inertia force −m a and
    the cutting force Q = 1000 N at the tool, d = 120 mm off the ram's axis (the file's
    data); the guide (horizontal normal force and couple) and B are solved."""
    result = _analyze(ks.load(SLOTTING))
    k = 30  # the crank at 300° − 30°: the ram moves down, cutting
    group = force_polygons(result, [k]).positions[0].groups[0]
    assert group.links == ("rod", "ram")
    forces = {f.name: f for f in group.forces}
    g, m, q_cut, d = 10.0, 32.0, 1000.0, 0.120
    a_y = result["ram.ay"][k]
    assert forces["cutting"].vector == pytest.approx((0.0, q_cut), abs=1e-9)
    assert forces["G_ram"].vector == pytest.approx((0.0, -m * g), abs=1e-9)
    assert forces["F_I_ram"].vector == pytest.approx((0.0, -m * a_y), abs=1e-9)
    b = np.array([result["rod.B.x"][k], result["rod.B.y"][k]])
    c = np.array([result["rod.C.x"][k], result["rod.C.y"][k]])
    # ΣF_y = 0 gives B_y; the rod's force lies along CB; the guide's normal is −B_x
    b_y = -(q_cut - m * g - m * a_y)
    b_x = b_y * (b[0] - c[0]) / (b[1] - c[1])
    assert forces["B"].vector == pytest.approx((b_x, b_y), abs=1e-9 * abs(b_y))
    assert forces["B"].status == forces["guide"].status == "solved"
    guide = forces["guide"]
    assert guide.vector == pytest.approx((-b_x, 0.0), abs=1e-9 * abs(b_y))
    # the guide's moment about C balances the ram's loads (all on vertical lines)
    x_s = c[0]  # the ram's centre of mass is C
    loads = d * q_cut + (x_s - c[0]) * (-m * g - m * a_y)
    (px, py), (fx, fy) = guide.point, guide.vector
    guide_moment = (px - c[0]) * fy - (py - c[1]) * fx + guide.couple
    assert guide_moment == pytest.approx(-loads, abs=1e-9 * q_cut * d)


def test_course_positions_in_methods_json():
    model = ks.load(SLOTTING)
    result = analyze_for_pictures(model, course=True)
    rows = course_positions(result)[:3]
    out = methods_stage(result, rows)["force_polygons"]
    assert [p["label"] for p in out["positions"]] == [label for label, _ in rows]
    assert out["max_closure_error"] <= TOL
    assert "friction" in out["friction"]  # the file has friction: the note says so
    last = out["positions"][0]["groups"][-1]
    assert last["driving"] and last["links"] == ["crank"]


def test_group_figure_draws_the_polygon_at_its_scale():
    from kinetostatics.outputs.labels import link_numbers
    from kinetostatics.outputs.plotting.forces import group_figure

    result = _analyze(ks.load(SLOTTING))
    record = force_polygons(result, [30]).to_dict()
    group = record["positions"][0]["groups"][0]  # the RRP dyad {rod, ram}
    fig = group_figure(group, numbers=link_numbers(result.system), title="position 2")
    free, poly = fig.axes
    arrows = [a for a in poly.patches + poly.artists if a.get_gid() == "force-polygon"]
    drawn = [f for f in group["forces"] if any(f["vector"])]
    assert len(arrows) == len(drawn)
    labels = {t.get_text() for t in poly.texts if t.get_gid() == "force-polygon-label"}
    assert {"$F_{R34}$", "$F_{R65}$", "$G_{5}$", "$F_{I5}$", "cutting"} <= labels
    assert "20 N/mm" in poly.get_title()  # μ_F: the polygon's ≈1.02 kN over 60 mm rounds up
    closure = [t.get_text() for t in poly.texts if t.get_gid() == "closure"]
    assert closure and "closure error" in closure[0]
    fig.savefig(io.BytesIO(), format="png")


FRICTION_CIRCLES = {"slotting_machine": 1e-3, "shaper": 2e-3}  # the files' `radius:` (mm)


@pytest.mark.parametrize("stem", sorted(FRICTION_CIRCLES))
def test_with_friction_the_lines_touch_the_friction_circles(stem):
    """The consistent solution with friction: the polygons close and the moments balance;
    a turning pair's reaction is the Fx_friction/Fy_friction column and its line is
    tangent to the friction circle of the file's radius where the pair turns."""
    result = _analyze(ks.load(ROOT / "mechanisms" / f"{stem}.yaml"))
    n = len(result)
    rows = [n // 5, 3 * n // 5]
    assert np.all(result["friction.status"][rows] == 0)  # converged, every pair turning
    record = force_polygons(result, rows, friction=True)
    assert record.to_dict()["frictionless"] is False
    _check_balance(record)
    radius = FRICTION_CIRCLES[stem]
    seen = 0
    joints = {j.name: j for j in result.system.model.joints}
    for p in record.positions:
        for g in p.groups:
            for f in (*g.forces, *g.inner):
                if f.kind != "reaction" or not joints[f.joint].angular:
                    continue
                i, j = joints[f.joint].links
                sign = 1.0 if f.link == j else -1.0
                fx, fy = (result[f"{f.joint}.F{a}_friction"][p.row] for a in "xy")
                col = np.array([fx, fy])
                assert np.allclose(f.vector, sign * col, rtol=0, atol=1e-9 * np.hypot(*col))
                if f.friction_radius is None:
                    continue  # a pair without friction
                seen += 1
                assert f.friction_radius == pytest.approx(radius, rel=1e-9)
                assert f.offset == pytest.approx(radius, rel=1e-9), (f.joint, p.row)
                # the line's distance from the pin, from the drawn point and vector
                d = np.array(f.point) - np.array(f.pin)
                u = np.array(f.vector) / np.hypot(*f.vector)
                assert abs(d[0] * u[1] - d[1] * u[0]) == pytest.approx(radius, rel=1e-9)
        # the driving link's effort is the consistent solution's torque_friction
        effort = next(f for f in p.groups[-1].forces if f.kind == "balancing")
        assert abs(effort.couple) == pytest.approx(abs(result["motor.torque_friction"][p.row]))
    assert seen >= 4


def test_friction_asked_of_a_file_without_it_is_refused():
    result = _analyze(ks.load(ROOT / "mechanisms" / "fourbar_balancing.yaml"))
    with pytest.raises(ValueError, match="no friction"):
        force_polygons(result, [0], friction=True)


def test_the_docs_example_runs(monkeypatch, tmp_path):
    """docs/methods.md's example of this section runs and saves a picture per group."""
    text = (ROOT / "docs" / "methods.md").read_text(encoding="utf-8")
    section = text.split("## Force polygons of the Assur groups", 1)[1].split("\n## ", 1)[0]
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    code = code.replace('"mechanisms/', f'"{ROOT.as_posix()}/mechanisms/')
    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        exec(compile(code, "docs/methods.md (force polygons)", "exec"), {})
    assert sorted(p.name for p in tmp_path.glob("*.png")) == [
        "group1.png",
        "group2.png",
        "group3.png",
    ]
