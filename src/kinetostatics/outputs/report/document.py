"""The whole report: analyse, draw the pictures, assemble the sections and write
``report.md``, ``report.html`` and/or ``report.pdf``, ``results.csv`` and ``summary.json``."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ...base.files import json_text, make_folder, write_file
from ...model import Model
from .. import plotting as pl
from ..fonts import cjk_font
from ..labels import link_numbers, member, numbered
from ..lang import check_lang, tr
from ..loading import load
from ..plotting.crop import drawn_once, save_png
from ..summary import summarize
from .blocks import ReportError, _Heading, _Image, _Para, _to_html, _to_markdown
from .data import _data_blocks, _structure_blocks
from .drive import drive_blocks
from .elements import element_blocks
from .flywheel import flywheel_blocks
from .forces import polygon_blocks
from .gears import gear_blocks
from .methods import cam_blocks, centres_blocks, lever_blocks
from .pdf import pdf_module, write_pdf
from .results import _summary_blocks, balancing, length_unit, report_tables
from .sizing import sizing_blocks
from .vectors import vector_blocks

FORMATS = ("md", "html", "pdf")


def _rows(result, course):
    if course:
        return course
    # no crank cycle: 12 rows spread over the run
    order = np.argsort(result["travel"], kind="stable")
    picks = np.unique(np.linspace(0, len(order) - 1, min(12, len(order))).round().astype(int))
    return [(str(n + 1), int(order[k])) for n, k in enumerate(picks)]


def _upper_first(text: str) -> str:
    """A caption's first letter in upper case ("Balancing torque M_b of …")."""
    return text[:1].upper() + text[1:]


def _have(labels: list[str]) -> str:
    return ", ".join(labels) or "none: not whole turns of a crank"


def _position_labels(positions, labels: list[str]) -> list[str] | None:
    """The student's positions (``--positions``) as the report labels them, in the order of
    travel; None for all."""
    if positions is None:
        return None
    chosen = {p.replace("'", "′") for p in positions}
    for p in sorted(chosen):
        if p not in labels:
            raise ReportError(f"--positions: no course position '{p}' (have {_have(labels)})")
    if not chosen:
        raise ReportError(f"--positions: no position given (have {_have(labels)})")
    return [lab for lab in labels if lab in chosen]


def _polygon_labels(polygons, labels: list[str], turns: int, chosen=None) -> list[str]:
    if polygons is None:
        if chosen is not None:  # the student's positions: each with its polygons
            return chosen
        default = ("2", "7") if turns <= 1 else ("2/1", "7/1")
        return [p for p in default if p in labels] or labels[:1]
    polygons = [p.replace("'", "′") for p in polygons]
    for p in polygons:
        if p not in labels:
            raise ReportError(f"no course position '{p}' for polygons (have {_have(labels)})")
        if chosen is not None and p not in chosen:
            raise ReportError(
                f"--polygons: position '{p}' is not among --positions ({', '.join(chosen)})"
            )
    return polygons


@drawn_once()  # each picture drawn once, laid out by cropping the drawing (plotting/crop.py)
def write_report(  # noqa: PLR0913  the report's public keywords (docs/pictures.md, the CLI)
    source,
    out: str | Path,
    *,
    polygons: Sequence[str] | None = None,
    positions: Sequence[str] | None = None,
    dpi: float = 110,
    formats: Sequence[str] = ("md", "html"),
    lang: str = "en",
    what: str | None = None,
    cycle=None,
    methods=None,
    sizing=None,
) -> dict[str, Path]:
    """Analyse ``source`` (a YAML path or a Model) and write the report to ``out``.

    ``polygons``: course-position labels (``"2"``, ``"7"``, ``"1′"``; ``"7/2"`` for
    position 7 of the second turn of a multi-turn sweep) at which to draw velocity and
    acceleration polygons; default positions 2 and 7 (the ones a slotting-machine course
    design works by hand), or position 1 where there are no such positions.  ``positions``:
    the course positions (labels as ``polygons``) of the detailed chapters — the tables at
    the course-design positions, the drawings of the loads and the polygons, the springs'
    table — default all; the cycle's results, curves and diagrams are always over the
    whole cycle, and ``polygons`` then defaults to, and must be among, these.  ``formats``:
    any of ``md`` (``report.md``, images in ``img/``), ``html`` (``report.html``, images
    embedded) and ``pdf`` (``report.pdf``, A4, needs fpdf2: ``pip install
    'kinetostatics[pdf]'``).  ``lang``: ``en`` or ``zh`` (Chinese headings and labels;
    needs a font with Chinese glyphs: ``KINETOSTATICS_CJK_FONT``, a system font, or ``pip
    install 'kinetostatics[zh]'``).  Returns the paths written (``markdown``,
    ``html``, ``pdf`` as asked, ``csv``, ``summary``).  Each file is written whole
    (:func:`~kinetostatics.base.files.write_file`); an ``out`` that is a file, a
    full disk or a read-only folder is an :class:`~kinetostatics.errors.OutputError`
    whose line starts with ``what`` (default: ``out``).  ``cycle``: the cycle's stage,
    called on the report's result (``cycle(result)`` → a
    :class:`~kinetostatics.dynamics.stages.Cycle`; ``kinetostatics report`` passes
    :func:`~kinetostatics.dynamics.stages.report_stage`): the cycle means, the output
    strokes, the cycle efficiency, the flywheel and the drive chapters come from its
    record; without it the report holds what the rows hold (this layer solves nothing).
    ``methods``: the graded methods' stage, called as ``methods(result, rows)`` with the
    ``(label, row)`` positions of the detailed chapters (``kinetostatics report`` passes
    :func:`~kinetostatics.methods.stage.methods_stage`): its dict is written to
    ``methods.json`` (returned as ``methods``), and the chapters of the balancing moment
    three ways, the instant centres, the gears and the cam's design come from it.
    ``sizing``: the sizing stage, called as ``sizing(result)`` (``kinetostatics report``
    passes :func:`~kinetostatics.sizing.stage.sizing_stage`; None for a file without
    sizing data): its record is written to ``sizing.json`` (returned as ``sizing``) and
    is the last chapter's (docs/sizing.md).
    """
    formats = list(dict.fromkeys(formats))
    for f in formats:
        if f not in FORMATS:
            raise ReportError(f"unknown report format '{f}' (have {', '.join(FORMATS)})")
    check_lang(lang)
    if lang == "zh":
        cjk_font()  # fail before any work when there is no font
    if "pdf" in formats:
        pdf_module()  # likewise when fpdf2 is missing
    model = source if isinstance(source, Model) else load(source)
    if not model.drivers or not all(d.motion is not None for d in model.drivers):
        raise ReportError(
            f"{model.name}: the report analyses a cycle driven by motion drivers; "
            "a file with effort drivers is simulated (kinetostatics simulate)"
        )
    out = Path(out)
    what = str(out) if what is None else what
    img = out / "img"
    make_folder(out, what)
    make_folder(img, what)
    result = pl.analyze_for_pictures(model, course=True, events=True)
    system = result.system
    course = pl.course_positions(result)
    n_turns = pl.turns(result)
    labels = [lab for lab, _ in course]
    chosen = _position_labels(positions, labels)
    polygons = _polygon_labels(polygons, labels, n_turns, chosen)
    all_rows = _rows(result, course)
    rows = all_rows if chosen is None else [r for r in all_rows if r[0] in chosen]
    csv_path, summary_path = out / "results.csv", out / "summary.json"
    write_file(csv_path, what, result.to_csv)
    records = cycle(result) if cycle is not None else None
    dsg = records.flywheel if records is not None else None
    summary = summarize(result, records)
    text = json_text(summary, default=float, ensure_ascii=False)
    write_file(summary_path, what, lambda p: p.write_text(text, encoding="utf-8"))
    graded = methods(result, rows) if methods is not None else None
    if graded is not None:
        methods_text = json_text(graded, ensure_ascii=False)
        write_file(out / "methods.json", what, lambda p: p.write_text(methods_text, "utf-8"))
    sized = sizing(result) if sizing is not None else None
    if sized is not None:
        sizing_text = json_text(sized.to_json(), ensure_ascii=False)
        write_file(out / "sizing.json", what, lambda p: p.write_text(sizing_text, "utf-8"))
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731

    def image(fig, name: str, caption: str, true_scale: bool = False) -> _Image:
        path = img / f"{name}.png"
        write_file(path, what, lambda p: save_png(fig, p, dpi))
        w, h = fig.get_size_inches() * 25.4
        return _Image(path, caption, float(w), float(h), true_scale)

    moving_pins = [
        f"{a.link}.{a.point}"
        for j in model.joints
        if j.pin and model.ground.name not in j.links
        for a in j.anchors()
        if a.at_joint and a.link == j.links[1]
    ]
    out_m = pl.output_motion(result)
    shown = out_m["name"]  # the member that moves, not the pair a slide is measured at
    if out_m["kind"] == "slide":
        moved = next(k for k in model.joint(shown).links if k != model.ground.name)
        shown = member(moved, link_numbers(system), model, lang)
        shown = f"{shown} {moved}" if numbered(model) else moved
    paths = list(dict.fromkeys(moving_pins))
    first = all_rows[0][1]
    title = T("Course-design report: {name}", name=model.name)
    d0 = system.motion_drivers[0]
    blocks: list = [
        _Heading(1, title),
        _Para(
            T(
                "Kinetostatic analysis by `kinetostatics` (exact positions, velocities "
                "and accelerations; d'Alembert inertia loads; Newton–Euler reactions; "
                "friction by the approximate and the consistent solution). Conventions: "
                "x right, y up, angles and moments counter-clockwise positive; the total "
                "reaction F_Rij of a joint is the force of link i on link j."
            )
        ),
        _Para(
            T(
                "Position angle: every position is named by the angle φ of the first driver "
                "({driver}), measured counter-clockwise from +x in [0, 360)°; link angles θ "
                "likewise. travel is the rotation from position 1 in the sense of motion. "
                "Course-design positions 1…12 are every 30° of travel from the analysis start "
                "(φ₁ = {start}°); k′ are the positions where a load switches (start and end of "
                "cutting), after position k.",
                driver=d0.name,
                start=f"{np.degrees(model.analysis.start) % 360.0:.4g}",
            )
            + (
                T(
                    " The analysis runs {n} turns of {driver}: k/t is position k of turn t.",
                    n=n_turns,
                    driver=d0.name,
                )
                if n_turns > 1
                else ""
            )
        ),
        _Para(
            T(
                "Units: lengths of points and strokes in the file's unit ({unit}); velocities "
                "in m/s, accelerations in m/s², forces in N, moments in N·m, angles in deg, "
                "angular velocities in rad/s.",
                unit=length_unit(model)[0],
            )
        ),
    ]
    blocks += _data_blocks(model, system, lang)
    blocks += _structure_blocks(system, lang)
    blocks += _summary_blocks(result, summary, lang)
    blocks.append(_Heading(2, T("4. The mechanism")))
    blocks.append(
        image(
            pl.draw_mechanism(result, row=first, paths=paths, dpi=dpi, lang=lang),
            "mechanism",
            T(
                "The mechanism at position {pos} with the paths of its moving pins "
                "(to the scale μ_l stated on it).",
                pos=all_rows[0][0],
            ),
            True,
        )
    )
    blocks.append(_Heading(2, T("5. Kinematics and forces at the course-design positions")))
    blocks.append(
        _Para(
            T(
                "Rows of `results.csv` (the column CSV row) at the positions {labels}; values "
                "to 5 significant digits (0: below 1e-9 of the largest value of its unit in the "
                "table, round-off), column names as in the CSV; |v|, |a|, |F| are the "
                "magnitudes of the components before them. Wide tables are split into groups "
                "of columns, each repeating the position, its CSV row and its angle.",
                labels=", ".join(lab for lab, _ in rows),
            )
            + (
                ""
                if chosen is None
                else T(
                    " These chapters are at the positions assigned ({labels}); the results, "
                    "curves and diagrams over the cycle cover all positions.",
                    labels=", ".join(chosen),
                )
            )
        )
    )
    blocks += report_tables(result, rows, lang)
    blocks.append(_Heading(2, T("6. Curves over the cycle")))
    blocks.append(
        image(
            pl.motion_diagram(result, dpi=dpi, lang=lang),
            "motion",
            T(
                "Motion diagram of the output ({name}): position, velocity, acceleration; "
                "the shaded zone is where the process load acts.",
                name=shown,
            ),
        )
    )
    for d in system.motion_drivers:
        blocks.append(
            image(
                pl.torque_curves(result, d.name, dpi=dpi, lang=lang, cycle=records),
                "torque" if d is d0 else f"torque_{d.name}",
                T(
                    "{effort} of {driver} without friction, with the approximate and with "
                    "the consistent friction solution."
                    if model.has_friction
                    else "{effort} of {driver} (no joint has friction).",
                    effort=_upper_first(T(balancing(model, d.name))),
                    driver=d.name,
                ),
            )
        )
        if f"{d.name}.efficiency" in result.columns:
            blocks.append(
                image(
                    pl.efficiency_curve(result, d.name, dpi=dpi, lang=lang, cycle=records),
                    "efficiency" if d is d0 else f"efficiency_{d.name}",
                    T("Instantaneous and cycle efficiency of the drive {driver}.", driver=d.name),
                )
            )
    blocks.append(
        image(
            pl.reaction_curves(result, friction=model.has_friction, dpi=dpi, lang=lang),
            "reactions",
            T("Magnitudes of the total reactions F_R of the joints."),
        )
    )
    blocks.append(_Heading(2, T("7. Velocity and acceleration polygons")))
    blocks.append(
        _Para(
            T(
                "Drawn from the exact results to the stated scales μ_v and μ_a (true "
                "scale when printed at 100 %): p is the pole, lower-case "
                "letters the points (a2, a3: the coincident points of links 2 and 3), n "
                "and k the ends of normal and Coriolis components."
            )
        )
    )
    at = dict(course) if course else dict(rows)
    for lab in polygons:
        k = at[lab]
        tag = lab.replace("′", "p").replace("/", "_t")
        blocks.append(
            image(
                pl.draw_mechanism(result, row=k, forces=True, dpi=dpi, lang=lang),
                f"forces_{tag}",
                T(
                    "Position {pos}: the loads drawn to scale (total reactions F_R of link i "
                    "on link j at the joints, inertia forces F_I and inertia couples M_I, "
                    "weights G, the process load and the {effort}).",
                    pos=lab,
                    effort=T(balancing(model, d0.name)),
                ),
                True,
            )
        )
        for kind in ("velocity", "acceleration"):
            blocks.append(
                image(
                    pl.polygon_figure(result, kind, row=k, dpi=dpi, lang=lang),
                    f"{kind}_{tag}",
                    T(f"{kind.capitalize()} polygon at position {{pos}}.", pos=lab),
                    True,
                )
            )
    blocks.append(_Heading(2, T("8. Polar diagrams of the joint loads")))
    blocks.append(
        image(
            pl.polar_diagrams(result, dpi=dpi, lang=lang),
            "polar",
            T(
                "Reaction of each revolute joint in the frame of the link that receives "
                "it, over the cycle (numbers: course positions)."
            ),
        )
    )
    section = 9
    if model.elements:
        blocks += element_blocks(result, rows, section, lang)
        section += 1
    if dsg is not None:
        blocks += flywheel_blocks(summary["flywheel"], dsg, result, all_rows, image, lang, section)
        section += 1
    if "drive" in summary:
        blocks += drive_blocks(summary["drive"], result, image, lang, section)
        section += 1
    g = graded or {}
    if "balancing_moment" in g:
        blocks += lever_blocks(g["balancing_moment"], lang, section)
        section += 1
    if g.get("instant_centres"):
        # drawn where the polygons are (the positions asked, or 2 and 7), tabled at each
        blocks += centres_blocks(
            g["instant_centres"], result, image, lang, section, dpi, drawn=polygons
        )
        section += 1
    vectors = vector_blocks(g.get("vector_equations") or {}, lang, section)
    blocks += vectors
    section += bool(vectors)
    gears = gear_blocks(g["gears"], lang, section) if "gears" in g else []
    blocks += gears
    section += bool(gears)
    cams = cam_blocks(g.get("cam_design") or [], image, lang, section, dpi)
    blocks += cams
    section += bool(cams)
    # last, so that the chapters before keep their numbers; drawn where the polygons are
    polys = polygon_blocks(g, result, image, lang, section, drawn=polygons)
    blocks += polys
    section += bool(polys)
    if sized is not None:  # after every other chapter: theirs keep their numbers
        blocks += sizing_blocks(sized, image, lang, section, dpi)
    written: dict[str, Path] = {}
    if "md" in formats:
        written["markdown"] = out / "report.md"
        text = _to_markdown(blocks, out)
        write_file(written["markdown"], what, lambda p: p.write_text(text, encoding="utf-8"))
    if "html" in formats:
        written["html"] = out / "report.html"
        text = _to_html(blocks, title, lang)
        write_file(written["html"], what, lambda p: p.write_text(text, encoding="utf-8"))
    if "pdf" in formats:
        written["pdf"] = out / "report.pdf"
        write_file(written["pdf"], what, lambda p: write_pdf(blocks, p, title, lang))
    files = {"csv": csv_path, "summary": summary_path}
    files |= {"methods": out / "methods.json"} if graded is not None else {}
    return written | files | ({"sizing": out / "sizing.json"} if sized is not None else {})
