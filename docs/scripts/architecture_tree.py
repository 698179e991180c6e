"""Print the module tree of src/kinetostatics with each module's first docstring line.

    python docs/scripts/architecture_tree.py [--write]

With ``--write`` the block between ``<!-- tree:begin -->`` and ``<!-- tree:end -->`` in
docs/architecture.md is replaced; tests/architecture/test_architecture.py checks that the block
lists exactly the modules on disk.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "src" / "kinetostatics"
DOC = ROOT / "docs" / "architecture.md"
BEGIN, END = "<!-- tree:begin -->", "<!-- tree:end -->"
WIDTH = 26  # the column where descriptions start


def _summary(path: Path) -> str:
    doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
    text = " ".join(doc.split("\n\n", 1)[0].split())
    for stop in (". ", ": "):
        if stop in text and text.index(stop) < 90:
            text = text[: text.index(stop) + (1 if stop == ". " else 0)]
            break
    return text if len(text) <= 90 else text[:87].rsplit(" ", 1)[0] + " …"


def _lines(folder: Path, depth: int) -> list[str]:
    out = []
    pad = "    " * depth
    files = sorted(p for p in folder.iterdir() if p.suffix == ".py")
    dirs = sorted(p for p in folder.iterdir() if p.is_dir() and (p / "__init__.py").exists())
    for f in files:
        name = f"{pad}{f.name}"
        out.append(f"{name:<{WIDTH}}{_summary(f)}".rstrip())
    for d in dirs:
        out.append(f"{pad}{d.name}/")
        out += _lines(d, depth + 1)
    return out


def tree() -> str:
    return "\n".join([BEGIN, "```text", *_lines(PKG, 0), "```", END])


def main(argv: list[str]) -> int:
    block = tree()
    print(block)
    if "--write" in argv:
        text = DOC.read_text(encoding="utf-8")
        i, j = text.index(BEGIN), text.index(END) + len(END)
        DOC.write_text(text[:i] + block + text[j:], encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
