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

- Φ_q's group blocks: from :data:`KERNELS_FROM` positions on, a set whose joint type's
  compiled-backend kernels hold over whole arrays (``Compiled.whole_array_kernels``:
  plain arithmetic, the NumPy formulas' operations in their order) by its
  ``jacobian_kernel`` run once with every position at each index (:func:`_objects`),
  its entries scattered to the slots of
  :class:`~kinetostatics.structure.evaluation.BlockLayout`; every other set (and every
  set on fewer positions) by the contract's ``jacobian`` on its two links' poses
  gathered once — the joints' formulas stay in ``joints/`` either way; the ground's
  block kept for the shaking force as ``jacobian_blocks`` keeps it;
- the factorisation (:class:`~kinetostatics.base.linalg.BlockFactor`, its inverses by
  ``small_inverse`` as before) and q̇ by forward substitution over ν = −Φ_t gathered
  as ``BlockFactor.solve`` gathers it;
- γ by the ``gamma_kernel`` or ``acceleration_rhs`` of each set in the same way, from
  the links' rates, and q̈ by the same substitution.

The numbers are those of the general path: the same operations on the same operands
in the same order (tests/kinematics/test_plan.py compares every column to 1e-12 of its
scale on the shipped files and generated mechanisms).  The plan covers one model's rows
(``q (N, n_q)``) on the NumPy backend, at any N where every stack of joints runs its
type's kernels over whole arrays (revolute and prismatic pairs: joint by joint, as the
general path evaluates a stack over more than
:data:`~kinetostatics.structure.evaluation.STACK_UP_TO` positions), else up to that many;
stacked variants and the compiled backend take the general path, which stays the
oracle.  ``kinematic_plan(system).source`` is the generated text.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..base import kernels
from ..base.linalg import BlockFactor
from ..structure.evaluation import STACK_UP_TO
from ..structure.system import System, link_poses

__all__ = ["KinematicPlan", "kinematic_plan", "planned_derivatives", "written", "ENABLED"]

ENABLED = True
"""The plan is used where it covers the rows (False: the general path everywhere, as the
tests compare them)."""

KERNELS_FROM = 64
"""From this many positions on, the sets whose joint type's kernels hold over whole arrays
(``Compiled.whole_array_kernels``) are evaluated by those kernels, run once with every
position at each index (each formula one operation per component over contiguous
arrays, joint by joint); below, through the contract's NumPy methods (a stack's joints
in one operation per formula, which costs less when the arrays are short).  Measured by
tests/benchmarks/bench_speed_calls.py ``--crossover``."""


@dataclass(frozen=True, eq=False)
class KinematicPlan:
    """The generated derivative stage of one system: ``source`` (its Python text) and
    ``run(pe, psi_d, psi_dd) -> (qd, qdd, lu, ground)`` compiled from it."""

    source: str
    run: Callable
    long_runs: bool = True  # it also takes more than STACK_UP_TO rows (see covers)


def covers(system: System, q: np.ndarray) -> bool:
    """Whether the plan takes the rows ``q``: one model's ``(N, n_q)``, on the NumPy
    backend, a system with an evaluation layout; more than :data:`STACK_UP_TO` rows only
    where no stack of joints goes through the contract's methods (``long_runs``: every
    stacked type's kernels run over whole arrays, joint by joint, as the general path
    evaluates a stack over that many positions)."""
    return (
        ENABLED
        and q.ndim == 2
        and 0 < q.shape[0]
        and system.layout is not None
        and not kernels.active()
        and (q.shape[0] <= STACK_UP_TO or kinematic_plan(system).long_runs)
    )


def planned_derivatives(
    system: System, q: np.ndarray, psi_d: np.ndarray, psi_dd: np.ndarray
) -> tuple[np.ndarray, np.ndarray, BlockFactor] | None:
    """(q̇, q̈, factorised Φ_q) by the system's plan, as ``derivatives`` gives them, or None
    where the plan does not cover the rows (:func:`covers`)."""
    if not covers(system, q):
        return None
    pe = link_poses(system, q)
    qd, qdd, lu, ground = kinematic_plan(system).run(pe, psi_d, psi_dd)
    system.memo["ground_jacobian"] = (pe, ground)
    return qd, qdd, lu


def kinematic_plan(system: System) -> KinematicPlan:
    """The system's :class:`KinematicPlan`, generated on first use and kept with it."""
    plan = system.memo.get("kinematic plan")
    if plan is None:
        plan = system.memo["kinematic plan"] = _generate(system)
    return plan


# -- the joints' kernels over whole arrays -------------------------------------------------
def _objects(a: np.ndarray) -> np.ndarray:
    """The kernels' ``P (n + 1, 5, N)`` or ``V (n + 1, 3, N)`` for one pass over all the
    positions at once: an object array ``(n + 1, c, 1)`` whose entry ``[i, c, 0]`` is
    component c of link i over every position (a contiguous view of ``a``, stored
    component-major as the poses and rates are), so that the kernel's arithmetic on
    ``P[i, c, p]`` runs over whole arrays (its loop over the positions runs once)."""
    out = np.empty(a.shape[:2] + (1,), dtype=object)
    flat, parts = out.reshape(-1), a.reshape(-1, a.shape[-1])
    for k in range(len(flat)):
        flat[k] = parts[k]
    return out


def _scatter(buf: np.ndarray, slots: np.ndarray, values: np.ndarray, add: bool) -> None:
    """A kernel's entries ``values`` (objects: arrays over the positions, or constants)
    to their slots among the group blocks, set (link i's side) or added (link j's), as
    ``jacobian_blocks_all`` puts a set's two parts; a zero on zeros is left out."""
    for at, value in zip(slots, values):
        if type(value) is float and value == 0.0:
            continue
        if add:
            buf[at] += value
        else:
            buf[at] = value


def _rows(out: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
    """A γ kernel's entries ``values`` to their rows of γ, stored row-major ``(n_rows, N)``."""
    for at, value in zip(rows, values):
        out[at] = value


def _whole_array(s) -> np.ndarray | None:
    """The kernels' parameters of set ``s`` where its joint type's kernels also hold over
    whole arrays (``Compiled.whole_array_kernels``: plain arithmetic, no branch on a
    value), else None: the set is evaluated through the contract's NumPy methods."""
    cls = type(s.constraint)
    if s.driver is not None or not cls.whole_array_kernels:
        return None
    if cls.jacobian_kernel is None or cls.gamma_kernel is None:
        return None
    return s.constraint.kernel_params(len(s.members))


# -- the generator ------------------------------------------------------------------------
def _generate(system: System) -> KinematicPlan:
    """Write the stage's source for ``system`` and compile it."""
    lines, env = written(system)
    source = "\n".join(lines) + "\n"
    name = f"<kinematic plan of {system.model.name!r}>"
    exec(compile(source, name, "exec"), env)  # noqa: S102  our own generated text
    long_runs = not any(s.stacked and _whole_array(s) is None for s in system.sets)
    return KinematicPlan(source, env["run"], long_runs)


def written(system: System) -> tuple[list[str], dict]:
    """The plan's source lines for ``system`` and the names they read (the index arrays,
    the constraints, the kernels), uncompiled (a benchmark times them statement by
    statement: tests/benchmarks/bench_speed_calls.py)."""
    env: dict = {"np": np, "BlockFactor": BlockFactor, "objects": _objects}
    env |= {"scatter": _scatter, "to_rows": _rows}
    lines = ["def run(pe, psi_d, psi_dd):", "    n = pe.shape[0]"]
    gather = _blocks(system, env, lines)
    _rates_of(system, env, lines)
    _accelerations(system, env, lines, gather)
    lines.append("    return qd, qdd, lu, ground")
    return lines, env


def _blocks(system: System, env: dict, lines: list[str]) -> list[tuple[str, str, bool]]:
    """Φ_q's group blocks ``D<g>``, ``L<g>``, the ground's ``ground`` and the factors ``lu``,
    ``inv``; returns the names of each set's gathered poses and whether its type's
    kernels run over whole arrays (from :data:`KERNELS_FROM` positions on)."""
    layout = system.layout
    assert layout is not None
    lines.append(f"    buf = np.zeros(({layout.size + 1}, n))")
    kernels = False
    gather = []
    for k, s in enumerate(system.sets):
        env[f"C{k}"] = s.constraint
        env[f"TI{k}"], env[f"TJ{k}"] = layout.dest[k]
        contract = _contract_jacobian(env, k, s)
        par = _whole_array(s)
        gather.append((f"qi{k}", f"qj{k}", par is not None))
        if par is None:
            lines += contract
            continue
        if not kernels:  # the poses as the kernels read them, once
            lines.append(f"    P = objects(pe.transpose(1, 2, 0)) if n >= {KERNELS_FROM} else None")
            kernels = True
        cls = type(s.constraint)
        env[f"KJ{k}"], env[f"KG{k}"], env[f"KP{k}"] = cls.jacobian_kernel, cls.gamma_kernel, par
        env[f"E{k}"] = s.ends
        env[f"SHAPE{k}"] = (len(s.members),) + s.rows.shape[-1:] + (3, 1)
        env[f"KI{k}"], env[f"KJI{k}"] = (d.reshape(-1) for d in layout.dest[k])
        lines.append(f"    if n >= {KERNELS_FROM}:  # the type's kernel over whole arrays")
        lines += [
            f"        ji = np.empty(SHAPE{k}, dtype=object)",
            f"        jj = np.empty(SHAPE{k}, dtype=object)",
            f"        KJ{k}(KP{k}, P, E{k}, ji, jj)",
            f"        scatter(buf, KI{k}, ji.reshape(-1), False)",
            f"        scatter(buf, KJI{k}, jj.reshape(-1), True)",
            "    else:",
        ]
        lines += ["    " + line for line in contract]

    def view(at, copy=""):
        off, r, c = at
        return f"buf[{off}:{off + r * c}]{copy}.reshape({r}, {c}, n).transpose(2, 0, 1)"

    ground = "None" if layout.ground is None else view(layout.ground, ".copy()")
    lines.append(f"    ground = {ground}")
    parts, blocks = [], []
    for g, (p, d, lo, cols) in enumerate(
        zip(system.plans, layout.diag, layout.lower, layout.lower_cols)
    ):
        lines.append(f"    D{g} = {view(d)}")
        lines.append(f"    L{g} = {'None' if lo is None else view(lo)}")
        env[f"DONE{g}"], env[f"ROWS{g}"], env[f"COLS{g}"] = cols, p.rows, p.cols
        env[f"BLOCK{g}"] = (p.rows, p.cols)
        parts.append(f"(D{g}, L{g}, DONE{g})")
        blocks.append(f"BLOCK{g}")
    lines.append(f"    lu = BlockFactor(None, [{', '.join(blocks)}], [{', '.join(parts)}])")
    lines.append("    inv = lu.inv")
    return gather


def _contract_jacobian(env: dict, k: int, s) -> list[str]:
    """Set k's Φ_q entries through the contract's ``jacobian``: its two links' poses
    gathered once (``qi<k>``, ``qj<k>``: a stack's by :func:`numpy.take`, a single
    constraint's as views) and scattered to their slots."""
    if s.stacked:
        env[f"EI{k}"], env[f"EJ{k}"] = s.ends[0], s.ends[1]
        lines = [
            f"    qi{k} = np.take(pe, EI{k}, axis=1)",
            f"    qj{k} = np.take(pe, EJ{k}, axis=1)",
        ]
        axes = "(1, 2, 3, 0)"
    else:
        lines = [
            f"    qi{k} = pe[:, {int(s.ends[0, 0])}, :]",
            f"    qj{k} = pe[:, {int(s.ends[1, 0])}, :]",
        ]
        axes = "(1, 2, 0)"
    return lines + [
        f"    ji, jj = C{k}.jacobian(qi{k}, qj{k})",
        f"    buf[TI{k}] = ji.transpose{axes} + 0.0",
        f"    buf[TJ{k}] += jj.transpose{axes}",
    ]


def _contract_gamma(env: dict, k: int, s) -> list[str]:
    """Set k's rows of γ through the contract's ``acceleration_rhs``."""
    env[f"R{k}"] = s.rows if s.stacked else s.rows[0]
    if s.stacked:
        lines = [f"    vi = np.take(ve, EI{k}, axis=1)", f"    vj = np.take(ve, EJ{k}, axis=1)"]
    else:
        lines = [
            f"    vi = ve[:, {int(s.ends[0, 0])}, :]",
            f"    vj = ve[:, {int(s.ends[1, 0])}, :]",
        ]
    extra = "" if s.driver is None else f", psi_dd[:, {s.driver}]"
    return lines + [f"    gam[:, R{k}] = C{k}.acceleration_rhs(qi{k}, qj{k}, vi, vj{extra})"]


def _substitution(system: System, x: str, rhs_of) -> list[str]:
    """``x`` by forward substitution over the groups, group g's right-hand side
    ``rhs_of(g)`` (as :meth:`BlockFactor.solve` runs it)."""
    layout = system.layout
    assert layout is not None
    lines = [f"    {x} = np.zeros((n, {system.n_q}))"]
    for g in range(len(system.plans)):
        rhs = rhs_of(g)
        if layout.lower[g] is not None:
            rhs = f"{rhs} - np.einsum('...ij,...j->...i', L{g}, {x}[:, DONE{g}])"
        lines.append(f"    {x}[:, COLS{g}] = np.einsum('...ij,...j->...i', inv[{g}], {rhs})")
    return lines


def _rates_of(system: System, env: dict, lines: list[str]) -> None:
    """q̇ from ν = −Φ_t (zero on the joints' rows, ψ̇ on the drivers'), gathered per group
    as :meth:`BlockFactor.solve` gathers it (the same operands in the same memory order:
    ``einsum`` sums in another order over another layout)."""
    lines.append(f"    nu = np.concatenate((np.zeros((n, {system.n_joint_rows})), psi_d), axis=-1)")
    lines += _substitution(system, "qd", lambda g: f"nu[:, ROWS{g}]")


def _accelerations(system: System, env: dict, lines: list[str], gather: list) -> None:
    """γ from the gathered poses and the links' rates (stored component-major as the poses
    are, the ground's zeros last), then q̈."""
    n_links = len(system.links)
    lines.append(f"    vr = np.zeros(({n_links + 1}, 3, n))")
    lines.append(f"    vr[:{n_links}] = qd.reshape(n, {n_links}, 3).transpose(1, 2, 0)")
    lines.append("    ve = vr.transpose(2, 0, 1)")
    lines.append(f"    rows = np.empty(({system.n_rows}, n))")
    lines.append("    gam = rows.T")
    if any(k for _, _, k in gather):
        lines.append(f"    V = objects(vr) if n >= {KERNELS_FROM} else None")
    for k, s in enumerate(system.sets):
        contract = _contract_gamma(env, k, s)
        if not gather[k][2]:
            lines += contract
            continue
        env[f"KR{k}"] = s.rows.reshape(-1)
        env[f"OUT{k}"] = s.rows.reshape(len(s.members), -1).shape + (1,)
        lines += [
            f"    if n >= {KERNELS_FROM}:",
            f"        out = np.empty(OUT{k}, dtype=object)",
            f"        KG{k}(KP{k}, P, V, E{k}, out)",
            f"        to_rows(rows, KR{k}, out.reshape(-1))",
            "    else:",
        ]
        lines += ["    " + line for line in contract]
    lines += _substitution(system, "qdd", lambda g: f"gam[:, ROWS{g}]")
