"""The shipped documentation stands on its own: no file under docs/, src/ or
mechanisms/, nor README.md, sends the reader to a file outside the repository
(the project's internal notes SPEC.md, MECHANISMS.md, STYLE.md, ARCHITECTURE.md,
the shared folder or the source texts under seeds/).  Conventions live in
docs/conventions.md, the reference machines in docs/validation.md.

tests/ may keep internal notes and is not checked.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FORBIDDEN = re.compile(r"SPEC\.md|MECHANISMS\.md|STYLE\.md|ARCHITECTURE\.md|\.\./shared|seeds/")
SUFFIXES = {".md", ".py", ".yaml", ".yml"}


def _files():
    yield ROOT / "README.md"
    for folder in ("docs", "src", "mechanisms"):
        for path in sorted((ROOT / folder).rglob("*")):
            if path.is_file() and path.suffix in SUFFIXES:
                yield path


def test_no_reference_outside_the_repository():
    found = []
    for path in _files():
        text = path.read_text(encoding="utf-8")
        for n, line in enumerate(text.splitlines(), 1):
            if FORBIDDEN.search(line):
                found.append(f"{path.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not found, "references to files outside the repository:\n" + "\n".join(found)


def test_the_conventions_page_exists_and_is_listed():
    assert (ROOT / "docs" / "conventions.md").is_file()
    assert "docs/conventions.md" in (ROOT / "README.md").read_text(encoding="utf-8")
