"""The kinematic plan of a system: its velocities and accelerations as one generated function.

The general derivative stage (:func:`~kinetostatics.kinematics.derivatives.derivatives`)
walks the system's evaluation plan at every call: it asks each constraint set whether
it stacks and how many positions there are, gathers the poses through
:meth:`~kinetostatics.structure.evaluation.ConstraintSet.pairs`, builds the group blocks
as views through a closure, and loops over the groups in the block solves.  All of that
is decided by the system alone.  :func:`kinematic_plan` decides it once, when a system
is first analysed, and writes the stage as Python source — one straight line of
whole-array operations per set and per group, the index arrays and block offsets as
constants — compiled with :func:`compile` and kept in ``System.memo``:

- Φ_q's group blocks: a set whose joint type's compiled-backend kernels hold over whole
  arrays (``Compiled.whole_array_kernels``: plain arithmetic, the NumPy formulas'
  operations in their order) by its ``jacobian_kernel`` *traced*
  (:mod:`~kinetostatics.base.trace`): run once on symbols, the kernel writes its
  operations into the plan as lines over the links' pose components (``PE[i, c]``, each
  one contiguous array over the positions), its entries assigned to their slots of
  :class:`~kinetostatics.structure.evaluation.BlockLayout` — no call per joint or per
  stack, and the terms the sets share (a link's rotated points, a prismatic pair's frame
  in its Φ_q and its γ) computed once; a motion driver on such a joint (one model's
  plan) by its joint's ``direction_kernel`` traced the same way
  (:func:`~.plan_params.jacobian_kernel`); every other set (a cam, a gear pair) by the
  contract's ``jacobian`` on its two links' poses gathered once — the joints' formulas
  stay in ``joints/`` either way; the ground's block kept for the shaking force as
  ``jacobian_blocks`` keeps it;
- the factorisation (:class:`~kinetostatics.base.blocks.BlockFactor`, its inverses
  written out by :mod:`.plan_inverse` where they can be, with one model's groups'
  condition numbers) and q̇ by forward substitution over ν = −Φ_t gathered as
  ``BlockFactor.solve`` gathers it, the vectors stored component-major;
- γ by the traced ``gamma_kernel`` (over the links' rates ``vr[i, c]``; a driver's ψ̈ less
  its joint's traced ``bias_kernel``) or the contract's
  ``acceleration_rhs`` of each set in the same way, and q̈ by the same substitution;
  over long chunks both substitutions, and the reactions' back substitution, written
  over the blocks' entries that are not zero (:mod:`.plan_solve`).

The numbers are those of the general path: the same operations on the same operands
in the same order (a zero's sign aside: base/trace.py; tests/kinematics/test_plan.py
compares every column to 1e-12 of its scale on the shipped files and generated
mechanisms).  The plan covers a system whose groups have at most two links
(:data:`PLANNED_BLOCKS`), one model's rows (``q (N, n_q)``) on either backend and stacked
variants' (``q (V, N, n_q)``, on NumPy: their parameters that differ read from a table,
kinematics/plan_params.py), at any number of rows where every stack of joints is traced
(revolute and prismatic pairs), else up to
:data:`~kinetostatics.structure.evaluation.STACK_UP_TO`; other rows take the general
path, which stays the oracle.  ``kinematic_plan(system).source`` is the generated text.
On the compiled backend the stage runs fused, position by position (kinematics/fused.py),
this plan its fallback where a position fails a pivot test or a set has no kernels.
"""

from __future__ import annotations

import functools
import numbers
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..base import kernels
from ..base.arrays import entries_last
from ..base.blocks import BlockFactor, Conditions
from ..base.geometry import poses
from ..base.linalg import small_inverse
from ..base.trace import Leaves, Lines, operand, pruned, traced_kernel
from ..model.stacking import is_stacked
from ..structure.evaluation import STACK_UP_TO, jacobian_blocks_all
from ..structure.system import System, link_poses, phi
from .derivatives import derivatives
from .fused import fused_derivatives
from .plan_buffers import NOZERO, Unwritten, block, filled, run_in_chunks, unwritten_of
from .plan_inverse import RUNTIME, condition_into, entry, inverse_line
from .plan_params import (
    driver_params,
    flat,
    gamma_kernel,
    jacobian_kernel,
    parameter_pattern,
    topology,
    unflat,
    whole_array,
)
from .plan_solve import (
    TRACED_FROM,
    Written,
    either,
    index,
    product_in_runs,
    substitution,
    traced_product,
    traced_substitution,
    traced_transposed,
    transposed_in_runs,
)

__all__ = [
    "KinematicPlan",
    "kinematic_plan",
    "planned_derivatives",
    "derivatives_at",
    "planned_phi",
    "written",
    "ENABLED",
]

ENABLED = True
"""Whether the plan is used where it covers the rows (off: the general path everywhere)."""

CHUNK_BYTES = 4 * 2**20
"""Rows are run in chunks whose Φ_q entries take about this much memory (1,024–8,192
positions; one pass's temporaries stay in the caches), each chunk's blocks inverted on
their own: the reference machines' kinematics at 36,000 positions take ~0.8 of one pass."""


@dataclass(frozen=True, eq=False)
class KinematicPlan:
    """A generated stage of one system: ``source`` (its Python text) and ``run`` compiled
    from it — the derivatives' ``run(pe, psi_d, psi_dd, buf, qdT, qddT, INV, …, Z)`` writes
    Φ_q's entries into ``buf``, the blocks' inverses into ``INV`` (entry-major) and q̇, q̈
    (component-major) into ``qdT``, ``qddT``, all the caller's: ``buf`` and ``INV`` zeros,
    or, with ``unwritten``, not zeroed, their unwritten entries zeroed by ``Z`` where read
    (:mod:`.plan_buffers`); the residuals' ``run(pe, psi)`` returns Φ."""

    source: str
    run: Callable
    long_runs: bool = True  # it also takes more than STACK_UP_TO rows (see covers)
    table: np.ndarray | None = None  # a stacked system's: the parameters that differ (k, V)
    transposed: Callable | None = None  # one model's: Φ_qᵀ Y = R written out (plan_solve)
    unwritten: Unwritten | None = None  # one model's, where its buffers need no zeros
    product: Callable | None = None  # one model's: Φ_qᵀ y written out (plan_solve)


PLAN_AFTER = (20, 8000)
"""A system's plans are made once its analyses (as they pass :func:`planned_derivatives`)
would have saved their cost, ``calls / 20 + rows / 8000 >= 1``: making them costs ~6–10
ms for the reference machines, an analysis through them saves ~0.3 ms and ~1–2 µs per
row (bench_plan_after.py), so that a system pays at most about twice the best choice.
Before, the general path runs, as the plans' oracle (a ``run`` and its cycle keep it)."""


def _worth(system: System, n: int) -> bool:
    """Whether the plan is (or now becomes) worth making, one more analysis of ``n`` rows."""
    if "kinematic plan" in system.memo:
        return True
    calls, rows = system.memo.get("analysed", (0, 0))
    calls, rows = system.memo["analysed"] = (calls + 1, rows + n)
    short, long = PLAN_AFTER
    return calls * long + rows * short >= short * long


PLANNED_BLOCKS = 6
"""The largest group block (columns; a dyad's 6) of a system the plan is made for: a
triad's 12×12 inverse is dense, and lines over its entries cost more than the general
stage's passes over whole blocks (bench_plan_after.py: the Stephenson six-bar)."""


def covers(system: System, q: np.ndarray) -> bool:
    """Whether the plan takes the rows ``q``: one model's ``(N, n_q)`` (on either backend:
    on the compiled one fused, kinematics/fused.py) or a stacked model's ``(V, N, n_q)``
    (its variants' rows one after the other), a system with an evaluation layout and
    groups of at most :data:`PLANNED_BLOCKS` columns; more than :data:`STACK_UP_TO` rows
    only where no stack of joints goes through the contract's methods (``long_runs``:
    every stacked type's formulas traced)."""
    large = any(len(p.cols) > PLANNED_BLOCKS for p in system.plans)
    if not ENABLED or system.layout is None or large:
        return False
    if q.ndim == 2:
        variants = None
    elif q.ndim == 3 and _variants(system):
        variants = len(q)
    else:
        return False
    n = q[..., 0].size
    return 0 < n and (n <= STACK_UP_TO or _long_runs(system, variants))


def _variants(system: System) -> bool:
    """Whether the system's model may be stacked variants (model/stacking.py: values with
    a leading variant axis; a model's own tables have more than one axis too, but its
    rows are ``(N, n_q)``)."""
    if "stacked" not in system.memo:
        system.memo["stacked"] = is_stacked(system.model)
    return system.memo["stacked"]


def _long_runs(system: System, variants: int | None = None) -> bool:
    """Whether the plan takes more than :data:`STACK_UP_TO` rows (every stacked type's
    formulas traced), known without making it (a long first run waits for
    :data:`PLAN_AFTER`'s rows as a short one waits for its analyses)."""
    return not any(s.stacked and whole_array(s, variants=variants) is None for s in system.sets)


def planned_derivatives(
    system: System, q: np.ndarray, psi_d: np.ndarray, psi_dd: np.ndarray, factors: bool = True
) -> tuple[np.ndarray, np.ndarray, BlockFactor | Conditions] | None:
    """(q̇, q̈, factorised Φ_q) by the system's plan, as ``derivatives`` gives them, or None
    where the plan does not cover the rows (:func:`covers`) or is not worth generating yet
    (:data:`PLAN_AFTER`).  The plan writes into arrays made here, each entry of a block and
    each component one contiguous array over the rows, and the block factor is made of
    their views (the entries no line writes zeroed where first read: :mod:`.plan_buffers`),
    the rows in chunks (:data:`CHUNK_BYTES`).  On the compiled backend without ``factors``
    (the kinematics alone) the fused stage gives the rates and the groups' conditions."""
    if not covers(system, q) or not _worth(system, q[..., 0].size):
        return None
    layout = system.layout
    assert layout is not None
    shape = q.shape[:-1]
    n, plan = q[..., 0].size, kinematic_plan(system, len(q) if len(shape) > 1 else None)
    pe = link_poses(system, q)
    done = None
    if kernels.active() and len(shape) == 1:
        done = fused_derivatives(system, pe, psi_d, psi_dd, factors)
        if done is not None and not factors:  # the rates alone
            return _rows(done[2], shape), _rows(done[3], shape), Conditions(done[4])
    redone, conditions, transposed, zeros = False, None, None, None
    if done is not None:  # the compiled backend's program, position by position
        buf, inv, qdT, qddT, conditions = done
    else:
        unwritten = plan.unwritten if n >= TRACED_FROM else None
        alloc = np.zeros if unwritten is None else np.empty
        buf = alloc((layout.size + 1, n))
        qdT, qddT = np.empty((system.n_q, n)), np.empty((system.n_q, n))
        inv = [alloc((len(p.cols), len(p.cols), n)) for p in system.plans]
        into = (buf, qdT, qddT)
        if plan.table is None:  # with the groups' condition numbers
            asked = conditioned(system)
            cnd = [np.empty(n) if g in asked else None for g in range(len(inv))]
            rows = (pe, psi_d, psi_dd)
            per = min(max(CHUNK_BYTES // (8 * (layout.size + 1)), 1024), 8192)
            redone, zeros = run_in_chunks(plan.run, per, rows, into, inv, cnd, unwritten)
            conditions = {g: c for g, c in enumerate(cnd) if c is not None}
        else:  # a stacked model's variants, their rows one after the other
            rows = (np.reshape(x, (n,) + x.shape[len(shape) :]) for x in (pe, psi_d, psi_dd))
            plan.run(*rows, *into, inv, np.repeat(plan.table, shape[1], axis=1), shape)
    if plan.transposed is not None and not redone and n >= TRACED_FROM:  # one model's
        transposed = (
            functools.partial(transposed_in_runs, plan.transposed, buf, inv),
            functools.partial(product_in_runs, plan.product, buf, system.n_q),
        )
    parts = [
        (block(buf, d, shape), None if lo is None else block(buf, lo, shape), cols)
        for d, lo, cols in zip(layout.diag, layout.lower, layout.lower_cols)
    ]
    blocks = [(p.rows, p.cols) for p in system.plans]
    inv = [entries_last(x.reshape(x.shape[:2] + shape)) for x in inv]
    lu = BlockFactor(None, blocks, parts, inv, conditions, transposed, ready=filled(zeros))
    ground = None if layout.ground is None else block(buf, layout.ground, shape)  # a view
    system.memo["ground_jacobian"] = (pe, ground, filled(zeros, layout.ground))
    return _rows(qdT, shape), _rows(qddT, shape), lu


def _rows(x_t: np.ndarray, shape: tuple) -> np.ndarray:
    """A component-major vector ``(k, n)`` as rows ``shape + (k,)`` (a view)."""
    return x_t.T.reshape(shape + x_t.shape[:1])


def derivatives_at(
    system: System, q: np.ndarray, psi_d: np.ndarray, psi_dd: np.ndarray, factors: bool = True
) -> tuple[np.ndarray, np.ndarray, BlockFactor | Conditions]:
    """(q̇, q̈, factorised Φ_q, or without ``factors`` maybe its :class:`Conditions` only) by
    the plan where it covers the rows, else by the general stage (``derivatives``)."""
    planned = planned_derivatives(system, q, psi_d, psi_dd, factors)
    return derivatives(system, q, psi_d, psi_dd) if planned is None else planned


def planned_phi(system: System, q: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Φ of every constraint at one model's rows ``q (N, n_q)``, ψ ``(N, n_d)``, as
    :func:`~kinetostatics.structure.system.phi` gives it: the revolute and prismatic pairs'
    ``residual_kernel`` traced into one function per system (the other sets by the
    contract's ``residual``), or by ``phi`` itself where that does not cover the rows
    (stacked variants; more than ``STACK_UP_TO`` rows of a stack without kernels) or
    before the system's kinematic plan is worth making (:data:`PLAN_AFTER`)."""
    if q.ndim != 2:
        return phi(system, q, psi)
    plan = system.memo.get("residual plan")
    if plan is None:
        if "kinematic plan" not in system.memo:  # not worth it yet (PLAN_AFTER)
            return phi(system, q, psi)
        plan = system.memo["residual plan"] = _generate_residual(system)
    if q.shape[0] > STACK_UP_TO and not plan.long_runs:
        return phi(system, q, psi)
    return plan.run(link_poses(system, q), psi)


def kinematic_plan(system: System, variants: int | None = None) -> KinematicPlan:
    """The system's :class:`KinematicPlan` (of its ``variants`` where the model is stacked),
    generated on first use and kept with it."""
    plan = system.memo.get("kinematic plan")
    if plan is None or (plan.table is not None and plan.table.shape[1] != variants):
        plan = _generate(system) if variants is None else _stacked_plan(system, variants)
        system.memo["kinematic plan"] = plan
    return plan


_STACKED: dict[tuple, tuple] = {}
"""The stacked systems' plans compiled so far, by their topology and parameter pattern
(``parameter_pattern``): a search stacks a new population at each generation, whose
plan is the last one's with other numbers in its table (at most :data:`STACKED_KEPT`)."""
STACKED_KEPT = 32


def _stacked_plan(system: System, variants: int) -> KinematicPlan:
    """The plan of a stacked system: its source generated and compiled once per topology
    and pattern of parameters, bound to this system's constraints and table."""
    pattern, columns = parameter_pattern(system, variants)
    key = (topology(system), pattern)
    hit = _STACKED.get(key)
    if hit is None:
        lines, env = written(system, pattern)
        source = "\n".join(lines) + "\n"
        code = compile(source, f"<kinematic plan of {system.model.name!r}>", "exec")
        if len(_STACKED) >= STACKED_KEPT:
            _STACKED.clear()
        hit = _STACKED[key] = (source, code, env, _long_runs(system, variants))
    source, code, env, long_runs = hit
    env = dict(env) | {f"C{k}": s.constraint for k, s in enumerate(system.sets)}
    exec(code, env)  # noqa: S102  our own generated text
    table = np.array(columns).reshape(len(columns), variants)
    return KinematicPlan(source, env["run"], long_runs, table)


# -- the joints' kernels, traced ----------------------------------------------------------
def _traced_rows(traced: Lines, s, kernel, *args) -> list[str]:
    """The lines of set ``s``'s kernel writing its values ``out (k, n_eq, N)`` (Φ's or
    γ's), traced, each value to its row of ``rows``."""
    (out,) = traced_kernel(kernel, (s.rows.reshape(len(s.members), -1).shape + (1,),), *args)
    for at, value in zip(s.rows.reshape(-1).tolist(), out.reshape(-1).tolist()):
        traced.lines.append(f"    rows[{at}] = {operand(value)}")
    return traced.take()


def _generate_residual(system: System) -> KinematicPlan:
    """Φ's function for ``system``: ``run(pe, psi) -> (N, n_rows)``."""
    lines = ["def run(pe, psi):", "    n = pe.shape[0]", "    PE = pe.transpose(1, 2, 0)"]
    lines.append(f"    rows = np.empty(({system.n_rows}, n))")
    lines.append("    out = rows.T")
    env: dict = {"np": np}
    traced = Lines()
    poses = Leaves(traced, "PE", len(system.links), (0.0, 0.0, 0.0, 1.0, 0.0))
    long_runs = True
    for k, s in enumerate(system.sets):
        par = whole_array(s, ("residual_kernel",))
        if par is None:
            long_runs &= not s.stacked
            env[f"C{k}"], env[f"R{k}"] = s.constraint, s.rows if s.stacked else s.rows[0]
            extra = "" if s.driver is None else f", psi[:, {s.driver}]"
            lines += _pair(env, k, s, "pe", ("qi", "qj"))
            lines.append(f"    out[:, R{k}] = C{k}.residual(qi, qj{extra})")
            continue
        kernel = type(s.constraint).residual_kernel
        lines += _traced_rows(traced, s, kernel, par, poses, s.ends)
    lines.append("    return out")
    source = "\n".join(pruned(lines)) + "\n"
    exec(compile(source, f"<residuals of {system.model.name!r}>", "exec"), env)  # noqa: S102
    return KinematicPlan(source, env["run"], long_runs)


# -- the generator ------------------------------------------------------------------------
def _generate(system: System) -> KinematicPlan:
    """Write the stage's source for ``system`` and compile it."""
    lines, env = written(system)
    source = "\n".join(lines) + "\n"
    name = f"<kinematic plan of {system.model.name!r}>"
    exec(compile(source, name, "exec"), env)  # noqa: S102  our own generated text
    return KinematicPlan(
        source,
        env["run"],
        _long_runs(system),
        None,
        env.get("transposed"),
        env.get("UNWRITTEN"),
        env.get("product"),
    )


def written(system: System, pattern: tuple | None = None) -> tuple[list[str], dict]:
    """The plan's source lines for ``system`` and the names they read (the index arrays,
    the constraints), uncompiled (a benchmark times them statement by statement:
    tests/benchmarks/bench_speed_calls.py); ``pattern``: of a stacked system
    (``parameter_pattern``), whose rows are its variants' positions one after the
    other (``run`` then also takes the table of the parameters that differ, ``PA``, and
    ``shape`` = (V, N))."""
    env: dict = {"np": np, "invert": small_inverse, "unflat": unflat, "flat": flat}
    env["NOZERO"] = NOZERO
    extra = ", CND" if pattern is None else ", PA, shape"
    lines = [
        f"def run(pe, psi_d, psi_dd, buf, qdT, qddT, INV{extra}, Z=NOZERO):",
        "    n = pe.shape[0]",
        "    PE = pe.transpose(1, 2, 0)",
    ]
    traced, inverses = Lines(), []
    params = _params(system, pattern, traced, env)
    written = _blocks(system, env, lines, traced, inverses, params)
    if pattern is not None:  # a stacked model's: the whole-array substitutions alone
        written = None
    _rates_of(system, env, lines, written)
    _accelerations(system, env, lines, params, traced, written)
    lines.append("    return redone")
    solves = [] if written is None else ["", *traced_transposed(system, written), ""]
    solves += [] if written is None else traced_product(system, written)
    if written is not None and all(w != RUNTIME for w in written.writes.values()):
        env["UNWRITTEN"] = unwritten_of(system, written)
    return inverses + pruned(lines) + solves, env


def _params(system: System, pattern: tuple | None, traced: Lines, env: dict) -> list:
    """Each set's kernel parameters as its traced kernels read them (None: the contract's
    methods evaluate it); of a stacked system, its ``parameter_pattern``'s: a number, or
    the local read from the row of the table ``PA`` that it names."""
    if pattern is None:
        return [whole_array(s) if s.driver is None else driver_params(s) for s in system.sets]
    env["STACKED"] = True
    out = []
    for spec in pattern:
        if spec is None:
            out.append(None)
            continue
        shape, entries = spec
        par = np.empty(len(entries), dtype=object)  # numbers and the table's locals
        par[:] = [x if isinstance(x, float) else traced.value(x) for x in entries]
        out.append(par.reshape(shape))
    return out


def _blocks(  # noqa: PLR0913  the generator's state, passed down
    system: System, env: dict, lines: list[str], traced: Lines, inverses: list[str], params: list
) -> Written | None:
    """Φ_q's entries into ``buf`` (the caller's zeros), the diagonal blocks' inverses into
    ``INV`` (entry-major, each group's ``(k, k, n)``; written out by :mod:`.plan_inverse`,
    their functions' text into ``inverses``, where it can), the coupling blocks ``LT<g>``
    (component-major); ``params``: each set's traced kernels' parameters (None: its
    contract's methods)."""
    layout = system.layout
    assert layout is not None
    poses = Leaves(traced, "PE", len(system.links), (0.0, 0.0, 0.0, 1.0, 0.0))
    writes: dict[int, object] = {}  # each slot's writes: [(op, value)] or RUNTIME
    for k, s in enumerate(system.sets):
        env[f"C{k}"] = s.constraint
        env[f"TI{k}"], env[f"TJ{k}"] = layout.dest[k]
        par = params[k]
        if par is None:
            lines += _contract_jacobian(env, k, s)
            writes.update(dict.fromkeys(np.ravel(layout.dest[k]).tolist(), RUNTIME))
            continue
        shape = (len(s.members),) + s.rows.shape[-1:] + (3, 1)
        ji, jj = traced_kernel(jacobian_kernel(s), (shape, shape), par, poses, s.ends)
        for slots, values, op in ((layout.dest[k][0], ji, "="), (layout.dest[k][1], jj, "+=")):
            for at, value in zip(slots.reshape(-1).tolist(), values.reshape(-1).tolist()):
                if not (isinstance(value, numbers.Real) and value == 0.0):  # zero on zeros
                    first = "=" if at not in writes else op  # the buffer may not be zeros
                    traced.lines.append(f"    buf[{at}] {first} {operand(value)}")
                    w = writes.setdefault(at, [])
                    if w != RUNTIME:
                        w.append((first, value))
        lines += traced.take()
    first = None if "STACKED" in env else _start_blocks(system)  # shared: no one's pose
    lines.append("    redone = False")
    patterns = []
    for g, (d, lo) in enumerate(zip(layout.diag, layout.lower)):
        off, r, c = d
        m = [[entry(writes.get(off + i * c + j)) for j in range(c)] for i in range(r)]
        l_ref = _condition_scale(system, g, env)
        inverse = inverse_line(env, g, d, _view(d), m, None if first is None else first[g], l_ref)
        if inverse is None:
            lines += [f"    invert({_view(d)}, INV[{g}])", "    redone = True"]
            if l_ref is not None:
                lines.append(f"    condition_into(CND[{g}], {_view(d)}, INV[{g}], {l_ref!r})")
        else:
            lines.append(f"    redone = {inverse.call} or redone")
            inverses += inverse.source
        patterns.append(None if inverse is None else inverse.pattern)
        if lo is not None:
            off, r, c = lo
            lines.append(f"    LT{g} = buf[{off}:{off + r * c}].reshape({r}, {c}, n)")
        env[f"DONE{g}"], env[f"ROWS{g}"] = layout.lower_cols[g], system.plans[g].rows
        env[f"COLS{g}"] = system.plans[g].cols
    return None if any(p is None for p in patterns) else Written(patterns, writes)


def conditioned(system: System) -> list[int]:
    """The groups whose condition numbers the analysis reads (analysis/pipeline.py): all
    but the driven ones."""
    return [g for g, p in enumerate(system.plans) if p.group.kind != "driven"]


def _condition_scale(system: System, g: int, env: dict) -> float | None:
    """L_ref where the plan writes group ``g``'s condition number with its inverse (one
    model's plan, a group of :func:`conditioned`), else None."""
    if "STACKED" in env or g not in conditioned(system):
        return None
    env["condition_into"] = condition_into
    return float(system.l_ref)


def _start_blocks(system: System) -> list[np.ndarray] | None:
    """Each group's diagonal block at the start pose ``(r, c)`` (the row orders of the
    written inverses: :mod:`.plan_inverse`), or None before the start pose is known."""
    start = system.memo.get("start")
    if start is None:
        return None
    pe = poses(np.asarray(start[1], dtype=float).reshape(1, -1), len(system.links))
    return [np.asarray(d)[0] for d, _, _ in jacobian_blocks_all(system.sets, system.layout, pe)[0]]


def _view(at) -> str:
    """The text of a block's view ``(n, rows, cols)`` of ``buf`` (its offset, rows, cols)."""
    off, r, c = at
    return f"buf[{off}:{off + r * c}].reshape({r}, {c}, n).transpose(2, 0, 1)"


def _pair(env: dict, k: int, s, array: str, names: tuple[str, str]) -> list[str]:
    """Lines gathering set k's two links' rows of ``array`` (poses or rates, ``(n, links,
    c)``) as ``names``: a stack's by :func:`numpy.take`, a single constraint's as views."""
    a, b = names
    if s.stacked:
        env[f"EI{k}"], env[f"EJ{k}"] = s.ends[0], s.ends[1]
        ends = [f"np.take({array}, EI{k}, axis=1)", f"np.take({array}, EJ{k}, axis=1)"]
    else:
        ends = [f"{array}[:, {int(s.ends[0, 0])}, :]", f"{array}[:, {int(s.ends[1, 0])}, :]"]
    if "STACKED" in env:  # a stacked model's constraint reads (V, N, ...)
        ends = [f"unflat({x}, shape)" for x in ends]
    return [f"    {a} = {ends[0]}", f"    {b} = {ends[1]}"]


def _contract_jacobian(env: dict, k: int, s) -> list[str]:
    """Set k's Φ_q entries through the contract's ``jacobian``: its two links' poses
    gathered once (``qi<k>``, ``qj<k>``, read again for its γ) and scattered to their
    slots."""
    axes = "(1, 2, 3, 0)" if s.stacked else "(1, 2, 0)"
    lines = _pair(env, k, s, "pe", (f"qi{k}", f"qj{k}"))
    lines.append(f"    ji, jj = C{k}.jacobian(qi{k}, qj{k})")
    if "STACKED" in env:
        lines.append("    ji, jj = flat(ji, shape), flat(jj, shape)")
    return lines + [
        f"    buf[TI{k}] = ji.transpose{axes} + 0.0",
        f"    buf[TJ{k}] += jj.transpose{axes}",
    ]


def _contract_gamma(env: dict, k: int, s) -> list[str]:
    """Set k's rows of γ through the contract's ``acceleration_rhs``."""
    env[f"R{k}"] = s.rows if s.stacked else s.rows[0]
    extra = "" if s.driver is None else f", psi_dd[:, {s.driver}]"
    value = f"C{k}.acceleration_rhs(qi{k}, qj{k}, vi, vj{extra})"
    if "STACKED" in env:
        extra = "" if s.driver is None else f", unflat(psi_dd[:, {s.driver}], shape)"
        value = f"flat(C{k}.acceleration_rhs(qi{k}, qj{k}, vi, vj{extra}), shape)"
    return _pair(env, k, s, "ve", ("vi", "vj")) + [f"    gam[:, R{k}] = {value}"]


def _rates_of(system: System, env: dict, lines: list[str], written: Written | None) -> None:
    """q̇ from ν = −Φ_t (zero on the joints' rows, ψ̇ on the drivers'), gathered per group
    as :meth:`BlockFactor.solve` gathers it (a group with no driver's row: its coupling
    term alone, negated)."""
    dense = [
        f"    nu = np.zeros(({system.n_rows}, n))",
        f"    nu[{system.n_joint_rows}:] = psi_d.T",
    ]

    def rhs(g):  # a group without a driver's row: ν = 0 on its rows
        at = system.plans[g].rows
        return f"nu[{index(f'ROWS{g}', at)}]" if np.any(at >= system.n_joint_rows) else None

    def row(sub: Lines, r: int):
        d = r - system.n_joint_rows
        return sub.value(f"psi_d[:, {d}]") if d >= 0 else 0.0

    dense += substitution(system, "qd", rhs)
    traced = None if written is None else traced_substitution(system, "qd", row, written)
    lines += either(dense, traced)


def _accelerations(  # noqa: PLR0913  the generator's state, passed down
    system: System, env: dict, lines: list[str], params: list, traced: Lines, written
) -> None:
    """γ from the poses and the links' rates (stored component-major as the poses are, the
    ground's zeros last), then q̈."""
    n_links = len(system.links)
    lines.append(f"    vr = np.zeros(({n_links + 1}, 3, n))")
    lines.append(f"    vr[:{n_links}] = qdT.reshape({n_links}, 3, n)")
    lines.append("    ve = vr.transpose(2, 0, 1)")
    lines.append(f"    rows = np.empty(({system.n_rows}, n))")
    lines.append("    gam = rows.T")
    poses = Leaves(traced, "PE", n_links, (0.0, 0.0, 0.0, 1.0, 0.0))
    rates = Leaves(traced, "vr", n_links, (0.0, 0.0, 0.0))
    for k, s in enumerate(system.sets):
        if params[k] is None:
            lines += _contract_gamma(env, k, s)
            continue
        psi_dd = None if s.driver is None else traced.value(f"psi_dd[:, {s.driver}]")
        kernel = gamma_kernel(s, psi_dd)
        lines += _traced_rows(traced, s, kernel, params[k], poses, rates, s.ends)
    dense = substitution(
        system, "qdd", lambda g: f"rows[{index(f'ROWS{g}', system.plans[g].rows)}]"
    )
    traced_rows = None
    if written is not None:
        row = lambda sub, r: sub.value(f"rows[{r}]")  # noqa: E731
        traced_rows = traced_substitution(system, "qdd", row, written)
    lines += either(dense, traced_rows)
