"""The compiled evaluation plan of a system: Φ, Φ_q and γ by joint type.

A system's constraints are evaluated in *sets*: all the joints of a type that can stack
(:meth:`~kinetostatics.joints.Joint.stack`) in one call, on poses gathered for all of
them at once, and every other constraint (a driver, a type that does not stack) on its
own.  Where each value goes is fixed when the system is built: its rows of Φ and γ, and
its place in the group blocks of Φ_q (:class:`BlockLayout`) — so an evaluation is one
gather, one call and one scatter per set, whatever the number of joints.  The values
are those of the joints evaluated one by one, to the bit (elementwise operations on the
same numbers).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..base import kernels
from ..base.arrays import entries_first, entries_last
from ..base.kernels import Kernels

__all__ = [
    "ConstraintSet",
    "BlockLayout",
    "STACK_UP_TO",
    "constraint_sets",
    "block_layout",
    "phi_all",
    "gamma_all",
    "jacobian_blocks_all",
]


@dataclass(frozen=True, eq=False)
class ConstraintSet:
    """Constraints evaluated in one call: ``constraint`` (a stacked joint standing for
    ``joints``, or else the single constraint ``members[0]``), the indices ``members`` into
    the system's constraints, their links ``ends (2, k)`` (ground = n_links), their rows
    of Φ ``rows (k, n_eq)``, and ``driver``: the motion driver's column of ψ (or None)."""

    constraint: object
    members: tuple[int, ...]
    ends: np.ndarray
    rows: np.ndarray
    driver: int | None = None
    joints: tuple = ()  # a stack's own joints (two or more); () for a single constraint

    @property
    def stacked(self) -> bool:
        return bool(self.joints)

    def __getstate__(self):  # the poses kept by ``pairs`` and the kernels stay behind
        return {k: v for k, v in self.__dict__.items() if k not in ("_last", "_kernels")}

    def kernels(self) -> Kernels | None:
        """The set's compiled evaluations (base/kernels.py), or None: NumPy's."""
        if "_kernels" not in self.__dict__:
            self.__dict__["_kernels"] = self.constraint.kernels(len(self.members))
        return self.__dict__["_kernels"]

    def pairs(self, pe: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The poses of the members' two links from the system poses ``pe (..., n+1, 5)``:
        ``(..., k, 5)`` each when stacked, else ``(..., 5)``.

        A stack's are gathered (copies); those of read-only poses (the system's, kept
        for the last state) are kept for the next caller — Φ_q and γ of one state."""
        if not self.stacked:
            return pe[..., self.ends[0, 0], :], pe[..., self.ends[1, 0], :]
        last = self.__dict__.get("_last")
        if last is not None and last[0] is pe:
            return last[1]
        out = np.take(pe, self.ends[0], axis=-2), np.take(pe, self.ends[1], axis=-2)
        if not pe.flags.writeable:  # it cannot change while it is held here
            for a in out:
                a.flags.writeable = False
            self.__dict__["_last"] = (pe, out)
        return out


def constraint_sets(
    constraints: Sequence, ends: np.ndarray, row_start: np.ndarray, n_joints: int
) -> tuple[ConstraintSet, ...]:
    """The sets of ``constraints`` (joints first, then ``n_joints`` … motion drivers): the
    joints of a type that stacks together (two or more), everything else alone."""
    by_type: dict[type, list[int]] = {}
    for k, c in enumerate(constraints[:n_joints]):
        by_type.setdefault(type(c), []).append(k)
    sets, alone = [], []
    for kind, members in by_type.items():
        joint = kind.stack([constraints[k] for k in members]) if len(members) > 1 else None
        if joint is None:
            alone += members
            continue
        sets.append(_set(joint, members, ends, row_start, [constraints[k] for k in members]))
    for k in alone:
        sets.append(_set(constraints[k], [k], ends, row_start))
    for k in range(n_joints, len(constraints)):
        sets.append(_set(constraints[k], [k], ends, row_start, driver=k - n_joints))
    return tuple(sets)


def _set(constraint, members, ends, row_start, stack=(), driver=None) -> ConstraintSet:
    """The set of ``constraint`` (a stack of the joints ``stack``, or one constraint)."""
    rows = np.array([np.arange(row_start[k], row_start[k + 1]) for k in members], dtype=int)
    ends = np.ascontiguousarray(ends[members].T)
    return ConstraintSet(constraint, tuple(members), ends, rows, driver, tuple(stack))


STACK_UP_TO = 1024
"""A stack is evaluated in one call up to this many positions; beyond, each of its joints
on its own: the stack's temporaries, k times larger, then leave the cache, and the calls
saved no longer pay for it (a slider-crank's three pins: one call is 1.2× faster at 360
positions, 1.4× slower at 4,000; the slotting machine's five: 1.5× faster, 1.3× slower)."""


def _units(sets, pe: np.ndarray, ve: np.ndarray | None = None, done=()):
    """The calls an evaluation makes: ``(set index, member or None, set, constraint,
    (qi, qj), (vi, vj) or None, rows of Φ)`` — a stack whole, or its joints one by one
    over more than :data:`STACK_UP_TO` positions; the sets ``done`` (indices) left out."""
    many = pe[..., 0, 0].size > STACK_UP_TO
    for n, s in enumerate(sets):
        if n in done:
            continue
        if s.stacked and many:
            for m, (joint, i, j) in enumerate(zip(s.joints, *s.ends)):
                rates = None if ve is None else (ve[..., i, :], ve[..., j, :])
                yield n, m, s, joint, (pe[..., i, :], pe[..., j, :]), rates, s.rows[m]
        else:
            rates = None if ve is None else s.pairs(ve)
            rows = s.rows if s.stacked else s.rows[0]
            yield n, None, s, s.constraint, s.pairs(pe), rates, rows


def phi_all(sets, n_rows: int, pe: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Φ of every constraint, ``(..., n_rows)``, at poses ``pe`` and driver coordinates ψ."""
    out = np.empty(pe.shape[:-2] + (n_rows,))
    for _, _, s, c, (qi, qj), _, rows in _units(sets, pe):
        if s.driver is None:
            out[..., rows] = c.residual(qi, qj)
        else:
            out[..., rows] = c.residual(qi, qj, psi[..., s.driver])
    return out


def gamma_all(sets, n_rows: int, pe: np.ndarray, ve: np.ndarray, psi_dd: np.ndarray) -> np.ndarray:
    """γ of every constraint, ``(..., n_rows)``, at poses ``pe`` and link rates ``ve``
    ``(..., n+1, 3)`` (ground last); stored row-major (each row of γ a contiguous run over
    the positions, as the solves gather them)."""
    out = entries_last(np.empty((n_rows,) + pe.shape[:-2]), 1)
    done = _compiled_gamma(sets, pe, ve, psi_dd, out) if kernels.active() else ()
    for _, _, s, c, (qi, qj), (vi, vj), rows in _units(sets, pe, ve, done):
        if s.driver is None:
            out[..., rows] = c.acceleration_rhs(qi, qj, vi, vj)
        else:
            out[..., rows] = c.acceleration_rhs(qi, qj, vi, vj, psi_dd[..., s.driver])
    return out


@dataclass(frozen=True, eq=False)
class BlockLayout:
    """Where each constraint's Φ_q entries go among the Assur groups' blocks.

    The blocks live in one buffer ``(size + 1, ...)``: group g's diagonal block (its rows
    × its columns) at ``diag[g]``, and its coupling block at ``lower[g]`` (offset, rows,
    columns; None for none): its rows × ``lower_cols[g]``, the earlier groups' columns
    its constraints touch (in solve order) — the only ones where Φ_q has entries, so the
    blocks grow with the links a group is jointed to, not with all the links before it.
    The ground's columns of the joints jointed to it, ``ground`` (offset, rows, 3; None
    for none), follow: the rows ``ground_rows`` in order, × the ground's x, y, θ (the
    shaking force's map, :func:`~kinetostatics.kinetics.reactions.ground_reaction`).
    Row-major; entries of no block (a driver's ground columns) go to the last, spare slot.
    ``dest[s] = (to_i, to_j)``: the slots of set s's two links' entries, ``([k,] n_eq,
    3)`` each."""

    size: int
    diag: tuple[tuple[int, int, int], ...]
    lower: tuple[tuple[int, int, int] | None, ...]
    lower_cols: tuple[np.ndarray, ...]
    dest: tuple[tuple[np.ndarray, np.ndarray], ...]
    ground: tuple[int, int, int] | None = None
    ground_rows: np.ndarray = None
    ground_joints: tuple[int, ...] = ()  # the joints whose rows those are, in order


def block_layout(sets, plans, ends: np.ndarray, ground: int, n_joints: int) -> BlockLayout:
    """The :class:`BlockLayout` of ``sets`` over the group ``plans``; ``ends (n_c, 2)``: each
    constraint's two links, ``ground`` the ground's index there; the first ``n_joints``
    constraints are the joints."""
    slot = {}  # (row of Φ, column of q) -> slot
    diag, lower, lower_cols, at = [], [], [], 0
    done = np.zeros(0, dtype=int)
    for p in plans:
        touched = {3 * int(li) + x for k in p.constraints for li in ends[k] for x in range(3)}
        cols = np.array([c for c in done if c in touched], dtype=int)
        r, c, d = len(p.rows), len(p.cols), len(cols)
        for a, row in enumerate(p.rows):
            for b, col in enumerate(p.cols):
                slot[int(row), int(col)] = at + a * c + b
            for b, col in enumerate(cols):
                slot[int(row), int(col)] = at + r * c + a * d + b
        diag.append((at, r, c))
        lower.append((at + r * c, r, d) if d else None)
        lower_cols.append(cols)
        at += r * (c + d)
        done = np.concatenate((done, p.cols))
    of = {k: r for s in sets for k, r in zip(s.members, s.rows)}  # constraint -> its rows
    touching = tuple(k for k in range(n_joints) if ground in ends[k])
    rows = [row for k in touching for row in of[k]]
    for a, row in enumerate(rows):
        for x in range(3):
            slot[int(row), 3 * ground + x] = at + 3 * a + x
    ground_at = (at, len(rows), 3) if rows else None
    at += 3 * len(rows)
    spare = at
    dest = []
    for s in sets:
        sides = []
        for link in s.ends:
            to = np.array(
                [
                    [
                        [slot.get((int(row), 3 * int(li) + x), spare) for x in range(3)]
                        for row in rows
                    ]
                    for rows, li in zip(s.rows, link)
                ],
                dtype=np.intp,
            )
            sides.append(to if s.stacked else to[0])
        dest.append(tuple(sides))
    return BlockLayout(
        spare,
        tuple(diag),
        tuple(lower),
        tuple(lower_cols),
        tuple(dest),
        ground_at,
        np.array(rows, dtype=int),
        touching,
    )


def jacobian_blocks_all(
    sets, layout: BlockLayout, pe: np.ndarray
) -> tuple[list[tuple[np.ndarray, np.ndarray | None, np.ndarray]], np.ndarray | None]:
    """Φ_q by group, as ``jacobian_blocks`` returns it (diagonal block, coupling block,
    the coupling block's columns), and the ground's block ``(..., rows, 3)`` (None for
    none), at poses ``pe``: each set's two parts added to their zero slots (0 + J: a −0
    is written +0, as a sum onto zeros gives; link j's part onto what is there: zero,
    unless a joint joins a link to itself).

    The buffer is component-major, ``(size + 1, ...)``: each block ``(..., r, c)`` is a
    view with the positions as its fastest axis (long contiguous runs per entry); the
    ground's block is a copy (the small part a caller may keep)."""
    lead = pe.shape[:-2]
    buf = np.zeros((layout.size + 1,) + lead)
    done = _compiled_blocks(sets, layout, pe, buf) if kernels.active() else ()
    for n, m, _, c, pair, _, _ in _units(sets, pe, done=done):
        to_i, to_j = layout.dest[n] if m is None else (d[m] for d in layout.dest[n])
        ji, jj = c.jacobian(*pair)
        buf[to_i] = entries_first(ji, to_i.ndim) + 0.0
        buf[to_j] += entries_first(jj, to_j.ndim)

    back = tuple(range(2, 2 + len(lead))) + (0, 1)  # (r, c, ...) -> (..., r, c)

    def view(at, part=buf):
        if at is None:
            return None
        off, r, c = at
        return part[off : off + r * c].reshape((r, c) + lead).transpose(back)

    ground = None
    if layout.ground is not None:
        off, r, c = layout.ground
        ground = view((0, r, c), buf[off : off + r * c].copy())
    blocks = [
        (view(d), view(lo), cols)
        for d, lo, cols in zip(layout.diag, layout.lower, layout.lower_cols)
    ]
    return blocks, ground


# -- the compiled backend (base/kernels.py) ------------------------------------------------
def _flat(a: np.ndarray, d: int) -> np.ndarray:
    """A component-major array ``(..., e1 … ed)`` as ``(e1 … ed, N)``, the positions on one
    axis (a view where it is stored so, as the system's poses, rates and blocks are)."""
    first = entries_first(a, d)
    return first.reshape(first.shape[:d] + (-1,))


def _compiled_blocks(sets, layout: BlockLayout, pe: np.ndarray, buf: np.ndarray) -> set[int]:
    """The sets that have kernels, their Φ_q entries put in ``buf`` as the NumPy path puts
    them; returns their indices."""
    done, P, flat = set(), None, None
    for n, s in enumerate(sets):
        k = s.kernels()
        if k is None:
            continue
        if P is None:
            P, flat = np.ascontiguousarray(_flat(pe, 2)), buf.reshape(buf.shape[0], -1)
        shape = (len(s.members), s.constraint.n_eq, 3, P.shape[2])
        ji, jj = np.empty(shape), np.empty(shape)
        k.jacobian(P, s.ends, ji, jj)
        to_i, to_j = (d.reshape((-1,) + d.shape[-2:]) for d in layout.dest[n])
        kernels.compiled(kernels.scatter_blocks)(flat, to_i, to_j, ji, jj)
        done.add(n)
    return done


def _compiled_gamma(sets, pe, ve, psi_dd, out) -> set[int]:
    """The sets that have kernels, their rows of γ written in ``out`` (row-major, as
    :func:`gamma_all` stores it); returns their indices."""
    done, P, V, flat, lead = set(), None, None, None, ()
    for n, s in enumerate(sets):
        k = s.kernels()
        if k is None:
            continue
        if P is None:
            P, V = (np.ascontiguousarray(_flat(a, 2)) for a in (pe, ve))
            flat, lead = _flat(out, 1), pe.shape[:-2]
        rows = s.rows.reshape(len(s.members), -1)
        part = np.empty(rows.shape + (P.shape[2],))
        extra = None  # ψ̈ of a motion driver, over the positions as P has them
        if s.driver is not None:
            extra = np.broadcast_to(psi_dd[..., s.driver], lead).reshape(-1)
        k.gamma(P, V, s.ends, extra, part)
        flat[rows] = part
        done.add(n)
    return done
