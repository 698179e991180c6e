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

- Φ_q's group blocks: each set's two links' poses gathered once (a stack by
  :func:`numpy.take`, a single constraint as a view), its Jacobian from the joint
  contract (``constraint.jacobian``: the joints' formulas stay in ``joints/``) and
  scattered to the slots of :class:`~kinetostatics.structure.evaluation.BlockLayout`;
  the ground's block kept for the shaking force as ``jacobian_blocks`` keeps it;
- the factorisation (:class:`~kinetostatics.base.linalg.BlockFactor`, its inverses by
  ``small_inverse`` as before) and q̇ by forward substitution, where a group without
  a motion driver has a zero right-hand side (ν = −Φ_t is zero on joint rows);
- γ from the same gathered poses and the links' rates (``constraint.acceleration_rhs``),
  and q̈ by the same substitution.

The numbers are those of the general path: the same operations on the same operands
in the same order (tests/kinematics/test_plan.py compares every column to 1e-12 of its
scale on the shipped files and generated mechanisms).  The plan covers one model's rows
(``q (N, n_q)``) up to :data:`~kinetostatics.structure.evaluation.STACK_UP_TO` positions
on the NumPy backend; stacked variants, longer runs (where the general path evaluates a
stack's joints one by one) and the compiled backend take the general path, which stays
the oracle.  ``kinematic_plan(system).source`` is the generated text.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..base import kernels
from ..base.linalg import BlockFactor
from ..structure.evaluation import STACK_UP_TO
from ..structure.system import System, link_poses

__all__ = ["KinematicPlan", "kinematic_plan", "planned_derivatives", "ENABLED"]

ENABLED = True
"""The plan is used where it covers the rows (False: the general path everywhere, as the
tests compare them)."""


@dataclass(frozen=True, eq=False)
class KinematicPlan:
    """The generated derivative stage of one system: ``source`` (its Python text) and
    ``run(pe, qd_rates, psi_d, psi_dd) -> (qd, qdd, lu, ground)`` compiled from it."""

    source: str
    run: Callable


def covers(system: System, q: np.ndarray) -> bool:
    """Whether the plan takes the rows ``q``: one model's ``(N, n_q)`` with N ≤
    :data:`STACK_UP_TO`, on the NumPy backend, a system with an evaluation layout."""
    return (
        ENABLED
        and q.ndim == 2
        and 0 < q.shape[0] <= STACK_UP_TO
        and system.layout is not None
        and not kernels.active()
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


# -- the generator ------------------------------------------------------------------------
def _generate(system: System) -> KinematicPlan:
    """Write the stage's source for ``system`` and compile it."""
    env: dict = {"np": np, "BlockFactor": BlockFactor}
    lines = ["def run(pe, psi_d, psi_dd):", "    n = pe.shape[0]"]
    gather = _blocks(system, env, lines)
    _rates_of(system, env, lines)
    _accelerations(system, env, lines, gather)
    lines.append("    return qd, qdd, lu, ground")
    source = "\n".join(lines) + "\n"
    name = f"<kinematic plan of {system.model.name!r}>"
    exec(compile(source, name, "exec"), env)  # noqa: S102  our own generated text
    return KinematicPlan(source, env["run"])


def _blocks(system: System, env: dict, lines: list[str]) -> list[tuple[str, str]]:
    """Φ_q's group blocks ``D<g>``, ``L<g>``, the ground's ``ground`` and the factors ``lu``,
    ``inv``; returns the names of each set's gathered poses."""
    layout = system.layout
    assert layout is not None
    lines.append(f"    buf = np.zeros(({layout.size + 1}, n))")
    gather = []
    for k, s in enumerate(system.sets):
        env[f"C{k}"] = s.constraint
        env[f"TI{k}"], env[f"TJ{k}"] = layout.dest[k]
        if s.stacked:
            env[f"EI{k}"], env[f"EJ{k}"] = s.ends[0], s.ends[1]
            lines.append(f"    qi{k} = np.take(pe, EI{k}, axis=1)")
            lines.append(f"    qj{k} = np.take(pe, EJ{k}, axis=1)")
            axes = "(1, 2, 3, 0)"
        else:
            lines.append(f"    qi{k} = pe[:, {int(s.ends[0, 0])}, :]")
            lines.append(f"    qj{k} = pe[:, {int(s.ends[1, 0])}, :]")
            axes = "(1, 2, 0)"
        gather.append((f"qi{k}", f"qj{k}"))
        lines.append(f"    ji, jj = C{k}.jacobian(qi{k}, qj{k})")
        lines.append(f"    buf[TI{k}] = ji.transpose{axes} + 0.0")
        lines.append(f"    buf[TJ{k}] += jj.transpose{axes}")

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
    """q̇: ν is zero on the joints' rows and ψ̇ on the drivers' (rows n_j …), written per
    group (a zero right-hand side still goes through the inverse: NaN where a singular
    block's inverse is, as the general path gives)."""
    n_j = system.n_joint_rows
    for g, p in enumerate(system.plans):
        if (p.rows >= n_j).any():
            lines.append(f"    nu{g} = np.zeros((n, {len(p.rows)}))")
            lines += [
                f"    nu{g}[:, {a}] = psi_d[:, {int(row) - n_j}]"
                for a, row in enumerate(p.rows)
                if row >= n_j
            ]
        else:
            env[f"ZERO{g}"] = len(p.rows)
    lines += _substitution(
        system,
        "qd",
        lambda g: f"nu{g}" if f"ZERO{g}" not in env else f"np.zeros((n, ZERO{g}))",
    )


def _accelerations(system: System, env: dict, lines: list[str], gather) -> None:
    """γ from the gathered poses and the links' rates (stored component-major as the poses
    are, the ground's zeros last), then q̈."""
    n_links = len(system.links)
    lines.append(f"    vr = np.zeros(({n_links + 1}, 3, n))")
    lines.append(f"    vr[:{n_links}] = qd.reshape(n, {n_links}, 3).transpose(1, 2, 0)")
    lines.append("    ve = vr.transpose(2, 0, 1)")
    lines.append(f"    gam = np.empty(({system.n_rows}, n)).T")
    for k, s in enumerate(system.sets):
        qi, qj = gather[k]
        env[f"R{k}"] = s.rows if s.stacked else s.rows[0]
        if s.stacked:
            lines.append(f"    vi = np.take(ve, EI{k}, axis=1)")
            lines.append(f"    vj = np.take(ve, EJ{k}, axis=1)")
        else:
            lines.append(f"    vi = ve[:, {int(s.ends[0, 0])}, :]")
            lines.append(f"    vj = ve[:, {int(s.ends[1, 0])}, :]")
        extra = "" if s.driver is None else f", psi_dd[:, {s.driver}]"
        lines.append(f"    gam[:, R{k}] = C{k}.acceleration_rhs({qi}, {qj}, vi, vj{extra})")
    lines += _substitution(system, "qdd", lambda g: f"gam[:, ROWS{g}]")
