"""Subcommands ``plot``, ``animate`` and ``report`` (registered through ``cli.EXTENSIONS``).

Importing this module imports neither matplotlib nor the analysis: the
commands load them when they run.
"""

from __future__ import annotations

import argparse
import functools
import gc
from pathlib import Path

from . import COLLECTOR

__all__ = ["WHAT", "MAX_DPI", "MAX_FPS", "MAX_FRAMES", "finite_number", "register"]

WHAT = (
    "drawing",
    "motion",
    "torque",
    "efficiency",
    "reactions",
    "polar",
    "velocity",
    "acceleration",
    "centres",
)

# The methods of methods.json behind each picture that has one (docs/methods.md): ``plot``
# writes methods.json with those of the pictures it draws, at the drawn position.
METHODS = {
    "centres": "instant_centres",
    "velocity": "vector_equations",
    "acceleration": "vector_equations",
}


# The largest resolution, frame rate and number of frames: a picture at 1,200 dpi
# is about 10,000 pixels a side (print quality; matplotlib refuses 65,536), a GIF
# counts its delays in hundredths of a second, and every frame of an animation is
# held in memory until it is written (about 0.3 MB each at 110 dpi).
MAX_DPI = 1200.0
MAX_FPS = 100.0
MAX_FRAMES = 10_000


def _fewer_collections(command):
    """``command`` run with the collector at :data:`~kinetostatics.cli.COLLECTOR`, its
    thresholds given back after it (a command may run inside a caller's process: tests,
    notebooks) — except for the process's own command (``args.program``, cli.main),
    which set them at its start and ends with them."""

    @functools.wraps(command)
    def run(args) -> int:
        before = gc.get_threshold()
        gc.set_threshold(*COLLECTOR)
        try:
            return command(args)
        finally:
            if not getattr(args, "program", False):
                gc.set_threshold(*before)

    return run


def _frames(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got '{text}'") from None
    if not 2 <= n <= MAX_FRAMES:
        raise argparse.ArgumentTypeError(f"must be from 2 to {MAX_FRAMES} frames, got {n}")
    return n


def _up_to(limit: float):
    """An argparse type: a number greater than 0 and at most ``limit``."""

    def positive(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got '{text}'") from None
        if not 0 < v <= limit:
            raise argparse.ArgumentTypeError(
                f"must be greater than 0 and at most {limit:g}, got {text}"
            )
        return v

    return positive


def finite_number(text: str) -> float:
    """An argparse type: a finite number (a driver coordinate)."""
    import math

    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got '{text}'") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got '{text}'")
    return v


def _labels(text: str) -> list[str]:
    return [s.strip() for s in text.split(",") if s.strip()]


def register(sub) -> None:
    p = sub.add_parser(
        "plot",
        help="pictures: drawing, motion diagram, torque, reactions, polar diagrams, polygons, "
        "instant centres",
        description="Draw the mechanism and its curves as image files in --out. Curves run over "
        "the whole cycle; the drawing, the polygons and the instant centres are at --position, "
        "whose vector equations and instant centres go to methods.json.",
    )
    p.add_argument("file", help="mechanism YAML file")
    p.add_argument("--out", default="plots", help="output folder (default: plots)")
    p.add_argument(
        "--what",
        nargs="+",
        choices=WHAT + ("all",),
        default=["all"],
        metavar="WHAT",
        help=f"pictures to draw: {', '.join(WHAT)} or all (default: all)",
    )
    p.add_argument(
        "--position",
        type=finite_number,
        default=None,
        help="driver coordinate of the drawing, the polygons and the instant centres, deg "
        "(mm for a prismatic driver); default: the first position of the analysis",
    )
    p.add_argument(
        "--forces",
        action="store_true",
        help="draw the loads to scale on the drawing (reactions, inertia, weights)",
    )
    p.add_argument(
        "--friction",
        action="store_true",
        help="forces and polar diagrams from the consistent friction solution",
    )
    p.add_argument(
        "--paths",
        nargs="*",
        default=None,
        metavar="LINK.POINT",
        help="points whose paths the drawing traces (default: the moving pins)",
    )
    p.add_argument(
        "--output",
        default=None,
        help="output of the motion diagram: a joint, a link or link.point "
        "(default: the output slider)",
    )
    p.add_argument(
        "--format", choices=("png", "svg", "pdf"), default="png", help="image format (default: png)"
    )
    p.add_argument("--dpi", type=_up_to(MAX_DPI), default=110.0, help="resolution (default: 110)")
    p.add_argument(
        "--driver",
        default=None,
        metavar="NAME",
        help="motion driver whose torque and efficiency are drawn (default: the first)",
    )
    p.add_argument(
        "--sheet",
        default=None,
        metavar="OUT.pdf|OUT.dxf",
        help="write only the 12-position drawing: every course position at a round scale "
        "on an A2 (or A1) sheet with a title block, true size, as PDF or DXF",
    )
    p.add_argument(
        "--working",
        default=None,
        metavar="LABEL",
        help="the course position drawn heavy on the --sheet (default: 1)",
    )
    _lang_option(p)
    p.set_defaults(func=_fewer_collections(_drawn_once(_plot)))

    p = sub.add_parser(
        "animate",
        help="animation of the cycle (GIF; MP4 if ffmpeg is installed)",
        description="Animate one cycle, one frame per position, equally spaced.",
    )
    p.add_argument("file", help="mechanism YAML file")
    p.add_argument("--out", required=True, help="output file, .gif (or .mp4 with ffmpeg)")
    p.add_argument(
        "--frames",
        type=_frames,
        default=120,
        help="number of frames over the cycle (default: 120)",
    )
    p.add_argument(
        "--fps", type=_up_to(MAX_FPS), default=20.0, help="frames per second (default: 20)"
    )
    p.add_argument("--forces", action="store_true", help="overlay the loads at one force scale")
    p.add_argument(
        "--friction", action="store_true", help="forces from the consistent friction solution"
    )
    p.add_argument(
        "--paths",
        nargs="*",
        default=None,
        metavar="LINK.POINT",
        help="points whose paths are traced (default: the moving pins)",
    )
    p.add_argument("--dpi", type=_up_to(MAX_DPI), default=110.0, help="resolution (default: 110)")
    _lang_option(p)
    p.set_defaults(func=_fewer_collections(_animate))

    p = sub.add_parser(
        "report",
        help="course-design report: Markdown, HTML and PDF with tables and pictures",
        description="Write report.md, report.html (self-contained) and/or report.pdf (A4), "
        "results.csv, summary.json and img/ to --out.",
    )
    p.add_argument("file", help="mechanism YAML file")
    p.add_argument("--out", default="report", help="output folder (default: report)")
    p.add_argument(
        "--polygons",
        type=_labels,
        default=None,
        metavar="LABELS",
        help="course positions for the polygons, comma-separated, e.g. 2,7,8' (default: 2,7, "
        "or the --positions)",
    )
    p.add_argument(
        "--positions",
        type=_labels,
        default=None,
        metavar="LABELS",
        help="the student's assigned course positions, comma-separated, e.g. 2,7 (numbered as "
        "the report prints them: 1 at analysis.start, then every 30° of crank travel; 1', 8' "
        "where a load switches): the tables at the positions, the loads drawn and the "
        "polygons only for these; the results, curves and diagrams over the cycle for all "
        "(default: all positions)",
    )
    p.add_argument("--dpi", type=_up_to(MAX_DPI), default=110.0, help="resolution (default: 110)")
    p.add_argument(
        "--format",
        nargs="+",
        choices=("md", "html", "pdf"),
        default=None,
        metavar="FORMAT",
        help="documents to write: md, html, pdf (default: md html)",
    )
    p.add_argument(
        "--pdf",
        action="store_true",
        help="also write report.pdf (A4; needs fpdf2: pip install 'kinetostatics[pdf]')",
    )
    _lang_option(p)
    p.set_defaults(func=_fewer_collections(_report))


def _lang_option(p) -> None:
    p.add_argument(
        "--lang",
        choices=("en", "zh"),
        default="en",
        help="language of the headings and labels: en or zh (Chinese; needs a CJK font: "
        "KINETOSTATICS_CJK_FONT, a system font, or pip install 'kinetostatics[zh]')",
    )


def _default_paths(model) -> list[str]:
    pins = [
        f"{a.link}.{a.point}"
        for j in model.joints
        if j.pin and model.ground.name not in j.links
        for a in j.anchors()
        if a.at_joint and a.link == j.links[1]
    ]
    return list(dict.fromkeys(pins))


def _sheet(args, model) -> int:
    """``plot --sheet OUT``: the 12-position drawing, its limit positions from the output
    members' strokes (a stage: computed here, passed to the picture)."""
    from ..base.files import write_file
    from ..kinematics.events import output_strokes
    from ..outputs import plotting as pl
    from ..outputs.plotting import sheet

    out = Path(args.sheet)
    kind = out.suffix.lower().lstrip(".")
    if kind not in ("pdf", "dxf"):
        raise pl.PictureError(f"--sheet {args.sheet}: the sheet is written as .pdf or .dxf")
    result = pl.analyze_for_pictures(model, course=True, events=False)
    strokes = output_strokes(result)
    angles = [lp["angle"] for o in strokes.values() for lp in o["limit_positions"].values()]
    if angles:  # the limit positions as rows of their own
        result = pl.analyze_for_pictures(model, course=True, events=False, positions=angles)
    paths = sheet.output_paths(result, [o["link"] for o in strokes.values()])
    if args.paths is not None:
        paths = args.paths
    layout = sheet.sheet_layout(
        result, working=args.working, limits=sheet.limit_rows(result, angles), paths=paths
    )
    if kind == "dxf":
        write_file(
            out,
            f"--sheet {args.sheet}",
            lambda tmp: sheet.export_sheet_dxf(result, layout, tmp, lang=args.lang),
        )
    else:
        fig = sheet.sheet_figure(result, layout, lang=args.lang)
        write_file(out, f"--sheet {args.sheet}", lambda tmp: fig.savefig(tmp, format="pdf"))
    print(f"{model.name}: {out} ({layout.size}, scale {layout.scale_text()})")
    return 0


def _drawn_once(command):
    """``command`` run inside :func:`..outputs.plotting.crop.drawn_once`: each PNG laid out
    when it is saved, from its one drawing."""

    @functools.wraps(command)
    def run(args) -> int:
        from ..outputs.plotting.crop import drawn_once

        with drawn_once():
            return command(args)

    return run


def _plot(args) -> int:
    from ..outputs import plotting as pl
    from ..outputs.loading import load
    from ..outputs.plotting.crop import save_png

    model = load(args.file)
    if args.lang == "zh":
        from ..outputs.fonts import cjk_font

        cjk_font()  # a clear message before any work when there is no CJK font
    if args.sheet is not None:
        return _sheet(args, model)
    if args.working is not None:
        raise pl.PictureError("--working: the heavy position of the --sheet; give --sheet OUT")
    what = list(WHAT) if "all" in args.what else list(dict.fromkeys(args.what))
    positions = [args.position] if args.position is not None else []
    result = pl.analyze_for_pictures(model, positions=positions, course=True, events=True)
    row = pl.row_at(result, args.position)
    if args.driver is not None:
        names = [d.name for d in result.system.motion_drivers]
        if args.driver not in names:
            from ..errors import did_you_mean

            raise pl.PictureError(
                f"--driver {args.driver}: no motion driver of that name "
                f"(have {', '.join(names)}){did_you_mean(args.driver, names)}"
            )
    lang = args.lang
    out = Path(args.out)
    from ..base.files import make_folder, write_file

    make_folder(out, f"--out {args.out}")
    paths = _default_paths(model) if args.paths is None else args.paths
    cycle = None
    if "torque" in what or ("efficiency" in what and model.has_friction):
        from ..dynamics.stages import cycle_stage  # the curves' cycle means

        cycle = cycle_stage(
            result,
            outputs=False,
            self_locking=False,
            flywheel=False,
            drive=False,
            efficiency="efficiency" in what,
        )
    written = []
    label = _label_of(result, row, args.position)
    methods = _plot_methods(result, row, label, what)
    if methods is not None:
        from ..base.files import json_text

        text = json_text(methods, ensure_ascii=False)
        path = out / "methods.json"
        write_file(path, f"--out {args.out}", lambda tmp: tmp.write_text(text, "utf-8"))
    for name in what:
        if name == "centres":
            from ..outputs.plotting.centres import centres_figure

            entry = methods["instant_centres"][label]
            fig = centres_figure(result, entry, dpi=args.dpi, lang=lang)
        elif name == "drawing":
            fig = pl.draw_mechanism(
                result,
                row=row,
                forces=args.forces,
                friction=args.friction,
                paths=paths,
                dpi=args.dpi,
                lang=lang,
            )
        elif name == "motion":
            fig = pl.motion_diagram(result, args.output, dpi=args.dpi, lang=lang)
        elif name == "torque":
            fig = pl.torque_curves(result, args.driver, dpi=args.dpi, lang=lang, cycle=cycle)
        elif name == "efficiency":
            if not model.has_friction:
                print(f"{model.name}: no friction in the file: no efficiency curve")
                continue
            fig = pl.efficiency_curve(result, args.driver, dpi=args.dpi, lang=lang, cycle=cycle)
        elif name == "reactions":
            fig = pl.reaction_curves(result, friction=model.has_friction, dpi=args.dpi, lang=lang)
        elif name == "polar":
            fig = pl.polar_diagrams(result, friction=args.friction, dpi=args.dpi, lang=lang)
        else:
            fig = pl.polygon_figure(result, name, row=row, dpi=args.dpi, lang=lang)
        path = out / f"{name}.{args.format}"
        if args.format == "png":  # drawn once, laid out by cropping the drawing
            save = lambda tmp, fig=fig: save_png(fig, tmp, args.dpi)  # noqa: E731
        else:
            save = lambda tmp, fig=fig: fig.savefig(tmp, dpi=args.dpi, format=args.format)  # noqa: E731
        write_file(path, f"--out {args.out}", save)
        written.append(path)
    if methods is not None:
        written.append(out / "methods.json")
    print(f"{model.name}: {', '.join(str(p) for p in written)}")
    return 0


def _label_of(result, row: int, position: float | None) -> str:
    """The drawn position's label in methods.json: its course position (``7``, ``8′``),
    else the driver coordinate as given (``--position 47.5`` → ``47.5``), or ``start``."""
    from ..outputs import plotting as pl

    for label, k in pl.course_positions(result):
        if k == row:
            return label
    return "start" if position is None else f"{position:g}"


def _plot_methods(result, row: int, label: str, what: list[str]) -> dict | None:
    """methods.json of the pictures drawn (the stage ``report`` runs, asked only for their
    methods, at the drawn row); None when no picture drawn has a method."""
    parts = sorted({METHODS[name] for name in what if name in METHODS})
    if not parts:
        return None
    from ..methods.stage import methods_stage

    return methods_stage(result, [(label, row)], parts=parts)


def _animate(args) -> int:
    from ..outputs import plotting as pl
    from ..outputs.loading import load

    out = Path(args.out)
    if out.suffix.lower() not in (".gif", ".mp4"):
        raise pl.PictureError(f"--out {out}: write the animation as .gif (or .mp4 with ffmpeg)")
    model = load(args.file)
    result = pl.analyze_for_pictures(model, frames=args.frames, events=False)
    paths = _default_paths(model) if args.paths is None else args.paths
    from ..errors import output_error

    try:
        pl.animate(
            result,
            out,
            forces=args.forces,
            friction=args.friction,
            paths=paths,
            fps=args.fps,
            dpi=args.dpi,
            lang=args.lang,
        )
    except OSError as exc:
        raise output_error(exc, f"--out {args.out}") from None
    print(f"{model.name}: {len(result)} frames -> {out}")
    return 0


def _report(args) -> int:
    from ..dynamics.stages import report_stage
    from ..methods.stage import methods_stage
    from ..outputs.report import write_report
    from ..sizing.stage import sizing_stage

    formats = list(args.format or ["md", "html"])
    if args.pdf and "pdf" not in formats:
        formats.append("pdf")
    paths = write_report(
        args.file,
        args.out,
        polygons=args.polygons,
        positions=args.positions,
        dpi=args.dpi,
        formats=formats,
        lang=args.lang,
        what=f"--out {args.out}",
        cycle=report_stage,
        methods=methods_stage,
        sizing=sizing_stage,
    )
    docs = [str(paths[k]) for k in ("markdown", "html", "pdf") if k in paths]
    data = ", ".join(str(paths[k]) for k in ("csv", "summary", "methods", "sizing") if k in paths)
    print(f"report: {', '.join(docs)} (data: {data})")
    return 0
