"""Pictures are made headless, and what they draw is the results: the polygons
close onto the computed velocities and accelerations, the drawn joints sit at
the computed positions, the curves carry the result columns, and an animation
has the requested frames.  No pixel snapshots."""

import math
import sys

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.outputs import plotting as pl
from tests.helpers import MECHANISMS, ROOT
from tests.oracles import slider_crank_closed_form as cf


@pytest.fixture(scope="module")
def slotting():
    return pl.analyze_for_pictures(
        ks.load(ROOT / "mechanisms" / "slotting_machine.yaml"), course=True
    )


@pytest.fixture(scope="module")
def slider_crank():
    return pl.analyze_for_pictures(
        ks.load(ROOT / "mechanisms" / "slider_crank.yaml"), positions=[47.5], course=True
    )


def _xy(result, ref, kind, row):
    sx, sy = {"velocity": ("vx", "vy"), "acceleration": ("ax", "ay"), "position": ("x", "y")}[kind]
    return np.array([result[f"{ref}.{sx}"][row], result[f"{ref}.{sy}"][row]])


@pytest.mark.parametrize("kind", ["velocity", "acceleration"])
@pytest.mark.parametrize("label", ["1", "2", "7", "8′", "11"])
def test_slotting_polygon_closes_onto_the_computed_vectors(slotting, kind, label):
    row = pl.row_at(slotting, label=label)
    poly = pl.polygon(slotting, row, kind)
    scale = max(np.hypot(*n.vector) for n in poly.nodes.values())
    # every named point's absolute vector is the result's
    for node in poly.nodes.values():
        for ref in node.refs:
            if "@" not in ref:
                np.testing.assert_allclose(
                    node.vector, _xy(slotting, ref, kind, row), rtol=0, atol=1e-12 * scale
                )
    # every relative-vector chain closes: start + Σ components = end
    for ch in poly.chains:
        closing = poly.tip(ch.start) + sum(v for _, v in ch.components)
        np.testing.assert_allclose(closing, poly.tip(ch.end), rtol=0, atol=1e-9 * scale)
    # the textbook equations: v_C = v_B + v_CB, and the slot: a3 = a2 − (k + r)
    ends = {(ch.start, ch.end) for ch in poly.chains}
    assert ("b", "c") in ends and ("a3", "a2") in ends
    assert poly.fixed == ("crank.O2", "bar.O3")
    ch = next(c for c in poly.chains if (c.start, c.end) == ("b", "c"))
    np.testing.assert_allclose(
        _xy(slotting, "bar.B", kind, row) + sum(v for _, v in ch.components),
        _xy(slotting, "ram.C", kind, row),
        rtol=0,
        atol=1e-9 * scale,
    )
    if kind == "acceleration":
        slide = next(c for c in poly.chains if (c.start, c.end) == ("a3", "a2"))
        assert [n for n, _ in slide.components] == ["ak_A2A3", "ar_A2A3"]
        k = slide.components[0][1]
        w3 = slotting["bar.omega"][row]
        vr = next(
            c
            for c in pl.polygon(slotting, row, "velocity").chains
            if (c.start, c.end) == ("a3", "a2")
        ).components[0][1]
        np.testing.assert_allclose(k, 2 * w3 * np.array([-vr[1], vr[0]]), atol=1e-12 * scale)


def test_slider_crank_polygon_matches_the_closed_form(slider_crank):
    row = pl.row_at(slider_crank, 47.5)
    p = cf.SliderCrank()
    ref = cf.kinematics(p, math.radians(47.5))
    for kind, key in (("velocity", "vB"), ("acceleration", "aB")):
        poly = pl.polygon(slider_crank, row, kind)
        chain = next(c for c in poly.chains if (c.start, c.end) == ("a", "b"))
        closing = poly.tip("a") + sum(v for _, v in chain.components)
        np.testing.assert_allclose(closing, [ref[key], 0.0], rtol=1e-9, atol=1e-9 * abs(ref[key]))
    vel = pl.polygon(slider_crank, row, "velocity")
    np.testing.assert_allclose(vel.tip("a"), [ref["A_vx"], ref["A_vy"]], rtol=1e-12)


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_drawn_joints_are_the_computed_positions(path):
    model = ks.load(path)
    if any(d.motion is None for d in model.drivers):
        pytest.skip("an effort-driven mechanism: simulate, not analyze")
    result = pl.analyze_for_pictures(model, frames=24, events=False)
    row = 7
    geo = pl.mechanism_geometry(result, row)
    model = result.system.model
    for j in model.joints:
        if j.kind not in ("revolute", "prismatic"):
            continue
        point = j.point_names[1] if j.kind == "revolute" else j.point_name
        link = j.links[1]
        np.testing.assert_allclose(
            geo.joints[j.name], _xy(result, f"{link}.{point}", "position", row), atol=1e-12
        )
    for lk in model.moving_links:
        for name in lk.points:
            np.testing.assert_allclose(
                geo.points[f"{lk.name}.{name}"],
                _xy(result, f"{lk.name}.{name}", "position", row),
                atol=1e-12,
            )
    # and the figure's pins are drawn there (axes in mm)
    from matplotlib.patches import Circle

    fig = pl.draw_mechanism(result, row=row, dpi=40)
    ax = fig.axes[0]
    centres = [np.array(c.center) for c in ax.get_children() if isinstance(c, Circle)]
    for j in model.joints:
        if j.kind == "revolute":
            assert min(np.hypot(*(c - geo.joints[j.name] * 1e3)) for c in centres) < 1e-9, j.name
    assert r"$\mu_l$ = " in ax.get_title(loc="left")


def test_drawing_with_forces_and_paths(slotting):
    row = pl.row_at(slotting, label="7")
    fig = pl.draw_mechanism(slotting, row=row, forces=True, paths=["rod.C", "bar.B"], dpi=40)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "x, mm" and ax.get_ylabel() == "y, mm"
    texts = [t.get_text() for t in ax.texts]
    assert any(t.startswith(" F_R₄₅") for t in texts)  # rod 4 on ram 5
    assert any("cutting" in t for t in texts)  # the cutting force acts at 7
    path = [ln for ln in ax.lines if len(ln.get_xdata()) == len(slotting)][0]
    np.testing.assert_allclose(
        path.get_xydata() / 1e3, np.column_stack((slotting["rod.C.x"], slotting["rod.C.y"]))
    )
    with pytest.raises(pl.PictureError, match="did you mean 'rod.C'"):
        pl.draw_mechanism(slotting, paths=["rod.CC"])


def test_curves_carry_the_result_columns(slotting):
    x = slotting["travel"]
    order = np.argsort(x, kind="stable")
    fig = pl.torque_curves(slotting, dpi=40)
    ax = fig.axes[0]
    curves = {ln.get_label().split(" (")[0]: ln for ln in ax.lines if len(ln.get_xdata()) == len(x)}
    np.testing.assert_array_equal(
        curves["without friction"].get_ydata(), slotting["motor.torque"][order]
    )
    np.testing.assert_array_equal(
        curves["with friction, consistent"].get_ydata(), slotting["motor.torque_friction"][order]
    )
    assert "N·m" in ax.get_ylabel() and "deg" in ax.get_xlabel()
    fig = pl.motion_diagram(slotting, dpi=40)
    s, v, a = (ax.lines[0].get_ydata() for ax in fig.axes[:3])
    np.testing.assert_allclose(
        s, (slotting["ram.C.y"][order]) * 1e3, atol=1e-9
    )  # guide point y = 0
    np.testing.assert_allclose(v, slotting["ram.C.vy"][order], atol=1e-12)
    np.testing.assert_allclose(a, slotting["ram.C.ay"][order], atol=1e-12)
    assert [ax.get_ylabel().split(", ")[-1] for ax in fig.axes[:3]] == ["mm", "m/s", "m/s²"]
    for make in (pl.reaction_curves, pl.efficiency_curve):
        fig = make(slotting, dpi=40)
        assert all(ax.get_xlabel() and ax.get_ylabel() for ax in fig.axes if ax.lines)
    fig = pl.plot_result(slotting, "rod.omega", "bar.omega", "ram.C.vy", dpi=40)
    assert [ax.get_ylabel() for ax in fig.axes if ax.lines] == ["rad/s", "m/s"]


def test_course_positions_and_events(slotting):
    labels = [lab for lab, _ in pl.course_positions(slotting)]
    assert labels == ["1", "1′", "2", "3", "4", "5", "6", "7", "8", "8′", "9", "10", "11", "12"]
    rows = dict(pl.course_positions(slotting))
    assert slotting["angle"][rows["7"]] == pytest.approx(120.0)
    assert slotting["angle"][rows["1′"]] == pytest.approx(270.4218, abs=1e-3)
    assert slotting["angle"][rows["8′"]] == pytest.approx(88.6321, abs=1e-3)
    spans = pl._active_spans(slotting)
    assert len(spans) == 1
    name, x0, x1 = spans[0]
    assert (x0, x1) == (pytest.approx(29.5782, abs=1e-3), pytest.approx(211.3679, abs=1e-3))


def test_polar_diagrams_in_the_link_frame(slotting):
    link, desc, F = pl.link_frame_loads(slotting, "C")
    assert link == "ram" and desc == "force of rod on ram"
    np.testing.assert_allclose(np.hypot(*F.T), np.hypot(slotting["C.Fx"], slotting["C.Fy"]))
    link, desc, F = pl.link_frame_loads(slotting, "B")
    th = np.radians(slotting["rod.theta"])
    along = slotting["B.Fx"] * np.cos(th) + slotting["B.Fy"] * np.sin(th)
    np.testing.assert_allclose(F[:, 0], along, atol=1e-9)
    fig = pl.polar_diagrams(slotting, dpi=40)
    assert len([ax for ax in fig.axes if ax.lines]) == 5  # the revolute joints


def test_polar_diagrams_mark_each_course_position_at_its_load(slotting):
    """Each course position of a polar diagram: a ray from the origin to the joint's load
    at that row, a point there and its label there (events in their colour)."""
    from matplotlib.collections import LineCollection

    fig = pl.polar_diagrams(slotting, ["C"], dpi=40)
    ax = fig.axes[0]
    _, _, F = pl.link_frame_loads(slotting, "C")
    course = pl.course_positions(slotting)
    tips = np.array([F[k] for _, k in course])
    (rays,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    segments = np.array(rays.get_segments())
    np.testing.assert_allclose(segments[:, 0], 0.0)
    np.testing.assert_allclose(segments[:, 1], tips)
    labels = {t.get_text(): (t.get_position(), t.get_color()) for t in ax.texts}
    assert list(labels) == [lab for lab, _ in course]
    for (lab, _), tip in zip(course, tips):
        np.testing.assert_allclose(labels[lab][0], tip)
        assert (labels[lab][1] == pl.style.EVENT_COLOR) == ("′" in lab)
    dots = [np.column_stack(ln.get_data()) for ln in ax.lines if ln.get_marker() == "o"]
    points = np.concatenate(dots)
    np.testing.assert_allclose(points, tips)  # in the course's order


def test_a_polar_diagram_labels_no_position_without_a_load():
    """Where the consistent friction solution has no value (self-locked, a dead centre),
    a polar diagram with friction has no point label: the labels are those of the
    positions with a load."""
    result = pl.analyze_for_pictures(
        ks.load(ROOT / "tests" / "hard" / "slider_crank_self_locking.yaml"), course=True
    )
    fig = pl.polar_diagrams(result, friction=True, dpi=40)
    for ax, joint in zip(fig.axes, [j.name for j in result.system.model.joints if j.pin]):
        _, _, F = pl.link_frame_loads(result, joint, friction=True)
        course = pl.course_positions(result)
        with_load = [lab for lab, k in course if np.isfinite(F[k]).all()]
        assert 0 < len(with_load) < len(course)  # the case has positions without a load
        assert [t.get_text() for t in ax.texts] == with_load


def test_course_positions_are_numbered_along_the_top_edge(slotting):
    """The curves number the course positions 1 … 12 above their top edge, each over a
    tick mark at its travel (every 30° from the first position), with the axis label
    above the numbers."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = pl.torque_curves(slotting, dpi=80)
    ax = fig.axes[0]
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    numbers = {t.get_text(): t for t in ax.texts if t.get_text().isdigit()}
    assert sorted(numbers, key=int) == [str(k) for k in range(1, 13)]
    for text, t in numbers.items():
        assert t.get_position()[0] == pytest.approx(30.0 * (int(text) - 1), abs=1e-9)
        box = t.get_window_extent(renderer)
        assert box.y0 > ax.bbox.y1  # above the top edge
        x_px = ax.transData.transform((t.get_position()[0], 0.0))[0]
        assert (box.x0 + box.x1) / 2 == pytest.approx(x_px, abs=0.5)  # centred on it
    (marks,) = [ln for ln in ax.lines if len(ln.get_xdata()) == 12 and ln.get_linestyle() == "None"]
    np.testing.assert_allclose(marks.get_xdata(), 30.0 * np.arange(12))
    assert ax.spines["top"].get_visible()
    (label,) = [t for t in ax.texts if t.get_text() == "course positions"]
    top = max(t.get_window_extent(renderer).y1 for t in numbers.values())
    assert label.get_window_extent(renderer).y0 > top - 1.0  # above them (its descent aside)


def test_polygon_figure_states_its_scale(slotting):
    row = pl.row_at(slotting, label="7")
    for kind, mu in (("velocity", r"$\mu_v$"), ("acceleration", r"$\mu_a$")):
        fig = pl.polygon_figure(slotting, kind, row=row, dpi=40)
        ax = fig.axes[0]
        title = ax.get_title(loc="left")
        assert mu in title
        # printed at 100 %, 1 mm of paper spans μ data units
        w_mm = ax.get_position().width * fig.get_figwidth() * 25.4
        x0, x1 = ax.get_xlim()
        scale = float(title.split(f"{mu} = ")[1].split(" ")[0])
        assert (x1 - x0) / w_mm == pytest.approx(scale, rel=1e-9)
        assert ax.get_xlabel().endswith("m/s" if kind == "velocity" else "m/s²")


def test_animation_has_the_requested_frames(tmp_path, capsys):
    from PIL import Image

    out = tmp_path / "cycle.gif"
    assert (
        main(
            [
                "animate",
                str(ROOT / "mechanisms" / "slotting_machine.yaml"),
                "--out",
                str(out),
                "--frames",
                "5",
                "--forces",
                "--dpi",
                "40",
            ]
        )
        == 0
    )
    with Image.open(out) as im:
        assert im.n_frames == 5
    assert "5 frames" in capsys.readouterr().out


def test_mp4_needs_ffmpeg(slider_crank, tmp_path, monkeypatch):
    import shutil

    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(pl.PictureError, match="needs ffmpeg"):
        pl.animate(slider_crank, tmp_path / "a.mp4")


def test_cli_plot_at_a_position_between_rows(tmp_path, capsys):
    assert (
        main(
            [
                "plot",
                str(ROOT / "mechanisms" / "slider_crank.yaml"),
                "--out",
                str(tmp_path),
                "--what",
                "drawing",
                "velocity",
                "--position",
                "47.5",
                "--dpi",
                "40",
            ]
        )
        == 0
    )
    # the velocity polygon's vector equations at the drawn position go to methods.json
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "drawing.png",
        "methods.json",
        "velocity.png",
    ]
    assert (
        main(
            [
                "plot",
                str(ROOT / "mechanisms" / "slider_crank.yaml"),
                "--out",
                str(tmp_path),
                "--what",
                "motion",
                "--output",
                "rodd",
            ]
        )
        == 2
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "did you mean 'rod'" in err[0]


def test_importing_the_picture_modules_is_light():
    import subprocess

    code = (
        "import sys, kinetostatics.plotting, kinetostatics.outputs.report, "
        "kinetostatics.cli.pictures;"
        "print(any(m.startswith('matplotlib') for m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
