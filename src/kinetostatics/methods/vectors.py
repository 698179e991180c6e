"""The vector equations of velocities and accelerations in textbook form (矢量方程图解法).

At a position, group by group in the order of the solution (the system's Assur plans), each
pair inside a group gives one equation at its point P between its links' two views of P:

    v_P(j) = v_P(i) + v_r,        a_P(j) = a_P(i) + a_r + a_k

where each side expands a link L's point by its *base*: the pair X that ties L to a body K
solved before it (the frame, a driven link, an earlier group):

    v_P(L) = v_X(K) + [v_r of X] + ω_L × XP
    a_P(L) = a_X(K) + [a_r + a_k of X] + a^n_PX (= −ω_L² XP) + a^t_PX (= α_L × XP)

The pair's own terms (nothing for a pin; the sliding velocity, its acceleration and the
Coriolis term 2ω_i × v_r for a slide; the normal term of rolling for a gear or a rack; the
equivalent lower pairs' terms for a cam) come from the joint contract's
``relative_motion``; a pair type that does not write them is named in the group's
``notes``.  A driven group
writes, for each point by which a later body is tied to it, its velocity and acceleration
from its base.  Each term carries its vector (the pipeline's values, global axes), a
direction and a magnitude text (方向/大小), known or "?" before the group is solved, and its
value after; each equation its closure |Σ lhs − Σ rhs| over its largest term (over
:data:`AT_REST` of the position's scale where every term is smaller: a link at rest).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.results import Result
from ..base.geometry import perp
from .records import asked_rows, json_float

__all__ = ["Term", "Equation", "GroupEquations", "VectorPosition", "vector_equations"]

COINCIDENT = 1e-12  # two points closer than this times the mechanism's size are one
AT_REST = 1e-3  # an equation's terms all below this times the position's scale: at rest


@dataclass(frozen=True)
class Term:
    """One term: ``symbol``, ``vector`` (m/s or m/s², global), the 方向 ``direction`` and
    大小 ``magnitude`` texts (the formula; ``?`` where ``known`` is False: an unknown of the
    group, its ``value`` = |vector| being the solved magnitude)."""

    symbol: str
    vector: tuple[float, float]
    direction: str
    magnitude: str
    known: bool

    @property
    def value(self) -> float:
        return float(np.hypot(*self.vector))

    def to_dict(self) -> dict[str, Any]:
        return {
            "symbol": self.symbol,
            "vector": [json_float(c) for c in self.vector],
            "direction": self.direction,
            "magnitude": self.magnitude if self.known else "?",
            "formula": self.magnitude,
            "known": self.known,
            "value": json_float(self.value),
        }


@dataclass(frozen=True)
class Equation:
    """Σ ``lhs`` = Σ ``rhs`` of ``kind`` ``velocity`` or ``acceleration`` at ``point`` (of
    pair ``joint``); ``residual`` = |Σ lhs − Σ rhs| over the largest term's magnitude."""

    kind: str
    joint: str
    point: str
    lhs: tuple[Term, ...]
    rhs: tuple[Term, ...]
    residual: float

    @property
    def text(self) -> str:
        def side(terms):
            return " + ".join(t.symbol for t in terms) or "0"

        return f"{side(self.lhs)} = {side(self.rhs)}"

    def to_dict(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "joint": self.joint,
            "point": self.point,
            "text": self.text,
            "lhs": [t.to_dict() for t in self.lhs],
            "rhs": [t.to_dict() for t in self.rhs],
            "residual": json_float(self.residual),
        }


@dataclass(frozen=True)
class GroupEquations:
    """The equations of one Assur group (``label``, its ``links``), velocities first; the
    ``solved`` unknowns (symbol, value, unit): each link's ω and α and each pair's sliding
    speed and acceleration; ``notes``: the pairs whose terms are not written."""

    label: str
    links: tuple[str, ...]
    equations: tuple[Equation, ...]
    solved: tuple[tuple[str, float, str], ...]
    notes: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "group": self.label,
            "links": list(self.links),
            "equations": [e.to_dict() for e in self.equations],
            "solved": [{"symbol": s, "value": json_float(v), "unit": u} for s, v, u in self.solved],
            "notes": list(self.notes),
        }


@dataclass(frozen=True)
class VectorPosition:
    """The groups' equations at ``row`` (``label``, time ``t``); ``max_residual`` the
    largest closure of them all."""

    label: str
    row: int
    t: float
    groups: tuple[GroupEquations, ...]

    @property
    def max_residual(self) -> float:
        return max((e.residual for g in self.groups for e in g.equations), default=0.0)

    def to_dict(self) -> dict[str, Any]:
        return {
            "label": self.label,
            "row": self.row,
            "t": json_float(self.t),
            "groups": [g.to_dict() for g in self.groups],
            "max_residual": json_float(self.max_residual),
        }


@dataclass(frozen=True)
class _State:
    """One row's link states, ground last: positions ``q``, rates ``v``, accelerations ``a``
    ``(n + 1, 3)``, the links' labels, the bases found so far and the links known."""

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    labels: tuple[str, ...]
    size: float

    def scale(self, acc: bool) -> float:
        """The position's largest speed (or acceleration) of a link's centre of mass or of
        its turning at the mechanism's size: the scale of an equation at rest."""
        if acc:
            w2 = self.v[:, 2] ** 2
            each = np.hypot(self.a[:, 0], self.a[:, 1]) + (np.abs(self.a[:, 2]) + w2) * self.size
        else:
            each = np.hypot(self.v[:, 0], self.v[:, 1]) + np.abs(self.v[:, 2]) * self.size
        return float(np.max(each))

    def point(self, link: int, p: np.ndarray, acc: bool) -> np.ndarray:
        """The velocity (or acceleration) of the point at ``p`` (global) moving with ``link``."""
        r = p - self.q[link, :2]
        w = self.v[link, 2]
        if acc:
            return self.a[link, :2] + self.a[link, 2] * perp(r) - w * w * r
        return self.v[link, :2] + w * perp(r)


def _labels(system) -> tuple[str, ...]:
    """Each link's label in the symbols, ground last: its ``number:`` where it has one,
    else its name in parentheses (v_A(crank))."""
    by_name = {lk.name: lk for lk in system.model.links}
    names = [*system.links, system.model.ground.name]
    return tuple(f"({n})" if by_name[n].number is None else str(by_name[n].number) for n in names)


def _state(result: Result, row: int) -> _State:
    system = result.system
    n = len(system.links)

    def ext(x):
        return np.vstack((np.asarray(x[row], float).reshape(n, 3), np.zeros((1, 3))))

    return _State(
        ext(result.q), ext(result.qd), ext(result.qdd), _labels(system), float(np.max(system.l_ref))
    )


def _motion(system, st: _State, k: int):
    """Pair ``k``'s :class:`RelativeMotion` at the row (None: not written for its type)."""
    i, j = (int(e) for e in system.ends[k])
    joint = system.joints[k]
    qi, qj = (st.q[e] for e in (i, j))
    return joint.relative_motion(
        qi, qj, st.v[i], st.v[j], st.a[i], st.a[j], (st.labels[i], st.labels[j])
    )


def _term(symbol, vector, direction, magnitude, known) -> Term:
    return Term(symbol, (float(vector[0]), float(vector[1])), direction, magnitude, bool(known))


def _pair_terms(motion, sign: float, acc: bool, driven: bool) -> list[Term]:
    """A pair's relative terms, of j relative to i (``sign`` −1: of i relative to j)."""
    out = []
    for t in motion.acceleration if acc else motion.velocity:
        known = driven or not t.rate
        sym = t.symbol if sign > 0 else f"−{t.symbol}"
        out.append(_term(sym, sign * t.vector, t.direction, t.magnitude, known))
    return out


@dataclass(frozen=True)
class _Base:
    """How a link L's points are reached: pair ``k`` with the known body ``K`` (its
    ``motion``; ``sign`` +1 where L is the pair's link j), ``omega_known``: ω_L is known
    before L's group is solved (L turns with K, or L is driven)."""

    k: int
    K: int
    motion: Any
    sign: float
    omega_known: bool


def _bases(system, st: _State, plan, known: set[int], driven: bool) -> dict[int, _Base]:
    """Each member link's base among the plan's pairs with a known body: of those whose
    terms are written, one with its accelerations first, then a lower pair, then a pin,
    then one with the frame (the textbook's pivot)."""
    members = {system.link_index(n) for n in plan.group.links}
    out: dict[int, _Base] = {}
    score: dict[int, tuple] = {}
    ground = len(system.links)
    for k in _pairs(system, plan):
        i, j = (int(e) for e in system.ends[k])
        for L, K, sign in ((j, i, 1.0), (i, j, -1.0)):
            if L not in members or K not in known or (m := _motion(system, st, k)) is None:
                continue
            # a lower pair (two rows) before a higher one: the follower's guide, not its cam
            rank = (m.acceleration is not None, system.joints[k].n_eq == 2, m.turns, K == ground)
            if L not in out or rank > score[L]:
                out[L], score[L] = _Base(k, K, m, sign, driven or not m.turns), rank
    return out


def _pairs(system, plan) -> list[int]:
    """The plan's constraints that are pairs (not motion drivers)."""
    return [k for k in plan.constraints if k < len(system.joints)]


def _about(st: _State, bases: dict, K: int, X: np.ndarray, xn: str, acc: bool) -> tuple[str, str]:
    """方向/大小 of the known point X of body K: about K's pivot on the frame, if it has one."""
    base = bases.get(K)
    ground = len(st.labels) - 1
    if acc or base is None or base.K != ground or not base.motion.turns:
        return "known", "known"
    on = base.motion.name
    return f"⊥{on}{xn}", f"ω{st.labels[K]}·l_{on}{xn}"


def _expand(st: _State, ctx: _Ctx, L: int, P: np.ndarray, pn: str, acc: bool) -> list[Term]:
    """The terms of point P (named ``pn``) of link L from L's base (module docstring)."""
    bases, members, driven = ctx.bases, ctx.members, ctx.driven
    ground, lab = len(st.labels) - 1, st.labels[L]
    pre = "a" if acc else "v"
    if L == ground:
        return []
    base = bases.get(L)
    if base is None:  # no pair with a known body that writes its terms: the point's own
        return [_term(f"{pre}_{pn}{lab}", st.point(L, P, acc), "?", "?", L not in members)]
    X, xn = base.motion.point, base.motion.name
    terms = []
    if base.K != ground:
        direction, magnitude = _about(st, bases, base.K, X, xn, acc)
        terms.append(
            _term(
                f"{pre}_{xn}{st.labels[base.K]}",
                st.point(base.K, X, acc),
                direction,
                magnitude,
                True,
            )
        )
    terms += _pair_terms(base.motion, base.sign, acc, driven)
    r = P - X
    if np.hypot(*r) <= COINCIDENT * st.size:
        return terms
    w_known = L not in members or base.omega_known
    sub = f"{pn}{lab}" if base.K == ground and base.motion.turns and not driven else f"{pn}{xn}"
    w, alpha = st.v[L, 2], st.a[L, 2]
    if not acc:
        return [*terms, _term(f"v_{sub}", w * perp(r), f"⊥{xn}{pn}", f"ω{lab}·l_{xn}{pn}", w_known)]
    normal = _term(f"a^n_{sub}", -w * w * r, f"{pn}→{xn}", f"ω{lab}²·l_{xn}{pn}", True)
    tangent = _term(f"a^t_{sub}", alpha * perp(r), f"⊥{xn}{pn}", f"α{lab}·l_{xn}{pn}", w_known)
    return [*terms, normal, tangent]


def _equation(st: _State, kind: str, joint: str, point: str, lhs, rhs) -> Equation:
    """The equation and its closure |Σ lhs − Σ rhs| over its largest term, or over
    :data:`AT_REST` of the position's scale where every term is smaller (a link at rest:
    its terms are round-off)."""
    total = sum((np.asarray(t.vector) for t in lhs), np.zeros(2))
    total = total - sum((np.asarray(t.vector) for t in rhs), np.zeros(2))
    largest = max((t.value for t in (*lhs, *rhs)), default=0.0)
    largest = max(largest, AT_REST * st.scale(kind == "acceleration"))
    residual = float(np.hypot(*total)) / largest if largest > 0.0 else 0.0
    return Equation(kind, joint, point, tuple(lhs), tuple(rhs), residual)


@dataclass(frozen=True)
class _Ctx:
    """What one group's expansions read: every base found so far (the group's and the
    earlier bodies'), the group's member links, whether it is the driven group."""

    bases: dict
    members: set
    driven: bool
    pair: tuple[int, int] = (-1, -1)  # the links (i, j) of the pair being written


def _inside(st: _State, ctx: _Ctx, joint, motion) -> list[Equation]:
    """A pair of the group that is no member's base (inside the group, or closing it on a
    known body): v_P(j) = v_P(i) + v_r, a_P(j) = a_P(i) + a_r + a_k; the accelerations
    only where every pair they need writes its own."""
    i, j = ctx.pair
    bases = [ctx.bases[L].motion for L in (i, j) if L in ctx.bases]
    accel = all(m.acceleration is not None for m in (motion, *bases))
    out = []
    for acc, kind in ((False, "velocity"), (True, "acceleration"))[: 1 + accel]:
        lhs = _expand(st, ctx, j, motion.point, motion.name, acc)
        rhs = _expand(st, ctx, i, motion.point, motion.name, acc)
        rhs += _pair_terms(motion, 1.0, acc, ctx.driven)
        out.append(_equation(st, kind, joint.name, motion.name, lhs, rhs))
    return out


def _outlet(st: _State, ctx: _Ctx, L: int, joint, motion) -> list[Equation]:
    """A point of driven link L by which a later body is tied to it: its velocity and
    acceleration (the pipeline's) from its base."""
    base = ctx.bases.get(L)
    accel = base is None or base.motion.acceleration is not None
    out = []
    for acc, kind in ((False, "velocity"), (True, "acceleration"))[: 1 + accel]:
        rhs = _expand(st, ctx, L, motion.point, motion.name, acc)
        if not rhs:  # the point is L's pivot on the frame (a flat cam's K on a dwell): at rest
            return []
        one = rhs[0] if len(rhs) == 1 else None
        lhs = _term(
            f"{'a' if acc else 'v'}_{motion.name}{st.labels[L]}",
            st.point(L, motion.point, acc),
            one.direction if one else "known",
            one.magnitude if one else "known",
            True,
        )
        out.append(_equation(st, kind, joint.name, motion.name, [lhs], rhs))
    return out


def _solved(system, st: _State, plan, members: set) -> tuple[tuple[str, float, str], ...]:
    """The group's unknowns after the solve: each pair's sliding speed and acceleration
    (their magnitudes), each member's ω and α (signed, counter-clockwise positive)."""
    out = []
    for k in _pairs(system, plan):
        if (motion := _motion(system, st, k)) is not None:
            out += [(t.symbol, _norm(t.vector), "m/s") for t in motion.velocity if t.rate]
            accel = motion.acceleration or ()
            out += [(t.symbol, _norm(t.vector), "m/s²") for t in accel if t.rate]
    for L in sorted(members):
        out += [
            (f"ω{st.labels[L]}", float(st.v[L, 2]), "rad/s"),
            (f"α{st.labels[L]}", float(st.a[L, 2]), "rad/s²"),
        ]
    return tuple(out)


def _norm(v) -> float:
    return float(np.hypot(v[0], v[1]))


def _group(system, st: _State, plan, known: set[int], bases: dict) -> GroupEquations:
    """One group's equations at the row (module docstring); ``bases`` (every link's so
    far) gains the group's."""
    group = plan.group
    driven = group.kind == "driven"
    members = {system.link_index(n) for n in group.links}
    bases.update(_bases(system, st, plan, known, driven))
    velocity, acceleration = [], []
    done: set[tuple[int, str]] = set()
    own = {b.k for L, b in bases.items() if L in members}
    for k, joint in enumerate(system.joints):
        i, j = (int(e) for e in system.ends[k])
        ctx = _Ctx(bases, members, driven, (i, j))
        later = [L for L, o in ((i, j), (j, i)) if L in members and o not in known | members]
        closing = {i, j} & members and {i, j} <= known | members and k not in own
        if not (closing or (driven and later)) or (motion := _motion(system, st, k)) is None:
            continue
        if closing:
            equations = _inside(st, ctx, joint, motion)
        elif (later[0], motion.name) not in done:
            done.add((later[0], motion.name))
            equations = _outlet(st, ctx, later[0], joint, motion)
        else:
            continue
        velocity += equations[:1]
        acceleration += equations[1:]
    return GroupEquations(
        group.label,
        group.links,
        (*velocity, *acceleration),
        _solved(system, st, plan, members),
        _notes(system, st, plan, members, known),
    )


def _notes(system, st: _State, plan, members: set, known: set[int]) -> tuple[str, ...]:
    """The group's pairs (and a driven group's pairs with later bodies) whose terms are not
    written for their type."""
    out = []
    for k, joint in enumerate(system.joints):
        ends = {int(e) for e in system.ends[k]}
        if not ((k in plan.constraints or ends & members) and ends <= known | members):
            continue
        motion = _motion(system, st, k)
        if motion is None:
            out.append(f"{joint.name} ({joint.kind}): not written for this pair type")
        elif motion.acceleration is None:
            out.append(f"{joint.name} ({joint.kind}): accelerations not written for this pair type")
    return tuple(out)


def vector_equations(result: Result, rows: Sequence) -> tuple[VectorPosition, ...]:
    """The vector equations of ``result`` at ``rows`` (row indices, or ``(label, row)``
    pairs as the course positions give them), group by group in the solution's order."""
    system = result.system
    out = []
    for label, row in asked_rows(result, rows):
        st = _state(result, row)
        known, bases = {len(system.links)}, {}
        groups = []
        for plan in system.plans:
            groups.append(_group(system, st, plan, known, bases))
            known |= {system.link_index(n) for n in plan.group.links}
        out.append(VectorPosition(label, row, float(result.t[row]), tuple(groups)))
    return tuple(out)
