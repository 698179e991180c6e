"""Structure: mobility, loops (rank test), Assur groups and `check`."""

import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.errors import StructureError
from kinetostatics.structure.graph import (
    check_loops,
    cyclomatic_number,
    independent_loops,
    joint_graph,
)

from .helpers import variant

EXPECTED = {
    "slider_crank": ["driven link {crank}", "RRP dyad {rod, slider}"],
    "slotting_machine": ["driven link {crank}", "RPR dyad {block, bar}", "RRP dyad {rod, ram}"],
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_groups_and_mobility(name):
    system = ks.build_system(ks.load(f"mechanisms/{name}.yaml"))
    assert system.structure.mobility == 1
    assert [p.group.label for p in system.plans] == EXPECTED[name]


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_check_prints_structure(name, capsys):
    assert main(["check", f"mechanisms/{name}.yaml"]) == 0
    out = capsys.readouterr().out
    assert "mobility (Grübler–Kutzbach): 1" in out
    assert "mobility (numerical, at the sketched pose): 1" in out
    for label in EXPECTED[name]:
        assert label in out


def test_loops_rank_test_accepts_any_basis_and_rejects_dependent_sets():
    model = ks.load("mechanisms/slotting_machine.yaml")
    g = joint_graph(model)
    assert cyclomatic_number(g) == 2 == len(independent_loops(g))
    where = ks.errors.Location("m.yaml", path="loops")
    small = ("O3", "B", "C", "guide")
    big = ("O2", "A", "slot", "B", "C", "guide")
    other = ("O2", "A", "slot", "O3")  # the crank–bar loop
    check_loops(g, (small, other), where)  # a different basis passes
    check_loops(g, (big, other), where)
    with pytest.raises(StructureError, match="not independent"):
        check_loops(g, (small, small[::-1]), where)
    with pytest.raises(StructureError, match="1 loops listed; the linkage has 2"):
        check_loops(g, (small,), where)
    with pytest.raises(StructureError, match="do not form a closed loop"):
        check_loops(g, (("O2", "A", "B"), other), where)


def test_user_loops_in_yaml_are_checked():
    model = variant("slider_crank", loops=(r"\ndrivers:", "\nloops: [[O, A, B, slide]]\ndrivers:"))
    assert ks.build_system(model).structure.loops == (("O", "A", "B", "slide"),)
