"""Files refused at load with one line naming what the user wrote (issue 36): a file over
the link limit stops at that cause, a spring whose two points always coincide, an
``output:`` that names no output (docs/errors.md, docs/yaml.md)."""

from __future__ import annotations

import pytest

import kinetostatics as ks
from kinetostatics.base.limits import MAX_LINKS
from kinetostatics.cli import main


def _chain(n: int) -> str:
    """A serial chain of ``n`` moving links, each named by loads, elements, sketch, output."""
    lines = ["links:", "  ground: {points: {O: [0, 0]}}"]
    lines += [f"  l{i}: {{points: {{P: [0, 0], Q: [1, 0]}}, mass: 1}}" for i in range(n)]
    lines += ["joints:", "  j0: {type: revolute, links: [ground, l0], points: [O, P]}"]
    lines += [
        f"  j{i}: {{type: revolute, links: [l{i - 1}, l{i}], points: [Q, P]}}" for i in range(1, n)
    ]
    lines += [
        "drivers: {motor: {joint: j0, motion: {speed: 10}}}",
        "loads: {w: {type: torque, link: l3, value: 1}}",
        "elements: {s: {type: spring, between: [l1.Q, l4.P], stiffness: 1, free_length: 1}}",
        "sketch: {l1.Q: [1, 0]}",
        "output: l5",
    ]
    return "\n".join(lines) + "\n"


def test_over_the_link_limit_is_one_line(tmp_path, capsys):
    """Over MAX_LINKS the links section is refused whole; what names a link is not
    reported again as 'unknown link' (it was: one line per joint end, load, element)."""
    with pytest.raises(ks.ModelError) as info:
        ks.loads(_chain(MAX_LINKS), file="many.yaml")
    assert [m for _, m in info.value.problems] == [
        f"{MAX_LINKS + 1} links; the limit is {MAX_LINKS}"
    ]
    path = tmp_path / "many.yaml"
    path.write_text(_chain(MAX_LINKS))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    line = f"{path}:1:1: links: {MAX_LINKS + 1} links; the limit is {MAX_LINKS}"
    assert err.splitlines() == [line]


def test_just_under_the_link_limit_loads():
    model = ks.loads(_chain(MAX_LINKS - 1))
    assert len(model.links) == MAX_LINKS
