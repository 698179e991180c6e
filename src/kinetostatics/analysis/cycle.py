"""Means, RMS and peaks over the cycle: the one place every output takes them from.

A mean over the cycle is an integral over time, divided by the span: for a crank at
constant speed the mean over the crank angle.  The quantities jump where a load switches
(a cutting force coming on at its travel band), so a trapezoid rule across the rows is
off by O(step) at every switch.  Here the span is cut wherever a quantity may jump or
kink (:func:`~kinetostatics.analysis.cuts.breaks`), each piece into sub-intervals of at
most 1/36 of the span, and each sub-interval integrated by Gauss–Legendre quadrature
with :data:`NODES` nodes, at which the pipeline is run once (all nodes in one
:func:`~kinetostatics.analysis.pipeline.analyze`).  Between the cuts the quantities are
smooth, so the quadrature is exact to round-off (for a polynomial of degree 2·NODES − 1
on each sub-interval: a few 1e-15 relative).

The cuts (:mod:`~kinetostatics.analysis.cuts`): the jumps — the load events, the
reversals of the resisting loads and of the joints with friction — the corners of the
tables, and the kinks of quantities only the whole pipeline gives (a driving effort
through zero, a friction law's normal force through zero, a cam law's segment end), each
located exactly on the solved state, never by interpolating across a jump.

:func:`cycle_stats` serves ``summary.json`` (``run``), the report, the pictures and the
flywheel: their means agree to round-off.  Its nodes are a record
(:class:`Quadrature`, :func:`cycle_quadrature`): the cycle's stage
(:mod:`~kinetostatics.dynamics.stages`) computes them once and passes them to every
integral over the cycle; nothing is cached on the result.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..errors import AssemblyError
from .cuts import (
    breaks,
    effort_zeros,
    merged_cuts,
    missed_cuts,
    quiet_analyze,
    quiet_friction,
    quiet_near,
    span,
)
from .results import Result

__all__ = [
    "NODES",
    "Quadrature",
    "cycle_nodes",
    "cycle_pieces",
    "cycle_quadrature",
    "cycle_stats",
]

NODES = 8  # Gauss–Legendre nodes per sub-interval
PIECES = 36  # sub-intervals per span at least (each ≤ span/36)
MISSED = 3  # rounds of cuts the nodes found and the rows missed, at most


@dataclass(frozen=True)
class Quadrature:
    """The cycle's quadrature of one result (:func:`cycle_quadrature`): a record, computed
    once by the caller that needs the cycle and passed to every stage that integrates over
    it (the means, the flywheel, the drive), never cached on the result.

    Attributes
    ----------
    weights : ndarray
        The quadrature weights (s), summing to the span, in the nodes' order.
    nodes : Result
        The pipeline's result at the nodes.
    pieces : ndarray or None
        ``(P, 2)``: each (t₀, t₁) holding :data:`NODES` consecutive nodes (None for a run
        of one row).
    friction : bool
        Whether the nodes carry the friction solutions (they then carry every
        frictionless column too).
    rule : tuple of int
        (nodes per piece, pieces per span at least).
    """

    weights: np.ndarray
    nodes: Result
    pieces: np.ndarray | None
    friction: bool
    rule: tuple[int, int]

    def serves(self, friction: bool, rule: tuple[int, int]) -> bool:
        """Whether these nodes give the integrals asked with ``friction`` and ``rule``."""
        return self.rule == rule and (self.friction or not friction)


def _asked(result: Result, friction: bool | None, quadrature) -> tuple[bool, tuple[int, int]]:
    if friction is None:
        friction = "friction.status" in result.columns
    return bool(friction), tuple(quadrature) if quadrature is not None else (NODES, PIECES)


def cycle_nodes(
    result: Result,
    *,
    friction: bool | None = None,
    quadrature: tuple[int, int] | None = None,
    given: Quadrature | None = None,
) -> tuple[np.ndarray, Result]:
    """(weights, node result): the quadrature weights (s, summing to the span) and the
    result of the pipeline at the nodes.  ``friction``: solve the friction solutions at
    the nodes (default: when the result has them); ``quadrature``: (nodes per piece,
    pieces per span at least), default (:data:`NODES`, :data:`PIECES`) — another only to
    check that the means have converged; ``given``: nodes already computed
    (:func:`cycle_quadrature`), used when they serve."""
    return cycle_pieces(result, friction=friction, quadrature=quadrature, given=given)[:2]


def cycle_pieces(
    result: Result,
    *,
    friction: bool | None = None,
    quadrature: tuple[int, int] | None = None,
    given: Quadrature | None = None,
) -> tuple[np.ndarray, Result, np.ndarray | None]:
    """(weights, node result, pieces): :func:`cycle_nodes` with the pieces ``(P, 2)``, each
    (t₀, t₁) holding :data:`NODES` consecutive nodes (None for a run of one row)."""
    q = cycle_quadrature(result, friction=friction, quadrature=quadrature, given=given)
    return q.weights, q.nodes, q.pieces


def cycle_quadrature(
    result: Result,
    *,
    friction: bool | None = None,
    quadrature: tuple[int, int] | None = None,
    given: Quadrature | None = None,
) -> Quadrature:
    """The cycle's quadrature of ``result`` (:class:`Quadrature`): ``given`` when it serves
    (the nodes with friction serve a frictionless integral too), else computed.

    Parameters
    ----------
    result : Result
        The analysis.
    friction : bool, optional
        Solve the friction solutions at the nodes (default: when the result has them).
    quadrature : tuple of int, optional
        (nodes per piece, pieces per span at least), default (:data:`NODES`,
        :data:`PIECES`); another only to check that the means have converged.
    given : Quadrature, optional
        Nodes already computed by the caller.

    Returns
    -------
    Quadrature
        The weights, the node result and the pieces.
    """
    friction, rule = _asked(result, friction, quadrature)
    if given is not None and given.serves(friction, rule):
        return given
    n_nodes, n_pieces = rule
    ta, tb = span(result)
    if not tb > ta:  # one row: its values
        return Quadrature(np.ones(len(result.t)), result, None, friction, rule)
    x, w = np.polynomial.legendre.leggauss(n_nodes)
    edges = breaks(result, ta, tb, friction)
    # the pieces are chosen on the frictionless efforts (cheap: no friction solution at
    # the nodes, which at self-locked nodes is a homotopy each), then the nodes analysed
    # once as asked; a switch or kink the rows missed (a pair between two rows) but the
    # nodes see is cut too, and the nodes placed again (switches first, then kinks)
    grouped, times, weights, nodes = _placed(result, edges, n_pieces, x, w)
    for _ in range(MISSED):
        missed = missed_cuts(result, nodes, edges, friction, n_nodes)
        if not missed:
            break
        edges = merged_cuts(ta, tb, [*edges, *missed])
        grouped, times, weights, nodes = _placed(result, edges, n_pieces, x, w)
    order = np.argsort(times, kind="stable")  # the pipeline returns rows in time order
    again, same = friction, False
    if not np.allclose(nodes.t, times[order], rtol=0, atol=1e-9 * (tb - ta)):
        order, grouped = np.arange(len(times)), None
    elif len(grouped):
        finer = _resolved(result, nodes, grouped, x, w, False)
        same = finer is None  # the nodes stay: with friction, only the kinetics is solved
        if finer is not None:  # pieces halved where the efforts were not resolved
            grouped, again = finer, True
            times, weights = _nodes_of(grouped, x, w)
            order = np.argsort(times, kind="stable")
    if again and not same:
        nodes = quiet_analyze(result.system, times=times, friction=friction, events=False)
    elif again:  # the same nodes with the friction solutions: their motion kept, to the bit
        nodes = quiet_friction(nodes)
    if friction and grouped is not None and len(grouped):
        # the efforts with friction: a pin force passing close to zero gives ρ|F| a sharp
        # though smooth minimum, which the frictionless efforts do not show
        finer = _resolved(result, nodes, grouped, x, w, True)
        if finer is not None:
            nodes = _with_halves(result, nodes, grouped, finer, x, w)
            grouped = finer
            times, weights = _nodes_of(grouped, x, w)
            order = np.argsort(times, kind="stable")
    return Quadrature(weights[order], nodes, grouped, friction, rule)


def _with_halves(result: Result, nodes: Result, pieces, finer, x, w) -> Result:
    """The node result (with friction, in time order) of the pieces ``finer``: the rows of
    ``nodes`` (of ``pieces``) for the pieces kept, the new pieces' nodes analysed (only
    they: the friction solution is row by row)."""
    old, now = {tuple(p) for p in pieces.tolist()}, {tuple(p) for p in finer.tolist()}
    new = np.array([p for p in finer.tolist() if tuple(p) not in old]).reshape(-1, 2)
    gone = np.array([tuple(p) not in now for p in pieces.tolist()])
    order = np.argsort(_nodes_of(pieces, x, w)[0], kind="stable")  # row r: node order[r]
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))  # node j (piece by piece): row rank[j]
    keep = np.ones(len(nodes), dtype=bool)
    keep[rank[np.repeat(gone, len(x))]] = False
    times = np.sort(_nodes_of(new, x, w)[0])
    try:  # each continued from its nearest node (as the halves were when chosen), not the
        # whole run's continuation from the start pose
        part = quiet_near(nodes, times, friction=True)
    except AssemblyError:
        part = quiet_analyze(result.system, times=times, friction=True, events=False)
    want = np.sort(_nodes_of(finer, x, w)[0])
    both = np.argsort(np.concatenate((nodes.t[keep], part.t)), kind="stable")
    if len(part) != len(times) or len(both) != len(want):  # not row by row: all again
        return quiet_analyze(result.system, times=want, friction=True, events=False)

    def join(a, b):
        return None if a is None else np.concatenate((a[keep], b))[both]

    return replace(
        nodes,
        **{k: join(getattr(nodes, k), getattr(part, k)) for k in _ROW_FIELDS},
        columns={c: join(np.asarray(v), np.asarray(part[c])) for c, v in nodes.columns.items()},
    )


_ROW_FIELDS = ("t", "coordinate", "q", "qd", "qdd", "lam", "lam_friction")


def _placed(result: Result, edges: np.ndarray, n_pieces: int, x: np.ndarray, w: np.ndarray):
    """(pieces, times, weights, frictionless node result): the stretches between the cuts
    ``edges`` divided into pieces of at most 1/``n_pieces`` of the span, and the
    Gauss–Legendre rule (nodes ``x``, weights ``w``) on each."""
    width = (edges[-1] - edges[0]) / n_pieces
    pieces = []
    for a, b in zip(edges[:-1], edges[1:]):
        m = max(1, int(np.ceil((b - a) / width - 1e-9)))
        cuts = np.linspace(a, b, m + 1)
        pieces += list(zip(cuts[:-1], cuts[1:]))
    grouped = np.array(pieces)
    times, weights = _nodes_of(grouped, x, w)
    nodes = quiet_analyze(result.system, times=times, friction=False, events=False)
    return grouped, times, weights, nodes


RESOLVED = 1e-13  # of an effort's largest |value|: a piece's predicted quadrature error
SPLITS = 8  # a piece is halved at most this many times (to 1/256 of it)
SURE = 5  # … beyond this many times only while its predicted error falls
CONVERGING = 0.5  # by this factor at least per halving


def _nodes_of(pieces: np.ndarray, x: np.ndarray, w: np.ndarray):
    """(times, weights) of the Gauss–Legendre rule (nodes ``x``, weights ``w`` on
    [−1, 1]) on each piece (t₀, t₁), piece after piece."""
    half = 0.5 * (pieces[:, 1] - pieces[:, 0])
    times = pieces[:, :1] + half[:, None] * (x + 1.0)
    return times.ravel(), (half[:, None] * w).ravel()


def _unresolved(nodes: Result, x: np.ndarray, scales: list[float]) -> np.ndarray:
    """Per piece of ``nodes`` (n consecutive nodes each), whether the quadrature may be off
    by more than :data:`RESOLVED` of an effort's scale: from the Legendre coefficients
    c_k of the interpolant through its n values, decaying like ρ^k from the head (c_0…c_2)
    to the tail (c_{n−2}, c_{n−1}), the rule's error is about that of c_{2n} ≈
    tail·ρ^{n+1}.  A smooth effort's pieces are resolved (ρ ~ 0.1); a sharp peak beside a
    singular position is not (ρ ~ 0.4, the two orders then differ by 1e-9)."""
    return _predicted(nodes, x, scales) > RESOLVED


def _predicted(nodes: Result, x: np.ndarray, scales: list[float]) -> np.ndarray:
    """Per piece, the largest predicted quadrature error of an effort over its scale
    (:func:`_unresolved`; 0 where not finite, and for a piece not solved by the friction
    fixed point at every node)."""
    n = len(x)
    inv = np.linalg.inv(np.polynomial.legendre.legvander(x, n - 1))
    out = np.zeros(len(nodes) // n)
    for fn, scale in zip(effort_zeros(nodes), scales):
        v = np.asarray(fn(nodes), dtype=float).reshape(-1, n)
        c = np.abs(v @ inv.T)
        tail, head = np.max(c[:, -2:], axis=1), np.max(c[:, :3], axis=1)
        before = np.max(c[:, -4:-2], axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = (tail / head) ** (1.0 / (n - 2))
            # the tail's own decay, where it is slower: a small near-kink on a large smooth
            # effort (a pin's ρ|F| through a sharp minimum) leaves the tail on a plateau
            # the decay from the head does not see (seed 1003614: predicted 4e-14, 1e-9)
            rho = np.fmax(rho, np.minimum(np.sqrt(tail / before), 1.0))
            err = tail * rho ** (n + 1) / scale
        out = np.maximum(out, np.where(np.isfinite(err), err, 0.0))
    if "friction.status" in nodes.columns:
        # with friction, only pieces solved by the fixed point (or at zero speed) at every
        # node: near a self-locking zone the efforts run to a pole that no halving
        # resolves, and each halving there costs a homotopy per node
        status = np.asarray(nodes["friction.status"], dtype=float).reshape(-1, n)
        out = np.where(np.all((status == 0) | (status == 3), axis=1), out, 0.0)
    return out


def _resolved(result: Result, nodes: Result, pieces, x, w, friction: bool):
    """The pieces halved (at most :data:`SPLITS` times) until the driving efforts of
    ``nodes`` are resolved on each (:func:`_unresolved`), or None when they already are;
    the halves analysed with ``friction`` or without."""
    scales = []
    for fn in effort_zeros(nodes):
        v = np.abs(np.asarray(fn(nodes), dtype=float))
        scales.append(float(np.max(v[np.isfinite(v)], initial=0.0)))
    err = _predicted(nodes, x, scales)
    bad = err > RESOLVED
    if not SPLITS or not bad.any():
        return None
    done, pending, before = [pieces[~bad]], pieces[bad], err[bad]
    for level in range(SPLITS):
        mid = 0.5 * (pending[:, 0] + pending[:, 1])
        halves = np.column_stack(
            (
                np.ravel(np.column_stack((pending[:, 0], mid))),
                np.ravel(np.column_stack((mid, pending[:, 1]))),
            )
        )
        if level == SPLITS - 1:
            done.append(halves)
            break
        times = _nodes_of(halves, x, w)[0]
        try:  # each position continued from the nearest node of the piece it halves: the
            # rows may be too far apart near a dead point, where two branches come close
            part = quiet_near(nodes, times, friction=friction)
        except AssemblyError:
            part = quiet_analyze(result.system, times=times, friction=friction, events=False)
        if len(part) != len(times) or not np.array_equal(part.t, times):
            done.append(halves)
            break
        err = _predicted(part, x, scales)
        bad = err > RESOLVED
        if level >= SURE - 1:  # beyond SURE halvings only while the error falls: a pole
            # (an effort through infinity at a dead point) is not resolved by halving
            bad &= err < CONVERGING * np.repeat(before, 2)
        done.append(halves[~bad])
        pending, before = halves[bad], err[bad]
        if not len(pending):
            break
    out = np.concatenate(done)
    return out[np.argsort(out[:, 0], kind="stable")]


def cycle_stats(
    result: Result,
    what: Mapping[str, str | Callable[[Result], np.ndarray]] | list[str],
    *,
    friction: bool | None = None,
    quadrature: tuple[int, int] | None = None,
    given: Quadrature | None = None,
) -> dict[str, dict[str, Any]]:
    """Mean, RMS and peak |·| over the run (a full cycle: one period) of each quantity.

    ``what``: column names, or ``{label: column name or function(Result) -> values}``
    (a function is evaluated on the result at the quadrature nodes).  Returns ``{label:
    {"mean", "rms", "peak", "covered"}}``: ``covered`` is the fraction of the span where
    the value exists; a mean and RMS are over that part (NaN when it is empty: a friction
    column of a machine self-locked everywhere); ``peak`` is the largest |value| at the
    analysed rows (as the batch table's), at the nodes for a function the rows lack.
    ``quadrature``, ``given``: as for :func:`cycle_quadrature` (a caller that integrates
    more than once computes the nodes once and passes them).
    """
    if not isinstance(what, Mapping):
        what = {name: name for name in what}
    weights, nodes = cycle_nodes(result, friction=friction, quadrature=quadrature, given=given)
    out = {}
    for label, source in what.items():
        if callable(source):
            v = np.asarray(source(nodes), dtype=float)
            try:
                rows = np.asarray(source(result), dtype=float)
            except KeyError:  # a column the rows lack (friction asked of a frictionless run)
                rows = np.zeros(0)
        else:
            v = np.asarray(nodes[source], dtype=float)
            rows = np.asarray(result[source], dtype=float)
        ok = np.isfinite(v)
        total = float(np.sum(weights))
        covered = float(np.sum(weights[ok])) / total if total > 0 else 0.0
        if ok.any():
            wk = weights[ok]
            mean = float(np.sum(wk * v[ok]) / np.sum(wk))
            rms = float(np.sqrt(np.sum(wk * v[ok] ** 2) / np.sum(wk)))
        else:
            mean = rms = float("nan")
        # the peak at the analysed rows (the batch table's too): the rows are where the
        # values are reported; with no finite row, at the nodes
        finite = rows[np.isfinite(rows)] if rows.size else v[ok]
        peak = float(np.max(np.abs(finite))) if finite.size else float("nan")
        out[label] = {"mean": mean, "rms": rms, "peak": peak, "covered": covered}
    return out
