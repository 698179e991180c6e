"""Subcommand ``init``: a course-design template written as a mechanism file.

``kinetostatics init --list`` lists the templates; ``kinetostatics init TEMPLATE
[--data ROW] --out FILE`` writes one with the data of a row of its table
(docs/templates.md).  Importing this module imports neither numpy nor the analysis.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["register"]


def _init(args) -> int:
    from ..io.templates import TemplateError, load_template, render, templates

    if args.list:
        for t in templates():
            print(f"{t.name:<12} {t.title} ({t.zh}); rows {', '.join(t.rows)}")
            print(f"{'':<12} {t.description}")
        return 0
    if args.template is None or args.out is None:
        raise TemplateError(
            "init: name a template and --out FILE (kinetostatics init TEMPLATE --out FILE), "
            "or list them with kinetostatics init --list"
        )
    template = load_template(args.template)
    text = render(template, args.data)
    out = Path(args.out)
    from ..errors import OutputError

    if out.exists() and not out.is_dir():
        raise OutputError(f"--out {args.out}: the file exists; init does not overwrite it")
    from ..base.files import write_file

    write_file(out, f"--out {args.out}", lambda path: path.write_text(text, encoding="utf-8"))
    key = template.row(args.data)
    print(f"{template.zh} {template.title}, row {key} -> {out}")
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "init",
        help="write a course-design template (slotting, shaper, press, ...) as a mechanism file",
    )
    p.add_argument(
        "template", nargs="?", help="the template's name, English or Chinese (see --list)"
    )
    p.add_argument("--list", action="store_true", help="list the templates and their rows")
    p.add_argument(
        "--data", metavar="ROW", help="the row of the design-data table (I, II, ...; default I)"
    )
    p.add_argument("--out", metavar="FILE", help="the mechanism file to write (not overwritten)")
    p.set_defaults(func=_init)
