"""A friction coefficient above 1 is read, and said to be implausible (io/plausible.py,
``Model.notes``): a warning naming its key and line, wherever a file gives one — a pin's
journal with its coefficient, a pin's coefficient with its bearing's bore, a slide, a
cam's contact, a rack's teeth — and nothing at a plausible one (metal pairs 0.05–0.8).
A coefficient of 12 meaning 12 % (0.12) analyses a machine that is nearly self-locked,
silently; so did one of 1.7·10⁷ found by the fuzz (docs/errors.md)."""

import re
from pathlib import Path

import pytest

import kinetostatics as ks
from kinetostatics.io.plausible import magnitude_warnings

ROOT = Path(__file__).resolve().parents[2]

# (file, the friction as written, the joint whose coefficient it becomes)
SITES = [
    ("inverted_slider_crank", "journal_radius: 12, coefficient: 0.1", "O4"),
    ("inverted_slider_crank", "friction: {coefficient: 0.12}", "slot"),
    ("cam_roller", "friction: {coefficient: 0.01}", "contact"),
    ("rack_rocker", "friction: {efficiency: 0.95}", "mesh"),
    ("slider_crank_sized", "friction: {radius: 1.5}", "O"),
]  # fmt: skip


def _with(name: str, written: str, value: str) -> str:
    text = (ROOT / "mechanisms" / f"{name}.yaml").read_text()
    assert text.count(written) == 1, (name, written)
    given = re.sub(r"\b(coefficient|efficiency|radius): [0-9.]+", f"coefficient: {value}", written)
    return text.replace(written, given)


@pytest.mark.parametrize(("name", "written", "key"), SITES)
def test_a_coefficient_above_one_is_said_implausible_at_its_key(name, written, key):
    text = _with(name, written, "12")
    line = 1 + text[: text.index("coefficient: 12")].count("\n")
    lines = magnitude_warnings(ks.loads(text, file="f.yaml"))
    said = [s for s in lines if "friction coefficient of 12 " in s]
    assert len(said) == 1, lines
    assert said[0].startswith(f"f.yaml:{line}:")
    assert f" joints.{key}.friction.coefficient: " in said[0]
    assert "implausible" in said[0] and "12 % is 0.12" in said[0]  # a percentage?


@pytest.mark.parametrize(("name", "written", "key"), SITES)
def test_a_plausible_coefficient_says_nothing(name, written, key):
    model = ks.loads(_with(name, written, "0.8"), file="f.yaml")
    assert not [s for s in magnitude_warnings(model) if "friction" in s]


def test_run_prints_the_warning(tmp_path, capsys):
    from kinetostatics.cli import main

    path = tmp_path / "m.yaml"
    path.write_text(_with("inverted_slider_crank", SITES[0][1], "15"))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    err = capsys.readouterr().err
    assert "kinetostatics: warning:" in err and "friction coefficient of 15 " in err
