"""Friction: the approximate and the consistent solution.

Each joint with friction applies an effort of link i on link j along its
relative coordinate, ``e = −s·μ(λ)``: μ is the joint's friction magnitude
(ρ|F| or f|N|) computed from its own reaction block λ, s = sign of the
relative speed (0 where |speed| ≤ 1e-9·x_ref, docs/conventions.md).  As a generalized
force it is ``g e`` with g the coordinate gradient, so equilibrium reads

    A x = −Q − Σ_k g_k e_k(x).

(a) *approximate*: e from the frictionless x₀, then one solve.
(b) *consistent*: the solution of the nonlinear equation on the branch
connected to x₀ by the homotopy μ → σμ, σ: 0 → 1.  A fixed-point iteration
from x₀, x ← x₀ + Σ e_k(x) A⁻¹(−g_k) (the n_f columns solved once per position, by
the kinematic block factors when A = Φ_qᵀ; an iteration evaluates the efforts only),
is accepted where it converges (status 0); elsewhere the homotopy is run with Newton
at each σ (status 1; kinetics/homotopy.py, all those positions at once).  A fold of the
branch (sign change of det J) or divergence before σ = 1 is self-locking (status 2, NaN
values).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..base import kernels
from ..base.arrays import entries_first, entries_last, max_abs_last
from ..base.blocks import BlockFactor
from ..structure.system import System, coordinate_gradients
from .homotopy import follow

__all__ = ["FrictionSetup", "setup", "efforts", "approximate", "consistent", "FrictionSolution"]

FIXED_POINT_ITER = 60
TOL = 1e-13


@dataclass
class FrictionSetup:
    """Per-position data that does not change while iterating."""

    joints: list[int]  # indices of joints with friction
    blocks: list[slice]  # their λ slices in x
    grad: np.ndarray  # (..., n_f, n_q) coordinate gradients
    sign: np.ndarray  # (..., n_f) sign of the relative speed (0 at zero speed)
    speed: np.ndarray  # (..., n_f) relative speeds
    zero: np.ndarray  # (...) any frictional joint at zero relative speed
    q: np.ndarray
    pairs: dict = field(default_factory=dict, repr=False)  # joint -> (q_i, q_j), filled on use
    # the solves the two solutions share (:func:`_per_effort`, :func:`approximate`)
    shared: dict = field(default_factory=dict, repr=False)


def setup(system: System, q: np.ndarray, qd: np.ndarray, ref_speed: float) -> FrictionSetup:
    joints = [k for k, j in enumerate(system.model.joints) if j.has_friction]
    blocks = [system.rows_of(k) for k in joints]
    if not joints:
        empty = np.zeros(q.shape[:-1] + (0,))
        return FrictionSetup(
            [],
            [],
            np.zeros(q.shape[:-1] + (0, system.n_q)),
            empty,
            empty,
            np.zeros(q.shape[:-1], dtype=bool),
            q,
        )
    grad = coordinate_gradients(system, q, joints)
    speed = np.einsum("...kn,...n->...k", grad, qd)
    ref = np.stack(
        np.broadcast_arrays(
            *[ref_speed * (1.0 if system.model.joints[k].angular else system.l_ref) for k in joints]
        ),
        axis=-1,
    )
    small = np.abs(speed) <= 1e-9 * ref
    sign = np.where(small, 0.0, np.sign(speed))
    return FrictionSetup(joints, blocks, grad, sign, speed, np.any(small, axis=-1), q)


def efforts(system: System, fs: FrictionSetup, x: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """Signed friction efforts of i on j, ``(..., n_f)``: with NumPy :func:`_minus_efforts`
    negated, with the compiled backend the joints' kernels (the same numbers)."""
    sets = _effort_kernels(system, fs) if kernels.active() and fs.joints else None
    if sets is not None:  # the same numbers (base/kernels.py), each set in one compiled loop
        flat = np.ascontiguousarray(x).reshape(-1, x.shape[-1])
        mu = np.empty((len(fs.joints), flat.shape[0]))
        _magnitudes(sets, flat, mu, _parts(sets, flat.shape[0]))
        return -fs.sign * scale * entries_last(mu, 1).reshape(fs.sign.shape)
    minus = np.empty((len(fs.joints),) + x.shape[:-1])  # every row is written
    minus = _minus_efforts(system, fs, _components(x), minus, scale)
    return np.negative(entries_last(minus, 1), order="C")  # (−s·scale)·μ, to the bit


def _effort_sets(system: System, joints: tuple[int, ...]) -> list[tuple]:
    """The calls of :func:`efforts`, worked out once per system: (the efforts' columns,
    the joint or the stack of a type's joints, their rows of λ, the joints' indices) —
    one column, the joint's rows (a slice) and one index when alone; ``(k,)``, ``(k,
    n_eq)`` and k indices for a stack."""
    key = ("friction_sets", joints)
    sets = system.memo.get(key)
    if sets is None:
        by_type: dict[type, list[int]] = {}
        for n, k in enumerate(joints):
            by_type.setdefault(type(system.model.joints[k]), []).append(n)
        sets = []
        for kind, ns in by_type.items():
            members = [system.model.joints[joints[n]] for n in ns]
            stack = kind.stack_friction(members) if len(ns) > 1 else None
            if stack is None:
                sets += [
                    (n, j, system.rows_of(joints[n]), (joints[n],)) for n, j in zip(ns, members)
                ]
                continue
            rows = np.array(
                [
                    np.arange(system.row_start[joints[n]], system.row_start[joints[n] + 1])
                    for n in ns
                ]
            )
            sets.append((np.array(ns), stack, rows, tuple(joints[n] for n in ns)))
        system.memo[key] = sets
    return sets


def _link_q(system: System, fs: FrictionSetup, ks: tuple[int, ...]):
    """The two links' poses ``(..., 3)`` of joint ``ks[0]``, or ``(..., k, 3)`` of the k
    joints ``ks`` of a stack (ground as zeros)."""
    if ks not in fs.pairs:
        qe = np.concatenate((fs.q, np.zeros(fs.q.shape[:-1] + (3,))), axis=-1)
        pairs = [_pair(qe, system.ends[k]) for k in ks]
        if len(ks) == 1:
            fs.pairs[ks] = pairs[0]
        else:
            fs.pairs[ks] = tuple(np.stack(side, axis=-2) for side in zip(*pairs))
    return fs.pairs[ks]


def _pair(qe: np.ndarray, ends) -> tuple[np.ndarray, np.ndarray]:
    i, j = ends
    return qe[..., 3 * i : 3 * i + 3], qe[..., 3 * j : 3 * j + 3]


def _generalized(fs: FrictionSetup, e: np.ndarray) -> np.ndarray:
    return np.einsum("...kn,...k->...n", fs.grad, e)


def _jacobian_terms(system: System, fs: FrictionSetup) -> list[tuple]:
    """What :func:`_jacobian` reads of each joint with friction, looked up once: (the
    joint, its rows of x, its two links' poses, its sign, its coordinate gradient)."""
    return [
        (system.model.joints[k], b, *_link_q(system, fs, (k,)), fs.sign[..., n, None],
         fs.grad[..., n, :, None])
        for n, (k, b) in enumerate(zip(fs.joints, fs.blocks))
    ]  # fmt: skip


def _jacobian(terms: list[tuple], a: np.ndarray, x: np.ndarray, scale: float) -> np.ndarray:
    """∂/∂x of A x + Σ g_k e_k(x), the joints' ``terms`` as :func:`_jacobian_terms` gives them."""
    jac = a.copy()
    for joint, b, qi, qj, sign, grad in terms:
        de = -sign * scale * joint.friction_gradient(x[..., b], qi, qj)
        jac[..., :, b] += grad * de[..., None, :]
    return jac


def approximate(
    system: System,
    fs: FrictionSetup,
    solve_a,
    q_load: np.ndarray,
    x0: np.ndarray,
    a: np.ndarray | BlockFactor | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(x, friction efforts) of the approximate solution: A x = −Q − Σ g_k e_k(x₀).  Given
    ``a`` (as :func:`consistent` takes it), by the linearity :func:`consistent` uses, x =
    x₀ + Σ e_k(x₀) A⁻¹(−g_k) with the n_f solves it needs anyway (:func:`_per_effort`):
    no solve of its own, and the consistent solution's first iteration, which is this x,
    is not computed again; without, by one solve ``solve_a``."""
    e = efforts(system, fs, x0)
    if a is None:
        return solve_a(-q_load - _generalized(fs, e)), e
    minus_e = np.negative(entries_first(e, 1), order="C")  # component-major
    x_t = _combined(_components(x0), _components(_per_effort(fs, a, solve_a), 2), minus_e)
    fs.shared["first"] = (x0, x_t)
    return np.array(entries_last(x_t, 1), order="C"), e  # a copy: the caller may write it


def _homotopies(system: System, fs: FrictionSetup, a, q_load, x0, failed: np.ndarray):
    """The homotopy (:func:`~kinetostatics.kinetics.homotopy.follow`) at the positions
    where ``failed``, all at once: (their index, then x, status, iterations and reach,
    one row or value each); A the kinematic factors' Φ_qᵀ there, or ``a`` dense.  What the
    Newton iterations read of the joints is taken at all those positions once, and at
    the rows still iterating when fewer are (the same numbers)."""
    index = np.nonzero(failed)
    sub = _rows_of(fs, index)
    a = a.transposed_at(index) if isinstance(a, BlockFactor) else a[index]
    terms, m = _jacobian_terms(system, sub), len(a)
    kept: list = [None, None]  # the last rows asked for, and what they read

    def at(rows):  # (setup, Jacobian terms, A) at the rows; all of them, or the last ones
        if len(rows) == m:
            return sub, terms, a
        if kept[0] is None or not np.array_equal(kept[0], rows):
            some = [(j, b, *(v[rows] for v in arrays)) for j, b, *arrays in terms]
            kept[:] = rows.copy(), (_rows_of(sub, (rows,)), some, a[rows])
        return kept[1]

    def friction(rows, y, s):  # Σ g e(y)·σ: (−s_k μ_k)·σ is (−s_k σ) μ_k to the bit
        part = at(rows)[0]
        return _generalized(part, efforts(system, part, y) * s)

    def jacobian(rows, y, s):
        _, some, a_rows = at(rows)
        return _jacobian(some, a_rows, y, s)

    return index, follow(a, q_load[index], x0[index], friction, jacobian)


def _components(a: np.ndarray, d: int = 1) -> np.ndarray:
    """``a (..., e1 … ed)`` stored component-major, ``(e1 … ed, ...)``, contiguous: a view
    where it is so stored already, else a copy."""
    return np.ascontiguousarray(entries_first(a, d))


def _combined(x0_t: np.ndarray, y_t: np.ndarray, minus_e: np.ndarray, out=None) -> np.ndarray:
    """x₀ + Σ e_k A⁻¹(−g_k) = x₀ + Σ (−e_k) A⁻¹g_k, component-major ``(n_λ, ...)``, from
    x₀, the n_f solves A⁻¹g_k ``(n_f, n_λ, ...)`` (:func:`_per_effort`'s, component-major)
    and the negated efforts ``(n_f, ...)``, all so stored, into ``out`` if given: one
    ``einsum`` pass over contiguous runs, ~2.4× faster over 36,000 positions than the same
    sum over position-major arrays.  Each product (−e_k)·A⁻¹g_k is e_k·A⁻¹(−g_k) to the bit."""
    out = np.einsum("kn...,k...->n...", y_t, minus_e, out=out)
    out += x0_t
    return out


def _per_effort(fs: FrictionSetup, a, solve_a) -> np.ndarray:
    """The n_f vectors A⁻¹g_k as rows ``(..., n_f, n_λ)``, solved once per setup: the
    reactions of a unit effort at each joint are −A⁻¹g_k, the sign carried by the efforts
    where they are combined (:func:`_combined`, :func:`_fixed_point_step`), so that the
    gradients are solved as stored, without a negated copy (A⁻¹g_k is −A⁻¹(−g_k) to the
    bit: every operation of the solves is odd in its right-hand side)."""
    if "per_effort" not in fs.shared:
        with np.errstate(all="ignore"):
            if isinstance(a, BlockFactor):
                per_effort = a.solve_transposed_rows(fs.grad)
            else:
                per_effort = np.moveaxis(solve_a(np.moveaxis(fs.grad, -2, 0)), 0, -2)
        fs.shared["per_effort"] = per_effort
    return fs.shared["per_effort"]


@dataclass
class FrictionSolution:
    x: np.ndarray  # (..., n_lam), NaN where self-locking
    e: np.ndarray  # (..., n_f) friction efforts
    status: np.ndarray  # (...) 0 fixed point, 1 homotopy, 2 self-locking, 3 zero speed
    iterations: np.ndarray  # (...)
    reach: np.ndarray | None = None  # (...) signed margin ±|x₀|/|x|: 1 frictionless, 0 at
    # the edge of a self-locked zone, < 0 inside (NaN unknown)


def consistent(
    system: System,
    fs: FrictionSetup,
    a: np.ndarray | BlockFactor,
    solve_a,
    q_load: np.ndarray,
    x0: np.ndarray,
) -> FrictionSolution:
    """The consistent solution on the branch connected to x₀ (see module docs).  ``a``: A,
    dense, or the kinematic factors where A = Φ_qᵀ (its products by the blocks)."""
    x = x0.copy()
    scale = np.maximum(max_abs_last(x0), 1e-300)
    # A x = −Q − Σ g_k e_k is linear in the efforts: x = x₀ − Σ e_k A⁻¹g_k, with the
    # n_f vectors A⁻¹g_k solved once (as rows, (..., n_f, n_λ)); an iteration then
    # evaluates the efforts only
    per_effort = _per_effort(fs, a, solve_a)
    it = np.zeros(x.shape[:-1], dtype=int)
    converged = np.zeros(x.shape[:-1], dtype=bool)
    live = np.ones(x.shape[:-1], dtype=bool)
    compiled = _effort_kernels(system, fs) if kernels.active() else None
    with np.errstate(all="ignore"):
        if compiled is not None:
            _compiled_fixed_point(compiled, fs, x0, per_effort, scale, x, it, converged, live)
        else:
            x = _fixed_point_in_runs(system, fs, x0, per_effort, scale, x, (it, converged, live))
    status = np.where(fs.zero, 3, 0)
    failed = ~converged
    e = efforts(system, fs, x)  # of the iterates: kept where no homotopy changes them
    with np.errstate(all="ignore"):
        failed |= ~(_residual(fs, a, q_load, x, e) <= 1e-10 * np.maximum(1.0, max_abs_last(q_load)))
    # no frictionless solution (A singular: a dead centre of the effort's joint): the branch
    # has nowhere to start, its reactions are unbounded already at σ = 0 — self-locking
    dead = ~np.all(np.isfinite(x0), axis=-1)
    x[dead], status[dead] = np.nan, 2
    failed &= ~dead
    with np.errstate(all="ignore"):  # |x₀|/|x| (kinetics/homotopy.py; not np.linalg.norm, slow
        # over a short last axis)
        reach = np.sqrt(np.einsum("...i,...i->...", x0, x0) / np.einsum("...i,...i->...", x, x))
    reach[dead] = np.nan
    if failed.any():
        index, (xs, st, n, reach[index]) = _homotopies(system, fs, a, q_load, x0, failed)
        x[index], it[index] = xs, it[index] + n
        status[index] = np.where(fs.zero[index] & (st != 2), 3, st)
    if failed.any() or dead.any():  # x changed there: the efforts at every row again
        e = efforts(system, fs, x)
    fs.shared.clear()  # the setup stays in the result: not its (..., n_f, n_λ) solves
    return FrictionSolution(x, e, status, it, reach)


FIXED_POINT_RUN = 4096
"""Positions per run of the NumPy fixed point at most: each iteration reads the n_f
solves A⁻¹g_k of its run, which then stay in the cache from one iteration to the next
(over 36,000 positions they are ~10 MB, read ~10 times).  A position's iterates do not
depend on the others', so the numbers are the same as in one run (tested); measured
over 36,000 positions, the whole analysis with both friction solutions: the slotting
machine's 179 → 156 ms, the slider-crank's 94 → 91 (runs of 1,024–8,192 alike)."""


def _fixed_point_in_runs(system, fs, x0, per_effort, scale, x, state) -> np.ndarray:
    """:func:`_fixed_point` over runs of :data:`FIXED_POINT_RUN` positions (the last
    axis before the components; a stacked system's variants stay whole), each with
    its setup's rows (:func:`_rows_of`): the same iterates, ``state`` updated in place."""
    n = x0.shape[-2] if x0.ndim > 1 else 0
    if n <= FIXED_POINT_RUN:
        return _fixed_point(system, fs, x0, per_effort, scale, x, state)
    out = np.empty(x.shape)
    first = fs.shared.get("first")
    first = first[1] if first is not None and first[0] is x0 else None
    for a in range(0, n, FIXED_POINT_RUN):
        at = (Ellipsis, slice(a, a + FIXED_POINT_RUN))  # the positions' axis
        one, two = at + (_ALL,), at + (_ALL, _ALL)  # with one or two axes after it
        run, x0_run = _rows_of(fs, at), x0[one]
        if first is not None:  # the approximate solution's x, component-major
            run.shared["first"] = (x0_run, np.ascontiguousarray(first[at]))
        out[one] = _fixed_point(
            system,
            run,
            x0_run,
            per_effort[two],
            scale[at] if np.ndim(scale) else scale,
            x[one],
            tuple(v[at] for v in state),
        )
    return out


_ALL = slice(None)


def _rows_of(fs: FrictionSetup, at: tuple) -> FrictionSetup:
    """The setup at the positions ``at`` (an index of the positions' axes)."""
    return FrictionSetup(
        fs.joints,
        fs.blocks,
        fs.grad[at + (_ALL, _ALL)],
        fs.sign[at + (_ALL,)],
        fs.speed[at + (_ALL,)],
        fs.zero[at],
        fs.q[at + (_ALL,)],
    )


def _fixed_point(system, fs, x0, per_effort, scale, x, state) -> np.ndarray:
    """The fixed point's loop of :func:`consistent` with NumPy: x ← x₀ + Σ e_k A⁻¹(−g_k)
    where live, its step max|Δx|/scale, converged where ≤ TOL, out where converged, not
    finite or diverging; returns x, updates ``state`` = (it, converged, live).  The first
    iteration from x₀ is the approximate solution where :func:`approximate` computed it
    so (the same operations on the same numbers).  The iterates, the efforts and the
    steps are held component-major in buffers of the loop (:func:`_minus_efforts`), each
    pass over contiguous runs of positions."""
    it, converged, live = state
    first = fs.shared.get("first")
    first = first[1] if first is not None and first[0] is x0 else None
    x0_t, x_t, y_t = _components(x0), _components(x), _components(per_effort, 2)
    own = [x_t, np.empty_like(x_t)]  # the iterates' buffers (not the approximate's)
    minus_e, work = np.empty(y_t.shape[:1] + x_t.shape[1:]), np.empty_like(x_t)
    for n in range(FIXED_POINT_ITER):
        if not live.any():
            break
        if n == 0 and first is not None:
            xn_t = first  # read, never written
        else:
            xn_t = own[1] if own[0] is x_t else own[0]
            _combined(x0_t, y_t, _minus_efforts(system, fs, x_t, minus_e), out=xn_t)
        step = np.max(np.abs(np.subtract(xn_t, x_t, out=work), out=work), axis=0)
        step /= scale
        if not live.all():  # the positions out keep their iterate
            if xn_t is first:
                xn_t = np.where(live, xn_t, x_t)
            else:
                np.copyto(xn_t, x_t, where=~live)
        x_t = xn_t
        it += live
        converged |= live & (step <= TOL)
        live &= ~converged & np.isfinite(step) & (step < 1e6)
    return np.array(entries_last(x_t, 1), order="C")  # a copy (of the first iterate too):
    # the caller writes it


def _minus_efforts(system, fs: FrictionSetup, x_t: np.ndarray, out: np.ndarray, scale=1.0):
    """−e_k = s_k·scale·μ_k at the reactions ``x_t`` stored component-major ``(n_λ, ...)``,
    into ``out (n_f, ...)`` (component-major): a type's joints in one call where it stacks
    them (:meth:`~kinetostatics.joints.Joint.stack_friction`), each set's reactions
    gathered as whole rows and its signs kept with the setup (the same each iteration).
    Negated, the efforts (:func:`efforts`): −(s·scale·μ) is (−s·scale)·μ to the bit."""
    for n, (cols, joint, rows, ks) in enumerate(_effort_sets(system, tuple(fs.joints))):
        qi, qj = _link_q(system, fs, ks) if joint.friction_reads_poses else (None, None)
        d = 1 if isinstance(rows, slice) else 2  # a joint alone, or a stack's (k, n_eq)
        key = ("signs", n, scale)
        if key not in fs.shared:
            fs.shared[key] = np.array(entries_first(fs.sign[..., cols] * scale, d - 1), order="C")
        mag = joint.friction_magnitude(entries_last(x_t[rows], d), qi, qj)
        if d == 1:
            np.multiply(fs.shared[key], mag, out=out[cols, ...])  # a view at one position too
        else:
            out[cols] = fs.shared[key] * entries_first(mag, 1)
    return out


# -- the compiled backend (base/kernels.py) ------------------------------------------------
def _effort_kernels(system: System, fs: FrictionSetup) -> list[tuple] | None:
    """The fixed point's efforts by the joints' friction kernels, per set of
    :func:`_effort_sets`: (compiled kernel, its parameters, the rows of λ ``(k, n_eq)``,
    the efforts' columns ``(k,)``); None where a joint has none (then NumPy's loop)."""
    key = ("friction_kernels", tuple(fs.joints))
    if key not in system.memo:
        out: list[tuple] | None = []
        for cols, joint, rows, ks in _effort_sets(system, tuple(fs.joints)):
            kernel, par = type(joint).friction_kernel, joint.friction_kernel_params(len(ks))
            if kernel is None or par is None:
                out = None
                break
            if isinstance(rows, slice):  # a joint alone
                rows, cols = np.arange(rows.start, rows.stop)[None], np.array([cols])
            out.append((kernels.compiled(kernel), par, np.ascontiguousarray(rows), cols))
        system.memo[key] = out
    return system.memo[key]


def _compiled_fixed_point(sets, fs, x0, per_effort, scale, x, it, converged, live) -> None:  # noqa: PLR0913  the arrays the compiled step updates in place
    """The fixed point's loop of :func:`consistent` with the efforts' magnitudes by the
    friction kernels and each iteration's update by :func:`_fixed_point_step`: the same
    operations position by position, so the same numbers to the bit.  Updates ``x``,
    ``it``, ``converged`` and ``live`` (contiguous, as ``consistent`` makes them).  Run
    by runs of :data:`FIXED_POINT_RUN` positions, as NumPy's: a run's A⁻¹g_k stay in the
    cache from one iteration to the next (a position's iterates are its own); the A⁻¹g_k
    read component-major, as they are solved (a copy only for stacked variants)."""
    n_f, n = per_effort.shape[-2], it.size
    flat = x.reshape(n, -1)
    x0 = np.ascontiguousarray(x0).reshape(n, -1)
    per_effort_t = np.ascontiguousarray(np.moveaxis(per_effort.reshape(n, n_f, -1), 0, -1))
    sign_t = np.ascontiguousarray(fs.sign.reshape(n, n_f).T)
    scale = np.ascontiguousarray(np.broadcast_to(scale, it.shape)).reshape(n)
    step = kernels.compiled(_fixed_point_step)
    state = it.reshape(n), converged.reshape(n), live.reshape(n)
    size = min(n, FIXED_POINT_RUN)
    acc = np.empty((per_effort_t.shape[1], size))
    for a in range(0, n, FIXED_POINT_RUN):
        b = min(n, a + FIXED_POINT_RUN)
        mu, parts = np.empty((n_f, b - a)), _parts(sets, b - a)
        for _ in range(FIXED_POINT_ITER):
            _magnitudes(sets, flat[a:b], mu, parts)
            if not step(x0, per_effort_t, mu, sign_t, scale, flat, *state, TOL, a, b, acc):
                break


def _parts(sets, n: int) -> list[np.ndarray]:
    """Work arrays for :func:`_magnitudes`: one ``(k, n)`` per set."""
    return [np.empty((len(cols), n)) for _, _, _, cols in sets]


def _magnitudes(sets, flat: np.ndarray, mu: np.ndarray, parts) -> None:
    """The joints' friction magnitudes at the reactions ``flat (n, n_λ)`` into ``mu (n_f,
    n)``, each set by its kernel (:func:`_effort_kernels`) into its work array."""
    for (kernel, par, rows, cols), part in zip(sets, parts):
        kernel(par, flat, rows, part)
        mu[cols] = part


def _fixed_point_step(x0, per_effort_t, mu, sign_t, scale, x, it, converged, live, tol, a, b, acc):  # noqa: PLR0913  a numba kernel: plain arrays only
    """One iteration at the live positions of the run ``a:b``: x ← x₀ + Σ e_k A⁻¹(−g_k),
    e_k = −s_k μ_k, as x₀ + Σ s_k μ_k A⁻¹g_k (``per_effort_t (n_f, n_λ, n)``: the A⁻¹g_k
    component-major; ``mu (n_f, b − a)``: the run's magnitudes; each product the same to
    the bit, each sum over k in ``einsum``'s order, over the run's positions at once into
    ``acc``), its step max|Δx|/scale, and the tests of ``consistent``; returns how many
    positions of the run stay live."""
    n_f, n_x = per_effort_t.shape[0], per_effort_t.shape[1]
    m = b - a
    e = np.empty(m)
    for c in range(n_x):  # rows as 1-d views: loops the compiler vectorises
        row = acc[c]
        for i in range(m):
            row[i] = 0.0
    for k in range(n_f):
        s_k, mu_k = sign_t[k, a:b], mu[k]
        for i in range(m):
            e[i] = s_k[i] * mu_k[i]
        for c in range(n_x):
            row, g = acc[c], per_effort_t[k, c, a:b]
            for i in range(m):
                row[i] += g[i] * e[i]
    count = 0
    for i in range(m):
        p = a + i
        if not live[p]:
            continue
        worst = 0.0
        for c in range(n_x):
            xn = x0[p, c] + acc[c, i]
            d = abs(xn - x[p, c])
            if d != d or d > worst:  # a NaN stays: nothing is greater
                worst = d
            x[p, c] = xn
        step = worst / scale[p]
        it[p] += 1
        if step <= tol:
            converged[p] = True
        if converged[p] or not (step < 1e6):  # not finite, or diverging
            live[p] = False
        else:
            count += 1
    return count


def _product(a, x: np.ndarray) -> np.ndarray:
    """A x, for A given dense or as the kinematic factors (A = Φ_qᵀ, by their blocks)."""
    if isinstance(a, BlockFactor):
        return a.product_transposed(x)
    return np.einsum("...ij,...j->...i", a, x)


def _residual(fs, a, q_load, x, e):
    """max|A x + Q + Σ g_k e_k| per row, ``e`` the efforts at x: with the kinematic
    factors component-major (each product and Σ g_k e_k whole-array passes over runs of
    positions)."""
    if not isinstance(a, BlockFactor):
        return max_abs_last(_product(a, x) + q_load + _generalized(fs, e))
    r = a.product_transposed_components(_components(x))
    r += entries_first(q_load, 1)
    r += np.einsum("kn...,k...->n...", entries_first(fs.grad), _components(e))
    return np.max(np.abs(r, out=r), axis=0)
