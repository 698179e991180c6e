"""docs/README.md is the index: README links to it and every page of docs/ is reachable
from it by links."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
LINK = re.compile(r"\]\(([^)#\s]+\.md)(?:#[^)]*)?\)")


def _links(page: Path) -> set[Path]:
    text = page.read_text(encoding="utf-8")
    return {(page.parent / target).resolve() for target in LINK.findall(text)}


def test_readme_links_the_index():
    assert (DOCS / "README.md").resolve() in _links(ROOT / "README.md")


def test_every_page_is_reachable_from_the_index():
    seen, todo = set(), [(DOCS / "README.md").resolve()]
    while todo:
        page = todo.pop()
        if page in seen or not page.is_file():
            continue
        seen.add(page)
        todo += [p for p in _links(page) if p.parent == DOCS.resolve()]
    pages = {p.resolve() for p in DOCS.glob("*.md")}
    assert pages - seen == set(), f"not reachable from docs/README.md: {sorted(pages - seen)}"


def test_the_index_links_only_pages_that_exist():
    missing = [p for p in _links(DOCS / "README.md") if not p.is_file()]
    assert not missing, missing
