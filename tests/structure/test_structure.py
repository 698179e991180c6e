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
from tests.helpers import variant

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


# the class of an Assur group (Ⅱ级, Ⅲ级 …): the pairs of its largest closed contour of
# internal pairs (孙桓《机械原理》第2章): a dyad Ⅱ; a ternary link held by three binary links
# Ⅲ; four links in a loop of four internal pairs, two of them ternary, Ⅳ
CLASSES = {
    "slotting_machine": [None, 2, 2],
    "stephenson_sixbar": [None, 3],
    "watt_sixbar": [None, 2, 2],
    "geared_fivebar": [None, None, 2],  # the pinion, held by a gear pair: a higher pair
}


@pytest.mark.parametrize("name", sorted(CLASSES))
def test_assur_groups_have_their_class(name):
    system = ks.build_system(ks.load(f"mechanisms/{name}.yaml"))
    assert [p.group.order for p in system.plans] == CLASSES[name]


def test_assur_class_is_the_largest_contour_of_internal_pairs():
    from types import SimpleNamespace

    from kinetostatics.structure.graph import assur_class

    def pairs(*links, n_eq=2):
        return [SimpleNamespace(links=tuple(p.split("-")), n_eq=n_eq) for p in links]

    assert assur_class("ab", pairs("0-a", "a-b", "b-0")) == 2
    # Ⅲ: ternary c with three internal pairs, each binary link with one external pair
    assert assur_class("cxyz", pairs("c-x", "c-y", "c-z", "x-0", "y-0", "z-0")) == 3
    # Ⅳ: the loop a–b–c–d of four internal pairs; a and c ternary with the external pairs
    assert assur_class("abcd", pairs("a-b", "b-c", "c-d", "d-a", "a-0", "c-0")) == 4
    assert assur_class("ab", pairs("0-a", "a-b") + pairs("b-0", n_eq=1)) is None
    assert assur_class("abc", pairs("0-a", "a-b", "b-c", "c-0")) is None  # 9 ≠ 8
