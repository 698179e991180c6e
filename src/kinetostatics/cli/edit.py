"""Subcommand ``edit``: the mechanism file in a live editor in the browser (docs/editor.md).

``kinetostatics edit FILE [--port N] [--no-browser]`` serves the page on 127.0.0.1 (a free
port unless ``--port``), prints its address (with the token that keeps other local users'
pages out), opens it in the browser and serves until Ctrl-C (one line, exit 130).
Importing this module imports neither numpy nor the analysis.
"""

from __future__ import annotations

import sys
from pathlib import Path

__all__ = ["register"]


def _edit(args) -> int:
    from ..editor.server import make_server
    from ..errors import OutputError
    from ..io import read_text

    if not 0 <= args.port <= 65535:
        raise OutputError(f"--port {args.port}: a port is 0 (a free one) to 65535")
    path = Path(args.file)
    read_text(path)  # a missing, unreadable or oversized file: its one line, as check's
    try:
        server = make_server(path, args.port)
    except OSError as exc:
        raise OutputError(
            f"--port {args.port}: cannot listen on 127.0.0.1 ({exc.strerror})"
        ) from None
    with server:
        print(f"kinetostatics edit: {path} at {server.url} (Ctrl-C ends)", flush=True)
        if not args.no_browser:
            import webbrowser

            if not webbrowser.open(server.url):
                print("kinetostatics: no browser found: open the address above", file=sys.stderr)
        server.serve_forever(poll_interval=0.2)
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "edit",
        help="edit a mechanism file in the browser: the drawing, forces and curves follow "
        "each change",
        description="Serve a live editor of FILE on 127.0.0.1 (only this machine; a random "
        "token in the address) until Ctrl-C. The page checks the text as you type, draws the "
        "mechanism, its loads and curves from the same analysis as `run`, saves the file "
        "whole and downloads results.csv, summary.json and the PDF report.",
    )
    p.add_argument("file", help="mechanism YAML file")
    p.add_argument(
        "--port", type=int, default=0, help="the port on 127.0.0.1 (default 0: a free one)"
    )
    p.add_argument(
        "--no-browser", action="store_true", help="print the address, do not open a browser"
    )
    p.set_defaults(func=_edit)
