"""Every file or folder under tests/ that README.md and the pages of docs/ name exists, so
that a page follows the tests when they move (docs/architecture.md, *Tests*)."""

import re

from tests.helpers import ROOT

# a path under tests/ as the pages write it: tests/net/long_run.py, tests/hard/, tests/*.py
_PATH = re.compile(r"(?<![\w/.])tests/[\w./*-]*[\w/*]")


def _named() -> list[tuple[str, str]]:
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    return [
        (page.relative_to(ROOT).as_posix(), path)
        for page in pages
        for path in _PATH.findall(page.read_text(encoding="utf-8"))
    ]


def test_the_pages_name_tests_that_exist():
    named = _named()
    assert len(named) > 100  # the pattern sees the pages' paths
    missing = [f"{page}: {path}" for page, path in named if not any(ROOT.glob(path.rstrip("/")))]
    assert not missing, "\n".join(missing)
