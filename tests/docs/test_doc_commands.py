"""Every ``kinetostatics …`` command that README.md and docs/*.md show runs as written.

The commands are read from the fenced shell blocks (``sh``, ``bash``, ``shell``,
``console`` and unlabelled ones) and from README's inline code; a synopsis (``FILE``,
``DIR``, ``[--option]``, ``…``) is a pattern, not a command, and is left out.  Each page's
commands run in order in one temporary folder holding ``mechanisms/`` and the example
inputs the pages name (``my_linkage.yaml``, ``class/``), through ``cli.main`` as the
shell would call it; each must exit 0 and leave the output its ``--out`` names.  The
long ones (a batch, an optimisation, a simulation, a report, an animation, and what
reads their output) run in the slow run.
"""

from __future__ import annotations

import re
import shlex
import shutil
from pathlib import Path

import pytest

from kinetostatics.cli import main

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SHELL = {"", "sh", "bash", "shell", "console"}
FENCE = re.compile(
    r"^(?P<indent> *)```(?P<lang>[\w-]*)[^\n]*\n(?P<body>.*?)^(?P=indent)```", re.S | re.M
)
INLINE = re.compile(r"`(kinetostatics \w+ mechanisms/[^`]+)`")
SYNOPSIS = re.compile(r"\b[A-Z]{3,}\b|[\[…]|\.\.\.")
SLOW = {"batch", "optimize", "simulate", "report", "animate", "best", "sensitivity"}


def commands(page: Path) -> list[list[str]]:
    """The page's commands (argument lists, the program's name first) in the order they
    appear, without prompts or comments."""
    text = page.read_text(encoding="utf-8")
    found: list[tuple[int, str]] = []
    for m in FENCE.finditer(text):
        if m.group("lang") not in SHELL:
            continue
        body = re.sub(r"\\\n\s*", " ", m.group("body"))
        for k, line in enumerate(body.splitlines()):
            for part in line.strip().removeprefix("$ ").split("&&"):
                if part.strip().startswith("kinetostatics "):
                    found.append((m.start() + k, part.strip()))
    if page.name == "README.md":  # the table of shipped examples
        found += [(m.start(), m.group(1)) for m in INLINE.finditer(text)]
    found.sort(key=lambda f: f[0])
    argvs = [shlex.split(c, comments=True) for _, c in found]
    return [a for a in argvs if not SYNOPSIS.search(" ".join(a))]


def _cases():
    for page in PAGES:
        cmds = commands(page)
        slow = any(c[1] in SLOW for c in cmds)
        if cmds:
            marks = [pytest.mark.slow] if slow else []
            yield pytest.param(page, cmds, id=str(page.relative_to(ROOT)), marks=marks)
    for page in PAGES:  # the quick commands of a page with slow ones still run by default
        cmds = commands(page)
        quick = [c for c in cmds if c[1] not in SLOW]
        if quick and len(quick) < len(cmds):
            yield pytest.param(page, quick, id=f"{page.relative_to(ROOT)}-quick")


def _folder(tmp_path: Path) -> Path:
    (tmp_path / "mechanisms").symlink_to(ROOT / "mechanisms")
    shutil.copy(ROOT / "mechanisms" / "slider_crank.yaml", tmp_path / "my_linkage.yaml")
    (tmp_path / "class").mkdir()
    for name in ("slider_crank.yaml", "inverted_slider_crank.yaml"):
        shutil.copy(ROOT / "mechanisms" / name, tmp_path / "class" / name)
    return tmp_path


def _outputs(argv: list[str]) -> list[str]:
    return [argv[k + 1] for k, a in enumerate(argv[:-1]) if a == "--out"]


@pytest.mark.parametrize(("page", "cmds"), list(_cases()))
def test_the_commands_of_a_page_run_as_written(page, cmds, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(_folder(tmp_path))
    for command in cmds:
        argv, command = command[1:], shlex.join(command)
        try:
            code = main(argv)
        except SystemExit as exc:  # --version, --help: argparse exits
            code = exc.code
        err = capsys.readouterr().err
        assert code in (0, None), f"{page.name}: `{command}` exited {code}: {err[-2000:]}"
        for out in _outputs(argv):
            path = Path(out)
            assert path.exists(), f"{page.name}: `{command}` wrote no {out}"
            assert path.is_file() and path.stat().st_size or any(path.iterdir()), out


def test_the_pages_show_commands():
    """The reader finds commands: README's set-up and use, and the docs' examples."""
    shown = {str(page.relative_to(ROOT)): commands(page) for page in PAGES}
    assert ["kinetostatics", "run", "mechanisms/slotting_machine.yaml", "--out", "out"] in shown[
        "README.md"
    ]
    verbs = {c[1] for cmds in shown.values() for c in cmds}
    assert {"run", "check", "batch", "optimize", "simulate", "schema", "export"} <= verbs
