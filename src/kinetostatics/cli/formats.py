"""Subcommands ``schema`` (the JSON Schema of a mechanism file) and ``export`` (a DXF or
SVG drawing of the mechanism at one position).

Importing this module imports neither matplotlib, ezdxf nor the analysis.
"""

from __future__ import annotations

import sys
from pathlib import Path

from .pictures import finite_number

__all__ = ["register"]


def _schema(args) -> int:
    from ..io.schema import schema_text

    text = schema_text()
    if args.out:
        from ..base.files import write_file

        write_file(
            Path(args.out),
            f"--out {args.out}",
            lambda path: path.write_text(text, encoding="utf-8"),
        )
        print(f"JSON Schema of a mechanism file -> {args.out}")
    else:
        sys.stdout.write(text)
    return 0


def _export(args) -> int:
    from ..outputs import plotting as pl
    from ..outputs.loading import load
    from ..outputs.plotting.export import export_dxf, export_svg

    model = load(args.file)
    # the row at --at is analysed exactly; beyond the reach of the linkage the analysis
    # says so, with the reachable range
    positions = [args.at] if args.at is not None else []
    result = pl.analyze_for_pictures(model, positions=positions, events=False)
    row = pl.row_at(result, args.at)
    out = Path(args.out) if args.out else Path(f"{Path(args.file).stem}.{args.format}")
    write = export_dxf if args.format == "dxf" else export_svg
    from ..base.files import write_file

    write_file(
        out,
        f"--out {out}",
        lambda path: write(result, row, path, forces=args.forces, friction=args.friction),
    )
    from ..errors import printable

    name = "angle" if "angle" in result.columns else "stroke"
    value = result[name][row] * (1.0 if name == "angle" else 1e3)
    print(
        f"{printable(model.name)}: {name} {value:g} {'deg' if name == 'angle' else 'mm'} -> {out}"
    )
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "export",
        help="the mechanism at one position as DXF (CAD) or SVG",
        description="Draw the mechanism at one position: links, joints, guides, points and, "
        "with --forces, the loads. DXF (pip install 'kinetostatics[dxf]') is in the file's "
        "length unit, one layer per kind; SVG is the picture of 'plot --what drawing'.",
    )
    p.add_argument("file", help="mechanism YAML file")
    p.add_argument(
        "--at",
        type=finite_number,
        help="driver coordinate in deg (mm for a prismatic driver); "
        "default: the first position of the analysis",
    )
    p.add_argument("--format", choices=("dxf", "svg"), default="dxf", help="default: dxf")
    p.add_argument("--forces", action="store_true", help="draw the loads at that position")
    p.add_argument(
        "--friction", action="store_true", help="the loads with friction (with --forces)"
    )
    p.add_argument("--out", help="the file to write (default: FILE's name .dxf or .svg)")
    p.set_defaults(func=_export)

    p = sub.add_parser(
        "schema",
        help="the JSON Schema of a mechanism YAML file (for editors; docs/yaml.md)",
        description="Print the JSON Schema of a mechanism file, made from the loader's own "
        "key tables. Point an editor at it with the first line "
        "'# yaml-language-server: $schema=mechanism.schema.json'.",
    )
    p.add_argument("--out", help="write it to this file instead of printing it")
    p.set_defaults(func=_schema)
