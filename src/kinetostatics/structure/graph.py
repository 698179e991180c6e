"""Structure of a linkage: the joint graph, mobility, loops and Assur groups.

Free functions over a :class:`JointGraph`, a small multigraph whose nodes are
links and whose edges are joints (key = joint name).  Motion drivers are not
edges: they are extra equations on a joint, counted when the Assur groups are
found.  The graph queries (components, cycle basis) are plain Python: they
give the same results, in the same order, as the networkx functions they
replaced (``tests/structure/test_structure_scaling.py`` compares them), without networkx's import
time at the start of every command.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ..errors import Location, StructureError
from ..model import Model
from .cycles import cycle_basis, subdivided

__all__ = [
    "JointGraph",
    "Group",
    "Structure",
    "joint_graph",
    "gruebler_mobility",
    "cyclomatic_number",
    "independent_loops",
    "check_loops",
    "assur_groups",
    "assur_class",
    "structure",
]

MAX_GROUP_SEARCH = 6  # largest group searched for by enumeration
MAX_SEARCH = 5_000_000  # steps of the group search, in all (a few seconds)


class JointGraph:
    """Links as nodes, joints as edges: an undirected multigraph kept in insertion order.

    ``nodes[link]`` holds a link's attributes (``ground``); ``adj[u][v][key]`` the
    attributes (``joint``, ``n_eq``) of joint ``key`` between links u and v, the
    same dictionary seen from both ends.  Iteration orders are networkx's.
    """

    def __init__(self, name: str = "") -> None:
        self.name = name
        self.nodes: dict[str, dict] = {}
        self.adj: dict[str, dict[str, dict[str, dict]]] = {}

    def add_node(self, node: str, **attrs) -> None:
        if node not in self.nodes:
            self.nodes[node], self.adj[node] = {}, {}
        self.nodes[node].update(attrs)

    def add_edge(self, u: str, v: str, key: str, **attrs) -> None:
        self.add_node(u)
        self.add_node(v)
        keys = self.adj[u].get(v)
        if keys is None:
            keys = self.adj[u][v] = self.adj[v][u] = {}
        keys.setdefault(key, {}).update(attrs)

    def edges(self) -> Iterator[tuple[str, str, str, dict]]:
        """Every joint once as ``(u, v, key, attributes)``, in networkx's order."""
        seen = set()
        for u, nbrs in self.adj.items():
            for v, keys in nbrs.items():
                if v not in seen:
                    for key, data in keys.items():
                        yield u, v, key, data
            seen.add(u)

    def number_of_nodes(self) -> int:
        return len(self.nodes)

    def number_of_edges(self) -> int:
        return sum(1 for _ in self.edges())

    def connected_components(self) -> Iterator[set[str]]:
        """The components as sets of links, in the order of their first link."""
        seen: set[str] = set()
        for node in self.nodes:
            if node not in seen:
                part, frontier = {node}, [node]
                while frontier:
                    frontier = [v for u in frontier for v in self.adj[u] if v not in part]
                    part.update(frontier)
                seen |= part
                yield part


@dataclass(frozen=True)
class Group:
    """One solve step: the links found together and the constraints that fix them.

    ``kind`` is ``driven`` (links fixed by motion drivers), ``dyad``, ``triad``
    or ``group``; ``letters`` the dyad's pair string such as ``RRP``; ``order`` the
    group's class (:func:`assur_class`; None for driven links and for a group with a
    higher pair or that is not an Assur group).
    """

    name: str
    kind: str
    letters: str
    links: tuple[str, ...]
    joints: tuple[str, ...]
    drivers: tuple[str, ...]
    order: int | None = None

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

    graph: JointGraph
    mobility: int
    loops: tuple[tuple[str, ...], ...]
    groups: tuple[Group, ...]


def joint_graph(model: Model) -> JointGraph:
    """Links as nodes, joints as edges keyed by joint name (attribute ``joint``)."""
    g = JointGraph(model.name)
    for link in model.links:
        g.add_node(link.name, ground=link.ground)
    for j in model.joints:
        g.add_edge(*j.links, key=j.name, joint=j, n_eq=j.n_eq)
    return g


def gruebler_mobility(g: JointGraph) -> int:
    """Grübler–Kutzbach: 3 per moving link minus the equations of every joint.

    Lower pairs remove 2 freedoms, higher pairs 1.
    """
    moving = sum(1 for d in g.nodes.values() if not d.get("ground"))
    return 3 * moving - sum(d["n_eq"] for *_, d in g.edges())


def cyclomatic_number(g: JointGraph) -> int:
    """Number of independent loops: E − V + (connected components)."""
    components = sum(1 for _ in g.connected_components())
    return g.number_of_edges() - g.number_of_nodes() + components


def independent_loops(g: JointGraph) -> tuple[tuple[str, ...], ...]:
    """A cycle basis as lists of joint names, in traversal order.

    Examples
    --------
    The four-bar has one loop:

    >>> g = JointGraph()
    >>> for link in ["ground", "crank", "coupler", "rocker"]:
    ...     g.add_node(link, ground=link == "ground")
    >>> for name, u, v in [("O", "ground", "crank"), ("A", "crank", "coupler"),
    ...                    ("B", "coupler", "rocker"), ("C", "rocker", "ground")]:
    ...     g.add_edge(u, v, key=name, n_eq=2)
    >>> sorted(independent_loops(g)[0])
    ['A', 'B', 'C', 'O']
    """
    root = next((n for n, d in g.nodes.items() if d.get("ground")), None)
    basis = cycle_basis(subdivided(g.edges()), root)
    return tuple(tuple(n[1] for n in cycle if isinstance(n, tuple)) for cycle in basis)


def _loop_vector(g: JointGraph, loop: tuple[str, ...], index: dict[str, int]) -> np.ndarray | None:
    """Signed edge vector of a closed chain of joints, or None if it is not a cycle."""
    ends = {key: (u, v) for u, v, key, _ in g.edges()}
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


def check_loops(g: JointGraph, loops: tuple[tuple[str, ...], ...], where: Location) -> None:
    """User loops must be closed chains, independent, and as many as the cyclomatic number.

    Independence is a rank test on the signed edge vectors, so any valid basis passes.
    """
    index = {key: k for k, (_, _, key, _) in enumerate(g.edges())}
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
    g: JointGraph, links: tuple[str, ...], joints: list[str]
) -> tuple[str, tuple[str, ...]]:
    """Pair letters of a dyad, external–internal–external, e.g. ``RRP``."""
    a, b = links
    data = {
        key: d["joint"] for x in (a, b) for keys in g.adj[x].values() for key, d in keys.items()
    }

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


def assur_class(links, joints) -> int | None:
    """The class of an Assur group (Ⅱ, Ⅲ, Ⅳ …, as 2, 3, 4): the number of pairs of its
    largest closed contour of internal pairs (pairs between two of its links) — a link
    holding k ≥ 3 internal pairs is a contour of k, a loop of links through internal
    pairs one of as many pairs as it has; a dyad is of class Ⅱ.  ``links``: the group's
    link names; ``joints``: its joints (``links``, ``n_eq``).  None when a joint is not
    a lower pair (n_eq 2) or 3·links ≠ 2·pairs (not an Assur group of lower pairs)."""
    links = set(links)
    if any(j.n_eq != 2 for j in joints) or 3 * len(links) != 2 * len(joints):
        return None
    inner = [tuple(j.links) for j in joints if set(j.links) <= links]
    degree = max((sum(x in e for e in inner) for x in links), default=0)
    best = degree if degree >= 3 else 2

    def walk(start, node, used: frozenset) -> int:  # the longest loop back to start
        longest = 0
        for k, (a, b) in enumerate(inner):
            if k in used or node not in (a, b):
                continue
            other = b if a == node else a
            if other == start:
                longest = max(longest, len(used) + 1)
            elif other > start and all(other not in inner[u] for u in used):
                longest = max(longest, walk(start, other, used | {k}))
        return longest

    for x in sorted(links):
        best = max(best, walk(x, x, frozenset()))
    return best


class _GroupSearch:
    """The search of :func:`assur_groups` for the next group, with its count of the work
    done (at most ``MAX_SEARCH`` steps for the whole decomposition).

    It keeps, from one group to the next, each unknown link's unknown neighbours and what
    its constraints give it (``gains``), and the single links that their constraints fix;
    a group placed changes them only around its own links, so decomposing a long chain
    costs in proportion to its length, not to its square.  Links are numbered in the
    order of ``unknown`` (the links' order), which removing placed links keeps.
    """

    def __init__(
        self, model: Model, g: JointGraph, constraints: list, unknown: list[str], known: set[str]
    ) -> None:
        self.model, self.g, self.constraints = model, g, constraints
        self.steps = 0
        self.names = list(unknown)
        self.known = known
        self.pos = {name: i for i, name in enumerate(unknown)}
        self.alive = dict.fromkeys(range(len(unknown)))  # the unknown links, in order
        pos = self.pos
        self.nbrs = [{pos[v] for v in g.adj.get(u, ()) if v in pos and v != u} for u in unknown]
        self.incident: list[list[int]] = [[] for _ in unknown]  # constraints per link
        self.touching: dict[str, list[int]] = {}  # link (known or not) -> its constraints
        for k, (_, links, _, _) in enumerate(constraints):
            for u in links:
                self.touching.setdefault(u, []).append(k)
                if u in pos:
                    self.incident[pos[u]].append(k)
        self.gains: list[list[tuple[int, int]]] = [[] for _ in unknown]
        self.singles: set[int] = set()
        for v in range(len(unknown)):
            self._gain_of(v)
        self._count(len(unknown) + sum(map(len, self.gains)))

    @property
    def unknown(self) -> list[str]:
        return [self.names[i] for i in self.alive]

    def _gain_of(self, v: int) -> None:
        """Link ``v``'s constraints as (the other link's number, or -1 if known; n_eq),
        and whether they fix it alone."""
        u, pos, known = self.names[v], self.pos, self.known
        gains = []
        for k in self.incident[v]:
            _, links, n_eq, _ = self.constraints[k]
            others = links - {u} or {u}
            o = next(iter(others))
            gains.append((-1 if o in known else pos[o], n_eq))
        self.gains[v] = gains
        if sum(n for o, n in gains if o < 0 or o == v) == 3:
            self.singles.add(v)
        else:
            self.singles.discard(v)

    def place(self, combo: tuple[str, ...]) -> None:
        """``combo``'s links are known from now on."""
        self.known |= set(combo)
        touched: set[int] = set()
        for u in combo:
            v = self.pos[u]
            self.alive.pop(v, None)
            self.singles.discard(v)
            for w in self.nbrs[v]:
                self.nbrs[w].discard(v)
                touched.add(w)
        touched = {w for w in touched if w in self.alive}
        for w in touched:
            self._gain_of(w)
        self._count(len(combo) + sum(len(self.gains[w]) for w in touched))

    def closing(self, subset: set[str]) -> list[tuple[str, set[str], int, bool]]:
        """The constraints on ``subset`` whose links are all in it or known, in order."""
        ks = sorted({k for u in subset for k in self.touching.get(u, ())})
        cs = [self.constraints[k] for k in ks]
        return [c for c in cs if c[1] <= subset | self.known]

    def smallest(self) -> tuple[str, ...] | None:
        """The first connected set of unknown links that its constraints fix exactly, by
        size, then in the order of ``itertools.combinations(unknown, size)``; None if
        none has up to ``MAX_GROUP_SEARCH`` links.

        Only connected sets are examined (:meth:`_sets`), so the cost grows with the
        joints per link, not as the binomial coefficients of the number of links.
        """
        names, nbrs, gains = self.names, self.nbrs, self.gains
        self._count(1)
        if self.singles:  # single links first
            return (names[min(self.singles)],)
        for size in range(2, min(len(self.alive), MAX_GROUP_SEARCH) + 1):
            for v in self.alive:
                best = None  # the first in combinations order: the least sorted numbers
                for members, total in self._sets(v, size, nbrs, gains):
                    if total == 3 * size:
                        key = tuple(sorted(members))
                        best = key if best is None else min(best, key)
                if best is not None:
                    return tuple(names[i] for i in best)
        return None

    def _sets(
        self,
        v: int,
        size: int,
        nbrs: list[set[int]],
        gains: list[list[tuple[int, int]]],
    ) -> Iterator[tuple[tuple[int, ...], int]]:
        """Every connected set of ``size`` positions whose least is ``v``, once each, with
        the equations of the constraints that close it on the known links.

        Wernicke's ESU enumeration: a set grows only by positions above ``v`` that are
        neighbours of the position just added and of no earlier member.  A constraint
        is counted when the last of its unknown links joins the set.
        """

        def gain(members: tuple[int, ...], w: int) -> int:
            self._count(1 + len(gains[w]) + len(nbrs[w]))
            return sum(n for o, n in gains[w] if o < 0 or o in members)

        def extend(members: tuple[int, ...], total: int, ext: list[int], closed: set[int]):
            if len(members) == size:
                yield members, total
                return
            while ext:
                w = ext.pop()
                grown = members + (w,)
                new = [u for u in nbrs[w] if u > v and u not in closed]
                yield from extend(grown, total + gain(grown, w), ext + new, closed | nbrs[w])

        first = [u for u in nbrs[v] if u > v]
        yield from extend((v,), gain((v,), v), first, nbrs[v] | {v})

    def _count(self, steps: int) -> None:
        self.steps += steps
        if self.steps <= MAX_SEARCH:
            return
        unknown = self.unknown
        names = ", ".join(unknown[:6]) + (f", … ({len(unknown)} links)" if len(unknown) > 6 else "")
        first = self.model.link(unknown[0]).where
        where = (
            first
            if first.line is not None
            else Location(self.model.source, path=f"links.{unknown[0]}")
        )
        raise StructureError(
            [
                (
                    where,
                    f"the search for Assur groups gave up after {MAX_SEARCH:,} steps: the "
                    f"links not yet placed ({names}) form too many connected sets of up "
                    f"to {MAX_GROUP_SEARCH} links, none fixed exactly by its joints and motion "
                    "drivers; the linkage is too large or too densely jointed to decompose "
                    "(does it lack motion drivers?)",
                )
            ]
        )


def assur_groups(model: Model, g: JointGraph | None = None) -> tuple[Group, ...]:
    """Decompose relative to the motion-driven links and order the solve.

    Starting from ground, repeatedly take the smallest connected set of unknown
    links that the constraints to known links (joints and motion drivers) fix
    exactly: Σ equations = 3·(links); among sets of that size, the first in the
    links' order.  Sets of up to ``MAX_GROUP_SEARCH`` links are searched, only
    connected ones, with at most ``MAX_SEARCH`` steps in all, beyond which
    :class:`~kinetostatics.errors.StructureError` is raised; what is left over
    when no set closes is solved as one group, with a warning.
    """
    g = joint_graph(model) if g is None else g
    joints = {j.name: j for j in model.joints}
    motion = [d for d in model.drivers if d.motion is not None]
    known = {model.ground.name}
    unknown = [link.name for link in model.moving_links]
    constraints = [(j.name, set(j.links), j.n_eq, False) for j in model.joints]
    constraints += [(d.name, set(joints[d.joint].links), 1, True) for d in motion]
    groups: list[Group] = []
    search = _GroupSearch(model, g, constraints, unknown, known)

    while search.alive:
        combo = search.smallest()
        if combo is None:
            combo = tuple(search.unknown)
            warnings.warn(
                f"links {', '.join(combo)} do not decompose into Assur groups; "
                "they are solved as one group",
                stacklevel=2,
            )
        cs = search.closing(set(combo))
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
        order = None if dnames else assur_class(combo, [joints[n] for n in jnames])
        groups.append(
            Group(
                f"group{len(groups) + 1}",
                kind,
                letters,
                tuple(links),
                tuple(jnames),
                tuple(dnames),
                order,
            )
        )
        search.place(combo)
    return tuple(groups)


def _overconstrained_hint(model: Model, g: JointGraph, mobility: int) -> str:
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
    for part in g.connected_components():
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
    if not motion and mobility < 0:  # nothing to blame on a driver
        raise StructureError(
            [
                (
                    Location(model.source, path="joints"),
                    f"the mobility (Grübler–Kutzbach) is {mobility}: the joints leave the "
                    "links no freedom" + _overconstrained_hint(model, g, mobility),
                )
            ]
        )
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
