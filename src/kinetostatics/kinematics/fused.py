"""The kinematic plan fused per position: the derivative stage on the compiled backend.

:mod:`.plan` writes a system's velocity and acceleration stage as whole-array lines;
here the same stage is traced, scalar by scalar, into one straight-line program
(base/program.py) that the compiled backend runs position by position over blocks of
positions — no NumPy call per operation, and no temporaries over all the positions:

- Φ_q's entries by the constraint sets' ``jacobian_kernel`` (a motion driver's by its
  joint's ``direction_kernel``), each to its slot of the system's block layout, as the
  plan puts them;
- each group's diagonal block inverted as :func:`~kinetostatics.base.linalg.small_inverse`
  inverts it (:func:`~kinetostatics.base.linalg.traced_inverse`: up to 3×3 the adjugate
  over the determinant, larger by the elimination in the row order partial pivoting
  picks for the first position the plan was made at) — a position where a pivot fails
  its test, or a determinant is zero, sends the whole call to the NumPy plan, which
  inverts that matrix by LAPACK;
- the groups' condition numbers (but the driven groups'), the norms of
  :func:`~kinetostatics.kinematics.newton.condition_number` as
  :func:`~kinetostatics.kinematics.newton.traced_condition` writes them, on the blocks
  and inverses still in registers, handed on with the factors (``BlockFactor.conditions``);
- q̇ and q̈ by the forward substitutions over the groups, γ by the sets' ``gamma_kernel``
  (a driver's ψ̈ less its joint's ``bias_kernel``) on the links' rates just solved.

Every constraint set must have whole-array kernels (revolute and prismatic pairs and the
drivers on them); a system with another (a cam, a gear pair) keeps the NumPy plan.  The
program writes what the NumPy plan writes — Φ_q's entries, the blocks' inverses, q̇, q̈
— and the condition numbers into one output whose rows the stage hands on as the same
views, so the stages after it cannot tell them apart (up to :data:`FACTORS_UP_TO`
positions); for the kinematics alone a second program writes q̇, q̈ and the conditions
only, the factors kept in its registers.  The numbers agree to round-off
(the row order of an elimination may differ from the call's own first position;
tests/kinematics/test_fused.py holds every column to 1e-12 of its scale).
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from ..base import program
from ..base.linalg import PIVOT_RATIO, traced_inverse
from ..base.trace import Leaves, Lines, Sym, larger, magnitude, operand, pruned, traced_kernel
from ..structure.evaluation import jacobian_blocks_all
from ..structure.system import System
from .newton import traced_condition
from .plan_params import driver_params

__all__ = ["FACTORS_UP_TO", "FusedPlan", "fused_plan", "fused_derivatives"]

KEY = "fused kinematic plan"
RATES_KEY = "fused kinematic plan, rates only"
FACTORS_UP_TO = 3000
"""The most positions the fused stage is run for when the factors are asked for (the
rates alone: any number).  It then writes Φ_q's entries and the inverses for the stages
after it, which solve with them (from 1,024 positions by the plan's written-out
transposed solves), and gains little over the NumPy plan from a few thousand positions
on: a frictionless analysis through the NumPy plan above 3,000 positions took 0.95–1.04×
its time through the fused stage at 4,000–20,000 positions and 0.93× at 36,000
(tests/benchmarks/bench_baseline.py --numba, this tree against one without the limit,
glibc's allocator held warm; with its defaults the fused stage was ahead by up to 18 % at
4,000–10,000 positions on the slider-crank, in runs varying by ±25 %)."""


@dataclass(frozen=True, eq=False)
class FusedPlan:
    """A system's derivative stage as a program: ``source`` (its lines), ``program`` (as
    assembled), and the output's rows: Φ_q's entries first (the block layout's buffer),
    then each group's inverse (its k² entries, entry-major) at ``inverses``, the groups'
    condition numbers (:func:`~kinetostatics.kinematics.newton.condition_number`, but
    the driven groups') at ``conditions``, q̇ at ``rates`` and q̈ after it."""

    source: str
    program: program.Program
    inverses: tuple[int, ...]
    conditions: tuple[tuple[int, int], ...]  # (group, its row) of each condition number
    rates: int


class _NotFused(Exception):
    """The stage cannot be written as a program for this system."""


def fused_plan(system: System, pe: np.ndarray, factors: bool = True) -> FusedPlan | None:
    """The system's :class:`FusedPlan`, made on first use (``pe``: the poses of the call
    that makes it, whose first finite position picks the eliminations' row orders) and
    kept with it; None where the stage cannot be fused."""
    key = KEY if factors else RATES_KEY
    if key not in system.memo:
        try:
            system.memo[key] = _generate(system, pe, factors)
        except (_NotFused, TypeError, ZeroDivisionError):  # a kernel branched; a 1/0
            system.memo[key] = None
    return system.memo[key]


def fused_derivatives(
    system: System, pe: np.ndarray, psi_d: np.ndarray, psi_dd: np.ndarray, factors: bool = True
) -> tuple[np.ndarray | None, list[np.ndarray] | None, np.ndarray, np.ndarray, dict] | None:
    """(Φ_q's entries ``(size + 1, N)``, the groups' inverses ``(k, k, N)``, q̇ and q̈
    ``(n_q, N)``, the groups' condition numbers ``{g: (N,)}``) at the poses ``pe (N, n +
    1, 5)``, as the NumPy plan and ``condition_number`` give them; None where the system
    has no fused plan, a position failed a pivot's test, or the factors are asked for at
    more than :data:`FACTORS_UP_TO` positions.  Without ``factors`` the program stores
    neither Φ_q's entries nor the inverses (None for both): they stay in its registers,
    and the rates and conditions are the output's only rows."""
    n = pe.shape[0]
    if factors and n > FACTORS_UP_TO:
        return None
    plan = fused_plan(system, pe, factors)
    if plan is None:
        return None
    out = np.zeros((plan.program.rows, n))  # a zero is not stored by the program: over
    # 36,000 positions storing them (half the rows) took longer than the zeroed memory
    inputs = (
        np.ascontiguousarray(pe.transpose(1, 2, 0)),
        np.ascontiguousarray(psi_d.T)[:, None, :],
        np.ascontiguousarray(psi_dd.T)[:, None, :],
    )
    if program.run(plan.program, inputs, out):
        return None
    n_q, at = system.n_q, plan.rates
    conditions = {g: out[row] for g, row in plan.conditions}
    if not factors:
        return None, None, out[at : at + n_q], out[at + n_q :], conditions
    inv = [
        out[at : at + len(p.cols) ** 2].reshape(len(p.cols), len(p.cols), n)
        for at, p in zip(plan.inverses, system.plans)
    ]
    return out[: plan.inverses[0]], inv, out[at : at + n_q], out[at + n_q :], conditions


def _zero(x) -> bool:
    return isinstance(x, numbers.Real) and x == 0.0


class _Rates:
    """The kernels' ``V (n + 1, 3, 1)`` when traced over the rates the program solved:
    entry ``[i, c, 0]`` is q̇'s column 3i + c, the ground's 0."""

    def __init__(self, qd: dict, n_links: int):
        self.qd, self.ground = qd, n_links
        self.shape = (n_links + 1, 3, 1)

    def __getitem__(self, key):
        i, c, _ = key
        return 0.0 if i == self.ground else self.qd.get(3 * i + c, 0.0)


def _generate(system: System, pe: np.ndarray, factors: bool = True) -> FusedPlan:
    layout = system.layout
    if layout is None:
        raise _NotFused
    lines = Lines()
    n_links = len(system.links)
    poses = Leaves(lines, "PE", n_links, (0.0, 0.0, 0.0, 1.0, 0.0))
    kinds = [_kernels(s) for s in system.sets]
    slots: dict[int, object] = {}  # Φ_q's entries by their slot
    for s, (jac, _, par), (to_i, to_j) in zip(system.sets, kinds, layout.dest):
        shape = (len(s.members),) + s.rows.shape[-1:] + (3, 1)
        if s.driver is not None:  # the joint's direction: one row
            shape = (1, 3, 1)
        ji, jj = traced_kernel(jac, (shape, shape), par, poses, s.ends)
        for at, v in zip(to_i.reshape(-1).tolist(), ji.reshape(-1).tolist()):
            if not _zero(v):  # as the plan: Φ_q's zeros are the buffer's
                slots[at] = v
        for at, v in zip(to_j.reshape(-1).tolist(), jj.reshape(-1).tolist()):
            if not _zero(v):
                slots[at] = slots.get(at, 0.0) + v
    slots.pop(layout.size, None)  # the spare slot: entries of no block
    body: list[str] = []
    _emit(body, lines, slots if factors else {})  # stored once computed: fewer registers
    finite = np.all(np.isfinite(pe), axis=(-2, -1))  # the first assembled position's
    k = int(np.argmax(finite))  # blocks pick the row orders (a NaN row would pick badly)
    first = jacobian_blocks_all(system.sets, layout, pe[k : k + 1])[0]
    inverses, inv, at = [], [], layout.size + 1 if factors else 0
    for (off, r, c), (d, _, _) in zip(layout.diag, first):
        m = [[slots.get(off + i * c + j, 0.0) for j in range(c)] for i in range(r)]
        block = traced_inverse(m, np.asarray(d)[0], lambda test: _check(lines, test))
        if block is None:
            raise _NotFused
        inv.append(block)
        if not factors:
            continue
        inverses.append(at)
        _emit(
            body,
            lines,
            {at + i * c + j: v for i, row in enumerate(block) for j, v in enumerate(row)},
        )
        at += r * c
    conditions = []
    for g, ((off, r, c), p) in enumerate(zip(layout.diag, system.plans)):
        if p.group.kind != "driven":  # as the analysis asks for them (analysis/pipeline.py)
            m = [[slots.get(off + i * c + j, 0.0) for j in range(c)] for i in range(r)]
            _emit(body, lines, {at: traced_condition(lines, m, inv[g], float(system.l_ref))})
            conditions.append((g, at))
            at += 1
    qd = _substitution(system, slots, inv, lambda g, a, row: _nu(system, lines, row))
    _emit(body, lines, {at + col: v for col, v in qd.items()})
    gamma = _gamma(system, kinds, lines, poses, _Rates(qd, n_links))
    qdd = _substitution(system, slots, inv, lambda g, a, row: gamma.get(row, 0.0))
    _emit(body, lines, {at + system.n_q + col: v for col, v in qdd.items()})
    body = pruned(body)
    rows = at + 2 * system.n_q
    assembled = program.assembled(body, rows)
    return FusedPlan("\n".join(body) + "\n", assembled, tuple(inverses), tuple(conditions), at)


def _emit(body: list[str], lines: Lines, stores: dict) -> None:
    """The lines traced since the last, then the stores of ``stores`` (output row ->
    value; a zero is the output's already)."""
    body += lines.take()
    body += [f"    out[{row}] = {operand(v)}" for row, v in sorted(stores.items()) if not _zero(v)]


def _kernels(s):
    """(Φ_q's kernel, γ's kernel, their parameters) of set ``s``: a joint type's
    ``jacobian_kernel`` and ``gamma_kernel`` where they hold over whole arrays, a motion
    driver's joint's ``direction_kernel`` and ``bias_kernel``."""
    if s.driver is not None:  # as the NumPy plan traces a driver's row
        par = driver_params(s)
        if par is None:
            raise _NotFused
        cls = type(s.constraint.joint)
        return cls.direction_kernel, cls.bias_kernel, par
    cls = type(s.constraint)
    if not getattr(cls, "whole_array_kernels", False):
        raise _NotFused
    jac, gam = cls.jacobian_kernel, cls.gamma_kernel
    par = s.constraint.kernel_params(len(s.members))
    if jac is None or gam is None or par is None:
        raise _NotFused
    return jac, gam, par


def _check(lines: Lines, test: tuple) -> None:
    """A pivot's or a determinant's test (:func:`traced_inverse`) as a ``check`` line; a
    test on numbers alone is decided here (failed: no program)."""
    if test[0] == "det":
        value, line, ok = test[1], "!= 0", lambda x: x != 0.0
    else:
        _, pivot, below, recip = test
        if below:
            value = magnitude(lines, pivot)
            for x in below:
                value = larger(lines, value, magnitude(lines, x))
            value = value * magnitude(lines, recip)
        else:  # 1, or NaN where the pivot is 0 or not finite
            value = pivot * recip
        limit = 1.0 / PIVOT_RATIO
        line, ok = f"<= {limit!r}", lambda x: x <= limit
    if isinstance(value, Sym):
        lines.lines.append(f"    check {value.name} {line}")
    elif not ok(value):
        raise _NotFused


def _nu(system: System, lines: Lines, row: int):
    """ν's row: ψ̇ of a driver's row, zero on a joint's."""
    d = row - system.n_joint_rows
    return lines.value(f"psi_d[{d}, 0]") if d >= 0 else 0.0


def _substitution(system: System, slots: dict, inv: list, rhs_of) -> dict:
    """The forward substitution over the groups (as the plan's): group g's columns
    ``x = B_g⁻¹ (rhs − L_g x_done)``, ``rhs_of(g, a, row)`` the right-hand side's entry
    on the group's a-th row; returns x by column."""
    layout = system.layout
    x: dict = {}
    for g, p in enumerate(system.plans):
        rhs = [rhs_of(g, a, int(row)) for a, row in enumerate(p.rows)]
        if layout.lower[g] is not None:
            off, r, c = layout.lower[g]
            done = layout.lower_cols[g].tolist()
            for a in range(r):
                acc = 0.0
                for b, col in enumerate(done):
                    acc = acc + slots.get(off + a * c + b, 0.0) * x.get(col, 0.0)
                rhs[a] = rhs[a] - acc
        for i, col in enumerate(p.cols.tolist()):
            acc = 0.0
            for j, v in enumerate(rhs):
                acc = acc + inv[g][i][j] * v
            x[col] = acc
    return x


def _gamma(system: System, kinds: list, lines: Lines, poses, rates) -> dict:
    """γ by row: each set's ``gamma_kernel`` traced, a driver's ψ̈ less its bias."""
    gamma: dict = {}
    for s, (_, gam, par) in zip(system.sets, kinds):
        if s.driver is not None:
            (bias,) = traced_kernel(gam, ((1, 1),), par, poses, rates, s.ends)
            value = lines.value(f"psi_dd[{s.driver}, 0]") - bias[0, 0]
            gamma[int(s.rows.reshape(-1)[0])] = value
            continue
        (out,) = traced_kernel(
            gam, (s.rows.reshape(len(s.members), -1).shape + (1,),), par, poses, rates, s.ends
        )
        gamma.update(zip(s.rows.reshape(-1).tolist(), out.reshape(-1).tolist()))
    return gamma
