"""The whole report: analyse, draw the pictures, assemble the sections and write
``report.md``, ``report.html``, ``results.csv`` and ``summary.json``."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ...errors import KinetostaticsError
from ...model import Model
from .. import plotting as pl
from ..loading import load
from .blocks import _Heading, _Image, _Para, _Table, _to_html, _to_markdown
from .data import _data_blocks, _structure_blocks
from .results import _flatten, _summary_blocks, report_tables


class ReportError(KinetostaticsError, ValueError):
    """A report cannot be written as asked."""


def write_report(
    source, out: str | Path, *, polygons: Sequence[str] | None = None, dpi: float = 110
) -> dict[str, Path]:
    """Analyse ``source`` (a YAML path or a Model) and write the report to ``out``.

    ``polygons``: course-position labels (``"2"``, ``"7"``, ``"1′"``) at which
    to draw velocity and acceleration polygons; default positions 2 and 7 (the
    ones a slotting-machine course design works by hand), or position 1 where
    there are no such positions.  Returns the paths written (``markdown``,
    ``html``, ``csv``, ``summary``).
    """
    if isinstance(source, Model):
        model = source
    else:
        model = load(source)
    out = Path(out)
    img = out / "img"
    img.mkdir(parents=True, exist_ok=True)
    result = pl.analyze_for_pictures(model, course=True, events=True)
    system = result.system
    course = pl.course_positions(result)
    labels = [lab for lab, _ in course]
    if polygons is None:
        polygons = [p for p in ("2", "7") if p in labels] or labels[:1]
    polygons = [p.replace("'", "′") for p in polygons]
    for p in polygons:
        if p not in labels:
            raise ReportError(
                f"no course position '{p}' for polygons (have "
                f"{', '.join(labels) or 'none: not a full cycle of a crank'})"
            )
    if course:
        rows = course
    else:  # no crank cycle: 12 rows spread over the run
        order = np.argsort(result["travel"], kind="stable")
        picks = np.unique(np.linspace(0, len(order) - 1, min(12, len(order))).round().astype(int))
        rows = [(str(n + 1), int(order[k])) for n, k in enumerate(picks)]
    csv_path, summary_path = out / "results.csv", out / "summary.json"
    result.to_csv(csv_path)
    summary = result.summary()
    summary_path.write_text(json.dumps(summary, indent=2, default=float))

    def save(fig, name: str) -> Path:
        path = img / f"{name}.png"
        fig.savefig(path, dpi=dpi)
        return path

    moving_pins = [
        f"{a.link}.{a.point}"
        for j in model.joints
        if j.pin and model.ground.name not in j.links
        for a in j.anchors()
        if a.at_joint and a.link == j.links[1]
    ]
    out_m = pl.output_motion(result)
    paths = list(dict.fromkeys(moving_pins))
    first = rows[0][1]
    blocks: list = [
        _Heading(1, f"Course-design report: {model.name}"),
        _Para(
            "Kinetostatic analysis by `kinetostatics` (exact positions, velocities "
            "and accelerations; d'Alembert inertia loads; Newton–Euler reactions; "
            "friction by the approximate and the consistent solution). Conventions: "
            "x right, y up, angles and moments counter-clockwise positive; a joint's "
            "reaction F_ij is the force of link i on link j. Course-design positions: "
            "1…12 every 30° from the analysis start in the sense of rotation; k′ are "
            "the positions where a load switches (start and end of cutting), after "
            "position k."
        ),
    ]
    blocks += _data_blocks(model, system)
    blocks += _structure_blocks(system)
    blocks += _summary_blocks(result, summary)
    blocks.append(_Heading(2, "4. The mechanism"))
    blocks.append(
        _Image(
            save(pl.draw_mechanism(result, row=first, paths=paths, dpi=dpi), "mechanism"),
            f"The mechanism at position {rows[0][0]} with the paths of its moving pins "
            "(true scale μ_l as stated).",
        )
    )
    blocks.append(_Heading(2, "5. Kinematics and forces at the course-design positions"))
    blocks.append(
        _Para(
            f"Rows of `results.csv` (the column CSV row) at the positions "
            f"{', '.join(lab for lab, _ in rows)}; values to 5 significant digits, "
            "column names and units as in the CSV."
        )
    )
    for t in report_tables(result, rows):
        blocks.append(t)
    blocks.append(_Heading(2, "6. Curves over the cycle"))
    blocks.append(
        _Image(
            save(pl.motion_diagram(result, dpi=dpi), "motion"),
            f"Motion diagram of the output ({out_m['name']}): position, velocity, "
            "acceleration; the shaded zone is where the process load acts.",
        )
    )
    blocks.append(
        _Image(
            save(pl.torque_curves(result, dpi=dpi), "torque"),
            "Driving torque without friction, with the approximate and with the "
            "consistent friction solution.",
        )
    )
    if any(f"{d.name}.efficiency" in result.columns for d in system.motion_drivers):
        blocks.append(
            _Image(
                save(pl.efficiency_curve(result, dpi=dpi), "efficiency"),
                "Instantaneous and cycle efficiency of the drive.",
            )
        )
    blocks.append(
        _Image(
            save(pl.reaction_curves(result, friction=model.has_friction, dpi=dpi), "reactions"),
            "Magnitudes of the joint reactions.",
        )
    )
    blocks.append(_Heading(2, "7. Velocity and acceleration polygons"))
    blocks.append(
        _Para(
            "Drawn from the exact results to the stated scales μ_v and μ_a (true "
            "scale when the PNG is printed at 100 %): p is the pole, lower-case "
            "letters the points (a2, a3: the coincident points of links 2 and 3), n "
            "and k the ends of normal and Coriolis components."
        )
    )
    for lab in polygons:
        k = dict(course)[lab]
        tag = lab.replace("′", "p")
        blocks.append(
            _Image(
                save(pl.draw_mechanism(result, row=k, forces=True, dpi=dpi), f"forces_{tag}"),
                f"Position {lab}: the loads drawn to scale (reactions of link i on "
                "link j at the joints, inertia forces and couples, weights, process "
                "load, driving torque).",
            )
        )
        for kind in ("velocity", "acceleration"):
            blocks.append(
                _Image(
                    save(pl.polygon_figure(result, kind, row=k, dpi=dpi), f"{kind}_{tag}"),
                    f"{kind.capitalize()} polygon at position {lab}.",
                )
            )
    blocks.append(_Heading(2, "8. Polar diagrams of the joint loads"))
    blocks.append(
        _Image(
            save(pl.polar_diagrams(result, dpi=dpi), "polar"),
            "Reaction of each revolute joint in the frame of the link that receives "
            "it, over the cycle (numbers: course positions).",
        )
    )
    if "flywheel" in summary:
        blocks.append(_Heading(2, "9. Flywheel"))
        fw = summary["flywheel"]
        blocks.append(
            _Table(
                ["quantity", "value"],
                [[k, v] for k, v in _flatten(fw)],
                "Flywheel (from summary.json)",
            )
        )
    md = _to_markdown(blocks, out)
    md_path, html_path = out / "report.md", out / "report.html"
    md_path.write_text(md, encoding="utf-8")
    html_path.write_text(_to_html(blocks, f"Course-design report: {model.name}"), encoding="utf-8")
    return {"markdown": md_path, "html": html_path, "csv": csv_path, "summary": summary_path}
