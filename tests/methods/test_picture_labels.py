"""Crowded labels of the methods' pictures (issue 38): ``crowding.place_labels`` sets the
labels of the instant centres and the force polygons apart by one deterministic rule, and
the force polygon's group is named in the picture's language from the record's structured
``kind``/``letters`` (not the English label)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.methods.centres import instant_centres
from kinetostatics.methods.polygons import force_polygons
from kinetostatics.outputs.labels import link_numbers
from kinetostatics.outputs.plotting import analyze_for_pictures, course_positions
from kinetostatics.outputs.plotting.crowding import Label, place_labels
from kinetostatics.outputs.plotting.forces import group_figure, group_title
from kinetostatics.outputs.plotting.style import _figure
from tests.helpers import ROOT

pytest.importorskip("matplotlib")


def _boxes(fig, texts):
    renderer = fig.canvas.get_renderer() if hasattr(fig.canvas, "get_renderer") else None
    renderer = renderer or fig._get_renderer()
    return [t.get_window_extent(renderer) for t in texts]


def _overlap(a, b) -> float:
    w = min(a.x1, b.x1) - max(a.x0, b.x0)
    h = min(a.y1, b.y1) - max(a.y0, b.y0)
    return w * h if w > 0 and h > 0 else 0.0


def _crowd():
    fig = _figure(80, 80, dpi=100)
    ax = fig.add_axes([0.1, 0.1, 0.8, 0.8])
    ax.set_xlim(0, 100)
    ax.set_ylim(0, 100)
    pts = [(50, 50), (53, 50), (50, 53), (54, 54), (47, 53), (50, 50)]  # within ~10 pt
    labels = [Label(f"P{k}", p, primary=k % 2 == 0) for k, p in enumerate(pts)]
    labels.append(Label("P0", (50, 50)))  # the same text at the same point: skipped
    return fig, ax, labels


def test_crowded_labels_do_not_overlap_and_one_point_has_one_label():
    fig, ax, labels = _crowd()
    placed = place_labels(ax, labels)
    texts = [t.get_text() for t in placed]
    # P0 and P5 at one point (both primary? P5 is secondary): the primary ones merge
    assert texts.count("P0") + sum("P0," in t for t in texts) == 1
    assert sorted(t for t in " ".join(texts).replace(",", " ").split()) == [
        "P0", "P1", "P2", "P3", "P4", "P5"
    ]  # fmt: skip
    boxes = _boxes(fig, placed)
    for a in range(len(boxes)):
        for b in range(a):
            assert _overlap(boxes[a], boxes[b]) == 0.0, (texts[a], texts[b])
    sizes = {t.get_text(): t.get_fontsize() for t in placed}
    assert sizes["P1"] < sizes["P2"]  # a secondary label is smaller
    # the rule is deterministic: the same offsets again
    fig2, ax2, labels2 = _crowd()
    again = place_labels(ax2, labels2)
    assert [t.xyann for t in again] == [t.xyann for t in placed]


def test_the_force_polygon_names_its_group_in_the_pictures_language():
    result = analyze_for_pictures(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml"),
                                  course=True)  # fmt: skip
    row = dict(course_positions(result))["2"]
    groups = force_polygons(result, [("2", row)]).to_dict()["positions"][0]["groups"]
    dyad = next(g for g in groups if g["kind"] == "dyad" and g["letters"] == "RPR")
    assert group_title(dyad, "en") == dyad["label"] == "RPR dyad {block, bar}"
    assert group_title(dyad, "zh") == "RPR 型Ⅱ级杆组 {block, bar}"
    fig = group_figure(dyad, numbers=link_numbers(result.system), lang="zh")
    title = fig.axes[0].get_title()
    assert "型Ⅱ级杆组" in title and "dyad" not in title
    # the polygon's labels keep clear of each other
    poly = fig.axes[1]
    texts = [t for t in poly.texts if t.get_gid() == "force-polygon-label"]
    boxes = _boxes(fig, texts)
    assert all(_overlap(boxes[a], boxes[b]) == 0.0 for a in range(len(boxes)) for b in range(a))


def test_centres_at_a_pin_share_a_label_and_the_pins_own_is_secondary():
    from kinetostatics.outputs.plotting.centres import centres_figure

    result = analyze_for_pictures(ks.load(ROOT / "mechanisms" / "watt_sixbar.yaml"), course=True)
    row = dict(course_positions(result))["2"]
    record = instant_centres(result, row).to_dict()
    fig = centres_figure(result, record)
    texts = [t for t in fig.axes[0].texts if t.get_gid() == "instant-centre"]
    names = [n for t in texts for n in t.get_text().split(", ")]
    assert len(names) == len(set(names))  # each centre once
    numbers = link_numbers(result.system)
    by_joint = {
        "P{}{}".format(*sorted(numbers[b] for b in c["bodies"]))
        for c in record["centres"]
        if c["how"] == "joint"
    }
    sizes = {n: t.get_fontsize() for t in texts for n in t.get_text().split(", ")}
    assert {sizes[n] for n in by_joint & set(sizes)} == {6.0}
    assert {sizes[n] for n in set(sizes) - by_joint} == {7.0}
    boxes = _boxes(fig, texts)
    overlaps = sum(_overlap(boxes[a], boxes[b]) > 0 for a in range(len(boxes)) for b in range(a))
    assert overlaps == 0
    assert np.isfinite([t.xyann for t in texts]).all()
