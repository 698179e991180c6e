"""README lists every shipped example (mechanisms/*.yaml) with a command that runs it."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_every_shipped_mechanism_is_listed_with_its_command():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    commands = re.findall(r"kinetostatics (run|simulate) mechanisms/(\w+\.yaml)", readme)
    listed = {name for _, name in commands}
    shipped = {p.name for p in (ROOT / "mechanisms").glob("*.yaml")}
    assert shipped, "no shipped mechanisms found"
    assert shipped - listed == set(), f"not listed in README with a command: {shipped - listed}"
    assert listed - shipped == set(), f"README lists files that are not shipped: {listed - shipped}"


def test_effort_driven_examples_are_listed_with_simulate():
    """A file without as many motion drivers as its mobility is run by `simulate`."""
    import kinetostatics as ks
    from kinetostatics.structure.system import build_system

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    for verb, name in re.findall(r"kinetostatics (run|simulate) mechanisms/(\w+\.yaml)", readme):
        system = build_system(ks.load(ROOT / "mechanisms" / name))
        motion = len(system.motion_drivers) == system.structure.mobility
        assert verb == ("run" if motion else "simulate"), name
