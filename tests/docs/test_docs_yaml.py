"""docs/yaml.md stays in step with the loader.

- Every ```yaml block with a top-level ``links:`` key is a complete example: it
  loads with ``kinetostatics.loads`` and, if it has drivers, analyses.
- A block fenced ```yaml broken is a deliberately wrong file; the ```text block
  after it is the loader's exact output (the file name is taken from it).
- Every top-level key, the units of length and speed, the quantity kinds, the
  reserved names, the expression functions and the limits are mentioned.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import kinetostatics as ks
from kinetostatics.base import expressions, limits, spec, units
from kinetostatics.io import TOP_KEYS

DOC = Path(__file__).resolve().parents[2] / "docs" / "yaml.md"
FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```[ \t]*$", re.S | re.M)


def _blocks() -> list[tuple[str, str, int]]:
    """(info string, body, line number) of every fenced block."""
    text = DOC.read_text(encoding="utf-8")
    return [
        (m.group(1).strip(), m.group(2), text.count("\n", 0, m.start()) + 1)
        for m in FENCE.finditer(text)
    ]


def _has_top_level(body: str, key: str) -> bool:
    return re.search(rf"^{key}\s*:", body, re.M) is not None


def _examples() -> list:
    return [
        pytest.param(body, id=f"line{line}")
        for info, body, line in _blocks()
        if info == "yaml" and _has_top_level(body, "links")
    ]


def _broken() -> list:
    blocks, out = _blocks(), []
    for k, (info, body, line) in enumerate(blocks):
        if info.split() == ["yaml", "broken"]:
            following = [b for b in blocks[k + 1 :] if b[0] == "text"]
            assert following, f"docs/yaml.md:{line}: a broken example needs its output after it"
            out.append(pytest.param(body, following[0][1], id=f"line{line}"))
    return out


@pytest.fixture(scope="module")
def doc() -> str:
    return DOC.read_text(encoding="utf-8")


def test_doc_has_at_least_three_complete_examples():
    assert len(_examples()) >= 3


@pytest.mark.parametrize("text", _examples())
def test_example_loads_and_analyses(text):
    model = ks.loads(text, file="docs/yaml.md")
    assert model.links and model.joints
    if model.drivers:
        result = ks.analyze(model)
        assert len(result) >= 1


@pytest.mark.parametrize("text, expected", _broken())
def test_broken_example_gives_the_documented_errors(text, expected):
    lines = [line for line in expected.splitlines() if line.strip()]
    name = lines[0].split(":", 1)[0]
    with pytest.raises(ks.ModelError) as info:
        ks.loads(text, file=name)
    assert str(info.value).splitlines() == lines


def test_every_top_level_key_is_documented(doc):
    for key in TOP_KEYS:
        assert f"`{key}`" in doc, f"top-level key '{key}' is not in docs/yaml.md"


@pytest.mark.parametrize("kind", ["length", "speed"])
def test_every_unit_is_documented(doc, kind):
    missing = [u for u in units.UNITS[kind] if f"`{u}`" not in doc]
    assert not missing, f"{kind} units missing from docs/yaml.md: {missing}"


def test_quantity_kinds_reserved_names_and_functions_are_documented(doc):
    for kind in units.QUANTITY_KINDS:
        assert f"`{kind}`" in doc, kind
    for name in spec.RESERVED:
        assert f"`{name}`" in doc, name
    for name in expressions.FUNCTIONS:
        assert f"`{name}" in doc, name  # `sqrt` or `log(x)`
    for name in expressions.CONSTANTS:
        assert f"`{name}`" in doc, name


def test_limits_are_documented(doc):
    for value in (limits.MAX_FILE_BYTES, limits.MAX_NODES, limits.MAX_LINKS, limits.MAX_DEPTH):
        assert f"{value:,}" in doc, value
    assert (
        f"{limits.MAX_POSITIONS:,}".replace(",", " ") in doc or f"{limits.MAX_POSITIONS:,}" in doc
    )
    assert str(expressions.MAX_EXPRESSION_LENGTH) in doc
    assert f"{expressions.MAX_DEPTH} levels" in doc
