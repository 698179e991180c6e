"""The structure search: same answers as before, polynomial work, a clear error past its limit.

The graph queries are plain Python since networkx left the start-up path: they are
compared here with networkx (when installed) on random multigraphs, and the Assur
group search with the exhaustive search over all combinations of links it replaced.
Large generated linkages (tests/chains.py) show the work growing polynomially: the
search's step budget ``MAX_SEARCH`` is lowered so that exponential work would fail.
"""

from __future__ import annotations

import itertools
import random
import re
import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.errors import StructureError
from kinetostatics.structure import graph
from kinetostatics.structure.graph import JointGraph, cyclomatic_number, independent_loops
from tests.chains import dyad_chain, fan, open_chain


# -- the graph queries against networkx ----------------------------------------
def _random_graphs(seed: int, count: int):
    """Random multigraphs (parallel joints, self loops, several components) as a list of
    ("node", name, ground) / ("edge", u, v, key) steps."""
    rng = random.Random(seed)
    for _ in range(count):
        nodes = [f"n{k}" for k in range(rng.randint(1, 9))]
        rng.shuffle(nodes)
        steps = [("node", n, k == 0) for k, n in enumerate(nodes)]
        steps += [
            ("edge", rng.choice(nodes), rng.choice(nodes), f"j{k}")
            for k in range(rng.randint(0, 14))
        ]
        yield steps


def test_graph_queries_match_networkx():
    nx = pytest.importorskip("networkx")
    for steps in _random_graphs(1, 400):
        g, h = JointGraph(), nx.MultiGraph()
        for step in steps:
            if step[0] == "node":
                g.add_node(step[1], ground=step[2])
                h.add_node(step[1], ground=step[2])
            else:
                g.add_edge(*step[1:], n_eq=2)
                h.add_edge(*step[1:], n_eq=2)
        assert [e[:3] for e in g.edges()] == list(h.edges(keys=True))
        assert list(g.connected_components()) == list(nx.connected_components(h))
        assert cyclomatic_number(g) == h.number_of_edges() - len(
            h
        ) + nx.number_connected_components(h)
        sub = nx.Graph()
        for u, v, key in h.edges(keys=True):
            sub.add_edge(u, ("joint", key))
            sub.add_edge(("joint", key), v)
        root = steps[0][1]
        if root in sub:  # networkx fails when the ground has no joint
            basis = nx.cycle_basis(sub, root)
            expected = tuple(tuple(n[1] for n in c if isinstance(n, tuple)) for c in basis)
            assert independent_loops(g) == expected


# -- the group search against the exhaustive search ----------------------------
def _random_linkage(rng: random.Random) -> str:
    """A random topology: revolute and prismatic joints between random links, 0–2 motion
    drivers; any mobility."""
    names = ["ground"] + [f"l{k}" for k in range(rng.randint(1, 9))]
    points: dict[str, list[str]] = {n: [] for n in names}
    joints, drivers = [], []
    for k in range(rng.randint(len(names) - 1, 2 * len(names) + 2)):
        u, v = rng.sample(names, 2)
        points[u].append(f"J{k}")
        points[v].append(f"J{k}")
        if rng.random() < 0.2:
            points[u].append(f"G{k}")
            axis = f"axis: {{point: G{k}, direction: [1, 0]}}, point: J{k}"
            joints.append(f"  J{k}: {{type: prismatic, links: [{u}, {v}], {axis}}}")
        else:
            joints.append(f"  J{k}: {{type: revolute, links: [{u}, {v}]}}")
            if rng.random() < 0.15:
                points[u].append(f"R{k}")
                points[v].append(f"R{k}")
                drivers.append(
                    f"  d{k}: {{joint: J{k}, points: [R{k}, R{k}], motion: {{speed: 1}}}}"
                )
    rng.shuffle(joints)
    text = ["name: random", "links:"]
    for n in names:
        pts = ", ".join(f"{p}: [{rng.random():.3f}, {rng.random():.3f}]" for p in points[n])
        text.append(
            f"  {n}:\n    points: {{{pts or 'P: [0, 0]'}}}"
            + ("\n    mass: 1" if n != "ground" else "")
        )
    text += ["joints:", *joints] + (["drivers:", *drivers] if drivers else [])
    return "\n".join(text) + "\n"


def _exhaustive_groups(model: ks.Model) -> list[tuple[str, ...]]:
    """The group search as it was: every combination of up to 6 unknown links, by size."""
    joints = {j.name: j for j in model.joints}
    cons = [(set(j.links), j.n_eq) for j in model.joints]
    cons += [(set(joints[d.joint].links), 1) for d in model.drivers if d.motion is not None]
    adj: dict[str, set[str]] = {}
    for j in model.joints:
        adj.setdefault(j.links[0], set()).add(j.links[1])
        adj.setdefault(j.links[1], set()).add(j.links[0])

    def connected(combo):
        seen, todo = {combo[0]}, [combo[0]]
        while todo:
            todo = [v for u in todo for v in adj.get(u, ()) if v in combo and v not in seen]
            seen.update(todo)
        return len(seen) == len(combo)

    known, unknown, out = {model.ground.name}, [n.name for n in model.moving_links], []
    while unknown:
        sets = (
            c
            for size in range(1, min(len(unknown), 6) + 1)
            for c in itertools.combinations(unknown, size)
            if sum(n for s, n in cons if s & set(c) and s <= set(c) | known) == 3 * size
            and connected(c)
        )
        found = next(sets, tuple(unknown))
        out.append(found)
        known |= set(found)
        unknown = [u for u in unknown if u not in found]
    return out


def test_group_search_finds_what_the_exhaustive_search_found():
    rng, compared = random.Random(3), 0
    for _ in range(120):  # (loading takes most of the time)
        model = ks.loads(_random_linkage(rng))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            groups = graph.assur_groups(model)
        expected = _exhaustive_groups(model)
        assert [set(g.links) for g in groups] == [set(c) for c in expected]
        # a group's links in the links' order (a dyad's may be turned by its letters)
        assert all(g.links in (c, c[::-1]) for g, c in zip(groups, expected))
        compared += sum(len(c) > 1 for c in expected)
    assert compared > 150  # groups of several links were compared, not only single links


# -- size scaling ----------------------------------------------------------------
def test_long_dyad_chain_decomposes_with_little_work(monkeypatch):
    """The search keeps its state from one group to the next: its work grows with the
    links (about 11 steps a link), not with their square (55,000 steps for these 199
    links when each group's search started over; a 999-link chain would need 1.4 M)."""
    monkeypatch.setattr(graph, "MAX_SEARCH", 15 * 199)
    system = ks.build_system(ks.loads(dyad_chain(99)))
    labels = [p.group.label for p in system.plans]
    assert labels == ["driven link {crank}"] + [
        f"RRR dyad {{rod{k}, rocker{k}}}" for k in range(1, 100)
    ]


def test_long_dyad_chain_analyses_and_every_rocker_turns_as_the_first():
    result = ks.analyze(ks.loads(dyad_chain(12, positions=36)))
    q, links = result.q, result.system.links
    first = q[:, 3 * links.index("rocker1") + 2]
    for k in range(2, 13):  # the parallelograms copy the first rocker's angle
        np.testing.assert_allclose(q[:, 3 * links.index(f"rocker{k}") + 2], first, atol=1e-9)


def test_unsolvable_open_chain_is_searched_in_polynomial_work(monkeypatch):
    """Was C(n, 6) subsets: 1 s at 25 links, 97 s at 50, never at 199 (docs/errors.md)."""
    monkeypatch.setattr(graph, "MAX_SEARCH", 40_000)  # 21,000 steps needed
    model = ks.loads(open_chain(199))
    system = ks.build_system(model)  # no warning: the file has fewer drivers than freedoms
    assert [p.group.label for p in system.plans][0] == "driven link {l0}"
    assert system.plans[1].group.links == tuple(f"l{k}" for k in range(1, 199))
    with pytest.raises(StructureError, match=r"as many motion drivers as the mobility \(199\)"):
        ks.analyze(model)


def test_densely_jointed_linkage_stops_with_a_clear_error(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(graph, "MAX_SEARCH", 100_000)
    (tmp_path / "fan.yaml").write_text(fan(40))  # C(80, 5) connected sets around the hub
    assert main(["check", str(tmp_path / "fan.yaml")]) == 2
    err = capsys.readouterr().err
    assert re.search(
        r"fan\.yaml:\d+:\d+: links\.hub: the search for Assur groups gave up after 100,000 "
        r"steps: the links not yet placed \(hub, b0, a1, b1, a2, b2, … \(80 links\)\)",
        err,
    ), err
    assert "(does it lack motion drivers?)" in err


def test_large_overconstrained_chain_is_refused_before_the_search():
    with pytest.raises(StructureError, match="the mobility is -64: .* overconstrained"):
        ks.build_system(ks.loads(dyad_chain(66, redundant=True)))
    undriven = dyad_chain(66, redundant=True).replace(
        "drivers:\n  motor: {joint: O0, motion: {speed: 120}}\n", ""
    )
    with pytest.raises(StructureError, match=r"joints: the mobility \(Grübler–Kutzbach\) is -64: "):
        ks.build_system(ks.loads(undriven))  # was an IndexError
