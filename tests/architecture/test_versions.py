"""tests/minimum-versions.txt pins exactly the minimums pyproject.toml declares, so that
``tests/venv_run.sh minimum`` tests what a user with the oldest supported versions has."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

tomllib = pytest.importorskip("tomllib")  # Python 3.11 on; the minimum run uses it

ROOT = Path(__file__).resolve().parents[2]


def _norm(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def _version(text: str) -> tuple[int, ...]:
    parts = [int(p) for p in text.split(".")]
    while parts and parts[-1] == 0:
        parts.pop()
    return tuple(parts)


def declared() -> dict[str, str]:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    reqs = list(project["dependencies"])
    for extra in project["optional-dependencies"].values():
        reqs += extra
    out = {}
    for req in reqs:
        m = re.fullmatch(r"([\w.-]+)(?:\[[\w,]+\])?\s*>=\s*([\d.]+)", req)
        if m:
            out[_norm(m.group(1))] = m.group(2)
    return out


def pinned() -> dict[str, str]:
    out = {}
    for line in (ROOT / "tests" / "minimum-versions.txt").read_text().splitlines():
        line = line.split("#")[0].strip()
        if line:
            name, version = line.split("==")
            out[_norm(name)] = version
    return out


def test_every_declared_minimum_is_pinned():
    pins = pinned()
    for name, minimum in declared().items():
        assert name in pins, f"{name} >= {minimum} is not pinned in tests/minimum-versions.txt"
        assert _version(pins[name]) == _version(minimum), (name, minimum, pins[name])


def test_the_declared_minimums_are_parsed():
    assert {"numpy", "scipy", "matplotlib", "pyyaml", "pytest"} <= set(declared())
