"""Structure of a linkage: the joint graph, mobility, loops and Assur groups.

Free functions over a networkx ``MultiGraph`` whose nodes are links and whose
edges are joints (key = joint name).  Motion drivers are not edges: they are
extra equations on a joint, counted when the Assur groups are found.
"""

from __future__ import annotations

import itertools
import warnings
from dataclasses import dataclass

import networkx as nx
import numpy as np

from ..errors import Location, StructureError
from ..model import Model

__all__ = [
    "Group",
    "Structure",
    "joint_graph",
    "gruebler_mobility",
    "cyclomatic_number",
    "independent_loops",
    "check_loops",
    "assur_groups",
    "structure",
]

MAX_GROUP_SEARCH = 6  # largest group searched for by enumeration


@dataclass(frozen=True)
class Group:
    """One solve step: the links found together and the constraints that fix them.

    ``kind`` is ``driven`` (links fixed by motion drivers), ``dyad``, ``triad``
    or ``group``; ``letters`` the dyad's pair string such as ``RRP``.
    """

    name: str
    kind: str
    letters: str
    links: tuple[str, ...]
    joints: tuple[str, ...]
    drivers: tuple[str, ...]

    @property
    def column(self) -> str:
        """Prefix of the group's result columns: its links joined by '_'."""
        return "_".join(self.links)

    @property
    def label(self) -> str:
        head = {
            "dyad": f"{self.letters} dyad",
            "triad": "triad",
            "driven": "driven link" if len(self.links) == 1 else "driven links",
        }.get(self.kind, f"{len(self.links)}-link group")
        return f"{head} {{{', '.join(self.links)}}}"


@dataclass(frozen=True)
class Structure:
    """The structural analysis of a model (no positions needed)."""

    graph: nx.MultiGraph
    mobility: int
    loops: tuple[tuple[str, ...], ...]
    groups: tuple[Group, ...]


def joint_graph(model: Model) -> nx.MultiGraph:
    """Links as nodes, joints as edges keyed by joint name (attribute ``joint``)."""
    g = nx.MultiGraph(name=model.name)
    for link in model.links:
        g.add_node(link.name, ground=link.ground)
    for j in model.joints:
        g.add_edge(*j.links, key=j.name, joint=j, n_eq=j.n_eq)
    return g


def gruebler_mobility(g: nx.MultiGraph) -> int:
    """Grübler–Kutzbach: 3 per moving link minus the equations of every joint.

    Lower pairs remove 2 freedoms, higher pairs 1.
    """
    moving = sum(1 for _, d in g.nodes(data=True) if not d.get("ground"))
    return 3 * moving - sum(d["n_eq"] for *_, d in g.edges(keys=True, data=True))


def cyclomatic_number(g: nx.MultiGraph) -> int:
    """Number of independent loops: E − V + (connected components)."""
    return g.number_of_edges() - g.number_of_nodes() + nx.number_connected_components(g)


def _subdivided(g: nx.MultiGraph) -> nx.Graph:
    """A simple graph with one extra node per joint, so parallel joints form cycles."""
    h = nx.Graph()
    for u, v, key in g.edges(keys=True):
        h.add_edge(u, ("joint", key))
        h.add_edge(("joint", key), v)
    return h


def independent_loops(g: nx.MultiGraph) -> tuple[tuple[str, ...], ...]:
    """A cycle basis as lists of joint names, in traversal order.

    Examples
    --------
    The four-bar has one loop:

    >>> g = nx.MultiGraph()
    >>> g.add_nodes_from(["ground", "crank", "coupler", "rocker"])
    >>> for name, u, v in [("O", "ground", "crank"), ("A", "crank", "coupler"),
    ...                    ("B", "coupler", "rocker"), ("C", "rocker", "ground")]:
    ...     _ = g.add_edge(u, v, key=name, n_eq=2)
    >>> sorted(independent_loops(g)[0])
    ['A', 'B', 'C', 'O']
    """
    root = next((n for n, d in g.nodes(data=True) if d.get("ground")), None)
    basis = nx.cycle_basis(_subdivided(g), root)
    return tuple(tuple(n[1] for n in cycle if isinstance(n, tuple)) for cycle in basis)


def _loop_vector(
    g: nx.MultiGraph, loop: tuple[str, ...], index: dict[str, int]
) -> np.ndarray | None:
    """Signed edge vector of a closed chain of joints, or None if it is not a cycle."""
    ends = {key: (u, v) for u, v, key in g.edges(keys=True)}
    if len(set(loop)) != len(loop) or len(loop) < 2:
        return None
    first = ends[loop[0]]
    for start in first:  # try both senses of traversal
        vec, node, ok = np.zeros(len(index)), start, True
        for key in loop:
            u, v = ends[key]
            if node == u:
                vec[index[key]], node = 1.0, v
            elif node == v:
                vec[index[key]], node = -1.0, u
            else:
                ok = False
                break
        if ok and node == start:
            return vec
    return None


def check_loops(g: nx.MultiGraph, loops: tuple[tuple[str, ...], ...], where: Location) -> None:
    """User loops must be closed chains, independent, and as many as the cyclomatic number.

    Independence is a rank test on the signed edge vectors, so any valid basis passes.
    """
    index = {key: k for k, (_, _, key) in enumerate(g.edges(keys=True))}
    vectors, problems = [], []
    for k, loop in enumerate(loops):
        vec = _loop_vector(g, loop, index)
        if vec is None:
            problems.append((where.child(k), f"joints {', '.join(loop)} do not form a closed loop"))
        else:
            vectors.append(vec)
    need = cyclomatic_number(g)
    if not problems and len(loops) != need:
        problems.append(
            (where, f"{len(loops)} loops listed; the linkage has {need} independent loops")
        )
    elif not problems and vectors and np.linalg.matrix_rank(np.array(vectors)) < len(vectors):
        problems.append((where, "the listed loops are not independent"))
    if problems:
        raise StructureError(problems)


def _letters(
    g: nx.MultiGraph, links: tuple[str, ...], joints: list[str]
) -> tuple[str, tuple[str, ...]]:
    """Pair letters of a dyad, external–internal–external, e.g. ``RRP``."""
    a, b = links
    data = {key: d["joint"] for _, _, key, d in g.edges(keys=True, data=True)}

    def letter(name: str) -> str:
        return data[name].letter

    inside = [n for n in joints if set(data[n].links) == {a, b}]
    ext_a = [n for n in joints if a in data[n].links and n not in inside]
    ext_b = [n for n in joints if b in data[n].links and n not in inside]
    forward = "".join(letter(n) for n in ext_a + inside + ext_b)
    backward = forward[::-1]
    rank = {"R": 0, "P": 1}
    key = lambda s: [rank.get(c, 2) for c in s]
    if key(backward) < key(forward):
        return backward, (b, a)
    return forward, (a, b)


def assur_groups(model: Model, g: nx.MultiGraph | None = None) -> tuple[Group, ...]:
    """Decompose relative to the motion-driven links and order the solve.

    Starting from ground, repeatedly take the smallest set of unknown links
    that the constraints to known links (joints and motion drivers) fix
    exactly: Σ equations = 3·(links).  Sets are searched by increasing size
    (cost: combinations up to ``MAX_GROUP_SEARCH`` links); what is left over
    is solved as one group, with a warning.
    """
    g = joint_graph(model) if g is None else g
    joints = {j.name: j for j in model.joints}
    motion = [d for d in model.drivers if d.motion is not None]
    known = {model.ground.name}
    unknown = [link.name for link in model.moving_links]
    constraints = [(j.name, set(j.links), j.n_eq, False) for j in model.joints]
    constraints += [(d.name, set(joints[d.joint].links), 1, True) for d in motion]
    groups: list[Group] = []

    def closing(subset: set[str]) -> list[tuple[str, set[str], int, bool]]:
        return [c for c in constraints if c[1] & subset and c[1] <= subset | known]

    while unknown:
        found = None
        for size in range(1, min(len(unknown), MAX_GROUP_SEARCH) + 1):
            for combo in itertools.combinations(unknown, size):
                subset = set(combo)
                cs = closing(subset)
                if sum(c[2] for c in cs) == 3 * size and nx.is_connected(g.subgraph(combo)):
                    found = (combo, cs)
                    break
            if found:
                break
        if found is None:
            combo = tuple(unknown)
            cs = closing(set(combo))
            warnings.warn(
                f"links {', '.join(combo)} do not decompose into Assur groups; "
                "they are solved as one group",
                stacklevel=2,
            )
            found = (combo, cs)
        combo, cs = found
        jnames = [c[0] for c in cs if not c[3]]
        dnames = [c[0] for c in cs if c[3]]
        if dnames:
            kind, letters, links = "driven", "", combo
        elif len(combo) == 2 and len(jnames) == 3:
            kind = "dyad"
            letters, links = _letters(g, combo, jnames)
        elif len(combo) == 4 and len(jnames) == 6:
            kind, letters, links = "triad", "", combo
        else:
            kind, letters, links = "group", "", combo
        groups.append(
            Group(
                f"group{len(groups) + 1}", kind, letters, tuple(links), tuple(jnames), tuple(dnames)
            )
        )
        known |= set(combo)
        unknown = [u for u in unknown if u not in combo]
    return tuple(groups)


def _overconstrained_hint(model: Model, g: nx.MultiGraph, mobility: int) -> str:
    """For a linkage whose Grübler–Kutzbach count is below 1 but which may move (it has
    loops): overconstrained linkages (redundant joints, e.g. a parallelogram with an extra
    crank) are not supported — their reactions, and the friction that depends on them,
    are statically indeterminate."""
    if mobility >= 1 or cyclomatic_number(g) == 0:
        return ""
    return (
        f" (if the linkage does move although Grübler–Kutzbach counts {mobility}, it is "
        "overconstrained: some joints are redundant, e.g. an extra crank or coupler of a "
        "parallelogram, and their reactions are statically indeterminate; such linkages "
        "are not supported: remove the redundant joints)"
    )


def structure(model: Model) -> Structure:
    """Graph, Grübler mobility, loops and Assur groups of a model.

    Raises :class:`~kinetostatics.errors.StructureError` for a ground that does
    not connect every link, bad user loops, or more motion drivers than the
    mobility allows.
    """
    g = joint_graph(model)
    ground = model.ground.name
    detached = []
    for part in nx.connected_components(g):
        if ground in part:
            continue
        names = [link.name for link in model.links if link.name in part]  # file order
        first = model.link(names[0]).where
        where = (
            first if first.line is not None else Location(model.source, path=f"links.{names[0]}")
        )
        if len(names) == 1:
            message = (
                f"link '{names[0]}' is not connected to the ground '{ground}': no joint attaches it"
            )
        else:
            message = (
                f"links {', '.join(names)} are not connected to the ground "
                f"'{ground}' by any chain of joints"
            )
        detached.append((where, message))
    if detached:
        raise StructureError(detached)
    mobility = gruebler_mobility(g)
    if model.loops is not None:
        check_loops(g, model.loops, Location(model.source, path="loops"))
        loops = model.loops
    else:
        loops = independent_loops(g)
    motion = [d for d in model.drivers if d.motion is not None]
    if len(motion) > mobility:
        extra = motion[max(mobility, 0)]
        where = (
            extra.where
            if extra.where.line is not None
            else Location(model.source, path=f"drivers.{extra.name}")
        )
        raise StructureError(
            [
                (
                    where,
                    f"{len(motion)} motion drivers "
                    f"({', '.join(d.name for d in motion)}) but the mobility "
                    f"is {mobility}: give '{extra.name}' an effort instead "
                    "of a motion, or remove it" + _overconstrained_hint(model, g, mobility),
                )
            ]
        )
    with warnings.catch_warnings():
        if len(motion) < mobility:  # undriven links cannot decompose: no news, no warning
            warnings.simplefilter("ignore")
        groups = assur_groups(model, g)
    return Structure(g, mobility, tuple(loops), groups)
