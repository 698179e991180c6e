"""The course-design report: one self-contained Markdown and HTML document.

:func:`write_report` analyses a mechanism over a full cycle with rows at the
course-design positions (1…12 from ``analysis.start`` in the sense of motion,
and the load events 1′, 8′ …), and writes to a folder:

- ``report.md`` (images in ``img/``) and ``report.html`` (images embedded,
  no outside files);
- ``results.csv`` and ``summary.json`` of that analysis (the tables of the
  report are rows of this CSV, at full precision in the CSV and to 5
  significant digits in the report; the column ``CSV row`` gives the data row,
  counted from 1 below the header);
- the pictures in ``img/``.

Sections: data, structure (Assur groups), results summary, the mechanism
drawing, tables of positions, velocities, accelerations, reactions and
driving torque at the course-design positions, the curves, the velocity and
acceleration polygons at chosen positions, polar diagrams, and a flywheel
section when the summary has a ``flywheel`` entry.
"""

from __future__ import annotations

import base64
import html
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import KinetostaticsError

__all__ = ["ReportError", "report_tables", "write_report"]


class ReportError(KinetostaticsError, ValueError):
    """A report cannot be written as asked."""


# -- document blocks, rendered to Markdown and to HTML -----------------------------
@dataclass
class _Heading:
    level: int
    text: str


@dataclass
class _Para:
    text: str


@dataclass
class _Table:
    header: list[str]
    rows: list[list[str]]
    caption: str = ""


@dataclass
class _Image:
    path: Path  # inside the output folder
    caption: str


@dataclass
class _List:
    items: list[str]


def _md_cell(s: str) -> str:
    return str(s).replace("|", "\\|").replace("\n", " ")


def _to_markdown(blocks, out: Path) -> str:
    lines: list[str] = []
    for b in blocks:
        if isinstance(b, _Heading):
            lines += ["#" * b.level + " " + b.text, ""]
        elif isinstance(b, _Para):
            lines += [b.text, ""]
        elif isinstance(b, _List):
            lines += [f"- {item}" for item in b.items] + [""]
        elif isinstance(b, _Table):
            if b.caption:
                lines += [f"*{b.caption}*", ""]
            lines.append("| " + " | ".join(_md_cell(h) for h in b.header) + " |")
            lines.append("|" + "|".join("---" for _ in b.header) + "|")
            for r in b.rows:
                lines.append("| " + " | ".join(_md_cell(c) for c in r) + " |")
            lines.append("")
        elif isinstance(b, _Image):
            rel = b.path.relative_to(out).as_posix()
            lines += [f"![{b.caption}]({rel})", "", f"*{b.caption}*", ""]
    return "\n".join(lines).rstrip() + "\n"


_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,Arial,sans-serif;max-width:1100px;
margin:2em auto;padding:0 1em;color:#1d1d1d;line-height:1.45}
h1{border-bottom:2px solid #1f5fa8;padding-bottom:.2em}
h2{border-bottom:1px solid #ccc;padding-bottom:.15em;margin-top:1.8em}
table{border-collapse:collapse;font-size:.82em;margin:.6em 0 1.2em;display:block;overflow-x:auto}
th,td{border:1px solid #d0d0d0;padding:.2em .45em;text-align:right;white-space:nowrap}
th{background:#eef3fa}
td:first-child,th:first-child{text-align:left}
figure{margin:1em 0}
figure img{max-width:100%;height:auto;border:1px solid #eee}
figcaption,.caption{font-size:.85em;color:#444;font-style:italic}
code{background:#f3f3f3;padding:0 .2em}
"""


def _to_html(blocks, title: str) -> str:
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{html.escape(title)}</title>",
        f"<style>{_CSS}</style></head><body>",
    ]
    for b in blocks:
        if isinstance(b, _Heading):
            parts.append(f"<h{b.level}>{html.escape(b.text)}</h{b.level}>")
        elif isinstance(b, _Para):
            parts.append(f"<p>{_inline(b.text)}</p>")
        elif isinstance(b, _List):
            parts.append("<ul>" + "".join(f"<li>{_inline(i)}</li>" for i in b.items) + "</ul>")
        elif isinstance(b, _Table):
            if b.caption:
                parts.append(f'<p class="caption">{html.escape(b.caption)}</p>')
            head = "".join(f"<th>{html.escape(h)}</th>" for h in b.header)
            body = "".join(
                "<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>"
                for r in b.rows
            )
            parts.append(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
        elif isinstance(b, _Image):
            data = base64.b64encode(b.path.read_bytes()).decode("ascii")
            parts.append(
                f'<figure><img alt="{html.escape(b.caption)}" '
                f'src="data:image/png;base64,{data}">'
                f"<figcaption>{html.escape(b.caption)}</figcaption></figure>"
            )
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def _inline(text: str) -> str:
    """Escape, then turn `code` spans into <code>."""
    out, code = [], False
    for piece in text.split("`"):
        out.append(f"<code>{html.escape(piece)}</code>" if code else html.escape(piece))
        code = not code
    return "".join(out)


# -- numbers -------------------------------------------------------------------------
def _fmt(v: float, scale: float) -> str:
    """5 significant digits; round-off below 1e-9 of the column's scale prints as 0;
    missing values (self-locking) as an empty cell."""
    if not np.isfinite(v):
        return ""
    if abs(v) <= 1e-9 * scale:
        return "0"
    return f"{v:.5g}"


def _header(result, name: str) -> str:
    unit = result.units[name].replace("*", "·").replace("^2", "²")
    return f"{name} ({unit})"


def _table(result, rows: list[tuple[str, int]], names: list[str], caption: str) -> _Table:
    names = [n for n in names if n in result.columns]
    header = ["pos.", "CSV row"] + [_header(result, n) for n in names]

    def size(n):
        v = np.abs(np.asarray(result[n], dtype=float))
        return float(np.max(v[np.isfinite(v)])) if np.any(np.isfinite(v)) else 0.0

    by_unit: dict[str, float] = {}
    for n in names:  # round-off is judged per unit, table-wide
        by_unit[result.units[n]] = max(by_unit.get(result.units[n], 0.0), size(n))
    scale = {n: by_unit[result.units[n]] for n in names}
    body = [
        [lab, str(k + 1)] + [_fmt(float(result[n][k]), scale[n]) for n in names] for lab, k in rows
    ]
    return _Table(header, body, caption)


def _distinct_points(result) -> list[str]:
    """Moving points with distinct paths: one of each pin, none at rest."""
    system = result.system
    kept: list[str] = []
    l_ref = system.l_ref
    for n in system.links:
        for p in system.model.link(n).points:
            ref = f"{n}.{p}"
            xy = np.column_stack((result[f"{ref}.x"], result[f"{ref}.y"]))
            if np.ptp(xy, axis=0).max() <= 1e-9 * l_ref:
                continue
            if any(
                np.allclose(
                    xy,
                    np.column_stack((result[f"{k}.x"], result[f"{k}.y"])),
                    rtol=0,
                    atol=1e-9 * l_ref,
                )
                for k in kept
            ):
                continue
            kept.append(ref)
    return kept


def _rotating_links(result) -> list[str]:
    return [
        n
        for n in result.system.links
        if np.max(np.abs(result[f"{n}.omega"]))
        > 1e-9 * max(1.0, abs(result.system.motion_drivers[0].driver.motion.speed))
    ]


def report_tables(result, rows: Sequence[tuple[str, int]]) -> list[_Table]:
    """The report's tables at ``rows`` ``[(label, row index)]``: positions,
    velocities, accelerations, reactions, driving torque and friction."""
    pts = _distinct_points(result)
    rot = _rotating_links(result)
    model = result.system.model
    first = (
        ["angle", "travel", "time"] if "angle" in result.columns else ["stroke", "travel", "time"]
    )
    tables = [
        _table(
            result,
            rows,
            first + [f"{n}.theta" for n in rot] + [f"{p}.{c}" for p in pts for c in ("x", "y")],
            "Positions: driver coordinate, link angles (deg, CCW from +x), points (m)",
        ),
        _table(
            result,
            rows,
            [f"{n}.omega" for n in rot] + [f"{p}.{c}" for p in pts for c in ("vx", "vy")],
            "Velocities: angular velocities (rad/s, CCW +) and point velocities (m/s)",
        ),
        _table(
            result,
            rows,
            [f"{n}.alpha" for n in rot] + [f"{p}.{c}" for p in pts for c in ("ax", "ay")],
            "Accelerations: angular accelerations (rad/s², CCW +) and point accelerations (m/s²)",
        ),
    ]
    reac = []
    for j in model.joints:
        reac += [f"{j.name}.{lab}" for lab in j.reaction_labels]
    tables.append(
        _table(
            result,
            rows,
            reac,
            "Joint reactions without friction: force of link i "
            "on link j (N); prismatic pairs also N (normal force) and M (couple, N·m)",
        )
    )
    drv = []
    for d in result.system.motion_drivers:
        for word in ("torque", "force"):
            for suffix in ("", "_friction_approx", "_friction"):
                drv.append(f"{d.name}.{word}{suffix}")
        drv.append(f"{d.name}.efficiency")
    drv += ["friction.status", "power.input", "power.friction"]
    tables.append(
        _table(
            result,
            rows,
            drv,
            "Driving effort without friction, with the approximate "
            "and the consistent friction solution, efficiency, friction status (0 "
            "converged, 1 by homotopy, 2 self-locking, 3 a relative speed is zero), "
            "input power and friction loss (W)",
        )
    )
    if model.has_friction:
        fr = []
        for j in model.joints:
            fr += [f"{j.name}.{lab}_friction" for lab in j.reaction_labels]
        tables.append(
            _table(
                result,
                rows,
                fr,
                "Joint reactions with friction (consistent "
                "solution), force of link i on link j (N)",
            )
        )
    return tables


# -- the data section ----------------------------------------------------------------
def _mm(v) -> str:
    return ", ".join(f"{1e3 * float(c):.6g}" for c in v)


def _data_blocks(model, system) -> list:
    from .plotting import link_numbers

    nums = link_numbers(system)
    blocks: list = [_Heading(2, "1. Data")]
    units = ", ".join(f"{k}: {v}" for k, v in model.units.items()) or "SI"
    blocks.append(
        _Para(
            f"Source: `{model.source}`. Units of the file: {units}. Everything below "
            "is in SI unless stated (lengths of points in mm). Gravity: "
            f"({model.gravity[0]:g}, {model.gravity[1]:g}) m/s²."
        )
    )
    if model.parameters:
        blocks.append(
            _Table(
                ["parameter", "value (as in the file)"],
                [[k, f"{v:.6g}"] for k, v in model.parameters.items()],
                "Parameters",
            )
        )
    rows = []
    for lk in model.links:
        pts = "; ".join(f"{p}: ({_mm(np.asarray(v) + lk.com)})" for p, v in lk.points.items())
        rows.append(
            [
                lk.name,
                str(nums[lk.name]),
                "frame" if lk.ground else f"{lk.mass:.6g}",
                "" if lk.ground else f"{lk.inertia:.6g}",
                "" if lk.ground else f"({_mm(lk.com)})",
                pts,
            ]
        )
    blocks.append(
        _Table(
            [
                "link",
                "no.",
                "mass (kg)",
                "J_S (kg·m²)",
                "centre of mass (mm)",
                "points (mm, in the link's own frame)",
            ],
            rows,
            "Links (numbers as in the pictures; the frame last)",
        )
    )
    rows = []
    for j in model.joints:
        text = j.describe()
        rows.append(
            [
                j.name,
                j.kind,
                f"{j.links[0]} → {j.links[1]}",
                f"F{nums[j.links[0]]}{nums[j.links[1]]}",
                text.get("where", ""),
                text.get("friction", ""),
            ]
        )
    blocks.append(
        _Table(
            ["joint", "type", "links i → j", "reaction", "where", "friction"],
            rows,
            "Joints (the reaction is the force of link i on link j)",
        )
    )
    rows = []
    for d in model.drivers:
        if d.motion is not None:
            sp = d.motion.speed
            speed = (
                f"{sp:+.6g} rad/s ({sp * 30 / math.pi:+.6g} rpm)"
                if model.joint(d.joint).angular
                else f"{sp:+.6g} m/s"
            )
            law = getattr(d.motion, "kind", None)
            rows.append(
                [
                    d.name,
                    d.joint,
                    f"{law} law, peak speed {speed}" if law else speed,
                    d.balance_at or d.joint,
                ]
            )
        else:
            rows.append([d.name, d.joint, f"effort {d.effort}", ""])
    blocks.append(
        _Table(["driver", "joint", "motion (+ counter-clockwise)", "effort at"], rows, "Drivers")
    )
    if model.loads:
        rows = []
        for ld in model.loads:
            conds = []
            for c in ld.active:
                if c.kind == "moving":
                    conds.append(
                        f"{c.link}.{c.point or 'CoM'} moving along ({c.axis[0]:g}, {c.axis[1]:g})"
                    )
                elif c.kind == "travel":
                    conds.append(
                        f"travel of {c.link}.{c.point or 'CoM'} along ({c.axis[0]:g}, "
                        f"{c.axis[1]:g}) in [{c.bounds[0] * 1e3:.4g}, {c.bounds[1] * 1e3:.4g}] mm"
                    )
                else:
                    conds.append(
                        f"driver coordinate in [{math.degrees(c.bounds[0]):.4g}, "
                        f"{math.degrees(c.bounds[1]):.4g}]°"
                    )
            value = np.asarray(ld.value)
            val = (
                f"({', '.join(f'{v:g}' for v in value)}) N"
                if value.ndim
                else f"{float(value):g} {'N·m' if ld.kind == 'torque' else 'N'}"
            )
            if ld.table is not None:
                val += " (tabulated)"
            rows.append(
                [
                    ld.name,
                    ld.kind,
                    f"{ld.link}" + (f".{ld.point}" if ld.point else ""),
                    val,
                    "; ".join(conds) or "always",
                ]
            )
        blocks.append(_Table(["load", "kind", "acts on", "value", "active while"], rows, "Loads"))
    return blocks


def _structure_blocks(system) -> list:
    st = system.structure
    items = [
        f"mobility (Grübler–Kutzbach): {st.mobility}",
        f"independent loops: {len(st.loops)}"
        + ("" if not st.loops else " — " + "; ".join(" – ".join(lp) for lp in st.loops)),
    ]
    blocks: list = [_Heading(2, "2. Structure"), _List(items)]
    rows = []
    for k, plan in enumerate(system.plans, 1):
        g = plan.group
        rows.append([str(k), g.label, ", ".join(g.joints + g.drivers)])
    blocks.append(
        _Table(
            ["step", "Assur group (class and members)", "joints and drivers"],
            rows,
            "Assur groups in solve order",
        )
    )
    return blocks


def _summary_blocks(result, summary) -> list:
    blocks: list = [_Heading(2, "3. Results over the cycle")]
    items = [
        f"{len(result)} positions analysed (a full cycle: {'yes' if result.full_cycle else 'no'})"
    ]
    for name, o in summary["outputs"].items():
        items.append(
            f"output {name}: stroke {o['stroke'] * 1e3:.4f} mm, time ratio K = "
            f"{o['time_ratio']:.4f}; limit positions at "
            f"{o['limit_positions']['min']['angle']:.3f}° "
            f"and {o['limit_positions']['max']['angle']:.3f}°"
        )
    for e in summary["events"]:
        items.append(
            f"event: {e['load']} switches {e['switch']} at {e['angle']:.4f}° ({e['condition']})"
        )
    for name, d in summary["drivers"].items():
        line = f"driver {name}: mean {d['mean']:.4g} {d['unit']}, peak |·| {d['peak']:.4g}"
        if "mean_friction" in d and not math.isfinite(d["mean_friction"]):
            line += (
                f"; with friction: no consistent solution at any position (self-locking; "
                f"approximate mean {d['mean_friction_approx']:.4g})"
            )
        elif "mean_friction" in d:
            line += (
                f"; with friction mean {d['mean_friction']:.4g} (approximate "
                f"{d['mean_friction_approx']:.4g}), peak {d['peak_friction']:.4g}"
            )
        items.append(line + " (means over the analysed rows)")
    if "friction.status" in result.columns:
        locked = int(np.sum(result["friction.status"] == 2))
        if locked:
            items.append(
                f"self-locking at {locked} of {len(result)} positions (friction.status "
                "2): the consistent friction columns are empty there and the means and "
                "peaks with friction are over the other rows"
                + (" — here there are none" if locked == len(result) else "")
            )
    for sp in summary["singular_positions"]:
        items.append(
            f"singular position: {sp['group']} at {sp['angle']:.4f}° "
            f"(condition {sp['condition']:.3g})"
        )
    if summary["indeterminate_reactions"]:
        items.append("redundant constraints: reactions are the minimum-norm solution")
    blocks.append(_List(items))
    rows = [
        [n, f"{p['peak']:.5g}", f"{p['at']:.4g}", _fmt(p.get("peak_friction", math.nan), 0.0)]
        for n, p in summary["reaction_peaks"].items()
    ]
    blocks.append(
        _Table(
            [
                "joint",
                "peak |F| without friction (N)",
                "at driver coordinate (deg)",
                "peak |F| with friction (N)",
            ],
            rows,
            "Peak joint reactions",
        )
    )
    return blocks


def _flatten(d: Any, prefix: str = "") -> list[tuple[str, str]]:
    if isinstance(d, dict):
        out = []
        for k, v in d.items():
            out += _flatten(v, f"{prefix}.{k}" if prefix else str(k))
        return out
    if isinstance(d, (list, tuple)):
        if all(not isinstance(v, (dict, list, tuple)) for v in d) and len(d) <= 12:
            return [(prefix, ", ".join(_scalar(v) for v in d))]
        out = []
        for k, v in enumerate(d):
            out += _flatten(v, f"{prefix}[{k}]")
        return out
    return [(prefix, _scalar(d))]


def _scalar(v) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


# -- the report ----------------------------------------------------------------------
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
    from ..model import Model
    from . import plotting as pl

    if isinstance(source, Model):
        model = source
    else:
        from .loading import load

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
