"""The cycle basis behind :func:`~kinetostatics.structure.graph.independent_loops`: a joint
graph with a node per joint (so that parallel joints form cycles) and Paton's fundamental
cycles of it, in plain Python, node for node as networkx's ``cycle_basis``."""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["cycle_basis", "subdivided"]


def subdivided(edges: Iterable[tuple]) -> dict:
    """A simple graph (adjacency dicts) of a joint graph's ``edges()`` (link, link, joint,
    data) with one extra node per joint, so parallel joints form cycles."""
    h: dict = {}
    for u, v, key, _ in edges:
        for a, b in ((u, ("joint", key)), (("joint", key), v)):
            h.setdefault(a, {})
            h.setdefault(b, {})
            h[a][b] = h[b][a] = None
    return h


def cycle_basis(h: dict, root=None) -> list[list]:
    """Paton's fundamental cycles of a simple graph given as adjacency dicts (CACM 491):
    a spanning tree grown depth first from ``root``, one cycle per edge off the tree,
    component after component (networkx's ``cycle_basis``, node for node)."""
    left = dict.fromkeys(h)  # the nodes not yet reached, in order
    cycles = []
    if root is not None and root not in h:
        root = None
    while left:
        if root is None:
            root = left.popitem()[0]
        stack, pred, used = [root], {root: root}, {root: set()}
        while stack:
            z = stack.pop()
            zused = used[z]
            for nbr in h[z]:
                if nbr not in used:  # a new node
                    pred[nbr] = z
                    stack.append(nbr)
                    used[nbr] = {z}
                elif nbr == z:  # a self loop
                    cycles.append([z])
                elif nbr not in zused:  # a cycle closes
                    pn = used[nbr]
                    cycle, p = [nbr, z], pred[z]
                    while p not in pn:
                        cycle.append(p)
                        p = pred[p]
                    cycle.append(p)
                    cycles.append(cycle)
                    used[nbr].add(z)
        for node in pred:
            left.pop(node, None)
        root = None
    return cycles
