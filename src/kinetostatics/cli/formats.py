"""Subcommands ``schema`` (the JSON Schema of a mechanism file) and ``export`` (a DXF or
SVG drawing of the mechanism at one position).

Importing this module imports neither matplotlib, ezdxf nor the analysis.
"""

from __future__ import annotations

import sys
from pathlib import Path

__all__ = ["register"]


def _schema(args) -> int:
    from ..io.schema import schema_text

    text = schema_text()
    if args.out:
        from ..base.files import write_whole
        from ..errors import output_error

        try:
            write_whole(Path(args.out), lambda path: path.write_text(text, encoding="utf-8"))
        except OSError as exc:
            raise output_error(exc, f"--out {args.out}") from None
        print(f"JSON Schema of a mechanism file -> {args.out}")
    else:
        sys.stdout.write(text)
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "schema",
        help="the JSON Schema of a mechanism YAML file (for editors; docs/yaml.md)",
        description="Print the JSON Schema of a mechanism file, made from the loader's own "
        "key tables. Point an editor at it with the first line "
        "'# yaml-language-server: $schema=mechanism.schema.json'.",
    )
    p.add_argument("--out", help="write it to this file instead of printing it")
    p.set_defaults(func=_schema)
