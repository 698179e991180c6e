"""The templates number their links as their guides do (``number:``, docs/templates.md):
the report written from a file of ``kinetostatics init`` names the members and the
reactions with those numbers (构件4, ω₄, F_R23), in Chinese and in English.

The expected numbers are the guides' (the shaper's: frame 1, crank 2, block 3, guide
bar 4, link 5, ram 6), written here; F_Rij is the reaction of link i on link j, i the
first link of the joint's ``links:`` (the slot of a guide bar carries its axis on the
bar: F_R43 in the shaper, the opposite of the guide's F_R34)."""

from __future__ import annotations

import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.io.templates import NAMES
from kinetostatics.outputs.labels import link_numbers
from kinetostatics.structure.system import system_of

_SUB = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")

# template: ({link: the guide's number}, {joint: (i, j) of F_Rij})
GUIDE = {
    "slotting": (
        {"crank": 1, "block": 2, "bar": 3, "rod": 4, "ram": 5, "frame": 6},
        {"O2": (6, 1), "A": (1, 2), "slot": (3, 2), "O3": (6, 3), "B": (3, 4), "C": (4, 5),
         "guide": (6, 5)},
    ),
    "shaper": (
        {"frame": 1, "crank": 2, "block": 3, "bar": 4, "link": 5, "ram": 6},
        {"O2": (1, 2), "A": (2, 3), "slot": (4, 3), "O4": (1, 4), "B": (4, 5), "C": (5, 6),
         "guide": (1, 6)},
    ),
    "press": (
        {"crank": 1, "coupler": 2, "rocker": 3, "link": 4, "ram": 5, "frame": 6},
        {"A": (6, 1), "B": (1, 2), "C": (2, 3), "D": (6, 3), "E": (3, 4), "F": (4, 5),
         "guide": (6, 5)},
    ),
    "jaw_crusher": (
        {"frame": 1, "crank": 2, "coupler": 3, "rocker": 4, "toggle": 5, "jaw": 6},
        {"O2": (1, 2), "A": (2, 3), "B_rocker": (3, 4), "B_toggle": (3, 5), "O4": (1, 4),
         "C": (5, 6), "O6": (1, 6)},
    ),
    "saw": (
        {"crank": 1, "rod": 2, "saw": 3, "frame": 4},
        {"O": (4, 1), "A": (1, 2), "B": (2, 3), "guide": (4, 3)},
    ),
}  # fmt: skip
# links that turn (a column of angular velocity in the report's tables)
TURNING = {
    "slotting": ("crank", "bar", "rod"),
    "shaper": ("crank", "bar", "link"),
    "press": ("crank", "coupler", "rocker", "link"),
    "jaw_crusher": ("crank", "coupler", "rocker", "toggle", "jaw"),
    "saw": ("crank", "rod"),
}


def write(tmp_path, name: str):
    path = tmp_path / f"{name}.yaml"
    assert main(["init", name, "--out", str(path)]) == 0
    return path


def test_every_template_is_listed_here():
    assert set(GUIDE) == set(NAMES) == set(TURNING)


@pytest.mark.parametrize("name", NAMES)
def test_each_link_carries_the_number_of_its_guide(tmp_path, name):
    numbers, _ = GUIDE[name]
    model = ks.load(write(tmp_path, name))
    assert {lk.name: lk.number for lk in model.links} == numbers
    assert link_numbers(system_of(model)) == numbers


def _rows(md: str, first: str) -> list[list[str]]:
    """The cells of the table rows of ``md`` whose first cell is ``first``."""
    lines = [ln for ln in md.splitlines() if ln.startswith(f"| {first} |")]
    return [[c.strip() for c in ln.strip("|").split("|")] for ln in lines]


def _cases():
    for name in NAMES:
        for lang in ("zh", "en"):
            slow = () if name == "shaper" else pytest.mark.slow
            yield pytest.param(name, lang, marks=slow, id=f"{name}-{lang}")


@pytest.mark.parametrize("name, lang", list(_cases()))
def test_the_report_names_members_and_reactions_by_the_guides_numbers(tmp_path, name, lang):
    numbers, reactions = GUIDE[name]
    out = tmp_path / "out"
    args = ["report", str(write(tmp_path, name)), "--out", str(out), "--format", "md"]
    assert main([*args, "--dpi", "30", "--positions", "2", "--lang", lang]) == 0
    md = (out / "report.md").read_text(encoding="utf-8")
    for link, n in numbers.items():  # the table of links: name, number
        assert [link, str(n)] in [row[:2] for row in _rows(md, link)], link
    for joint, (i, j) in reactions.items():  # the table of joints: its reaction's symbol
        assert any(f"F_R{i}{j}" in row for row in _rows(md, joint)), joint
    if lang == "zh":  # the tables' columns: 构件4 角速度 ω₄, O4 反力 F_R14x
        for link in TURNING[name]:
            n = numbers[link]
            assert f"构件{n} 角速度 ω{str(n).translate(_SUB)} (rad/s)" in md, link
        for joint, (i, j) in reactions.items():
            assert f"{joint} 反力 F_R{i}{j}x (N)" in md, joint
