"""Newton per Assur group: one group's block of Φ = 0 solved for its columns, batched
over positions, with the group's condition number and branch signature.

The tolerances of the position solve are here: ``TOL`` (Newton's, relative to L_ref
and 1 rad), and derived from it ``DISC_TOL`` (a closed-form dyad's discriminant at a
singular position, :mod:`.closed_path`) and ``SINGULAR_COND`` (the condition number
from which a located sign change of a group's determinant is a singular position,
:mod:`.continuation`).
"""

from __future__ import annotations

import numpy as np

from ..base.arrays import entries_first
from ..base.trace import Lines, Sym, larger
from ..structure.system import GroupPlan, System, jacobian, phi

__all__ = [
    "TOL",
    "MAX_ITER",
    "DISC_TOL",
    "SINGULAR_COND",
    "condition_number",
    "block_condition",
    "traced_condition",
    "group_condition",
    "group_signature",
    "group_newton",
]

TOL = 1e-12  # Newton tolerance relative to L_ref (and 1 rad)
MAX_ITER = 25
DISC_TOL = 100 * TOL  # a closed-form dyad's normalised discriminant D at or below which it
# is singular (its lengths within ~50·TOL of its own scale of a toggle)
SINGULAR_COND = DISC_TOL**-0.5  # a group's condition number from which a located sign change of
# its determinant is a singular position (a dyad's: ~1/√D)


def _scales(system: System, jac: np.ndarray, plan: GroupPlan) -> tuple[np.ndarray, np.ndarray]:
    """Column (unit) and row (equilibration) scales of a group block."""
    l_ref = np.asarray(system.l_ref)[..., None]  # (V, 1, 1) for stacked variants
    col = np.where(np.arange(len(plan.cols)) % 3 == 2, 1.0, l_ref)  # d/d(x/L) = L d/dx
    norm = np.max(np.abs(jac * col[..., None, :]), axis=-1)
    return col, 1.0 / np.where(norm > 0, norm, 1.0)


def _scaled_group_jacobian(system: System, q: np.ndarray, plan: GroupPlan) -> np.ndarray:
    jac = jacobian(system, q, plan.constraints, plan.cols)
    col, row = _scales(system, jac, plan)
    return jac * col[..., None, :] * row[..., None]


def condition_number(
    system: System, plan: GroupPlan, jac: np.ndarray, inv: np.ndarray
) -> np.ndarray:
    """Frobenius-norm condition number ‖S‖_F ‖S⁻¹‖_F of the group's scaled block
    S = D_r J D_c (lengths over L_ref, rows equilibrated), from J and J⁻¹, ``(...)``.

    It bounds the 2-norm condition number from above by at most the block size.
    """
    # entry-major views (k, k, ...): every operation runs along the positions (the blocks
    # are stored so; a trailing axis of k under a broadcast would run k entries per loop)
    j_t, inv_t = entries_first(jac), entries_first(inv)
    ang = (np.arange(len(plan.cols)) % 3 == 2).reshape((-1,) + (1,) * (j_t.ndim - 2))
    col = np.where(ang, 1.0, system.l_ref)  # as _scales; L_ref is (V, 1) for stacked variants
    n = j_t.shape[-1] if j_t.ndim > 2 else 1
    if n <= COND_CHUNK:
        return _condition(j_t, inv_t, col)
    cuts = np.linspace(0, n, -(-n // COND_CHUNK) + 1).astype(int)  # alike, none tiny
    return np.concatenate(  # the same numbers, with smaller temporaries (COND_CHUNK)
        [_condition(j_t[..., a:b], inv_t[..., a:b], col) for a, b in zip(cuts, cuts[1:])],
        axis=-1,
    )


COND_CHUNK = 8192
"""Positions per pass of :func:`condition_number` at most, in passes of alike lengths:
the same numbers as one pass (the operations are per position; a pass of one position
would sum its 36 squares in another order), with temporaries of ~2.4 MB for a 6×6
block instead of ~10 MB over 36,000 positions.  Measured there on the slotting
machine's two groups: 17.5 ms in one pass, 10.9 in chunks of 2,048, 7.6 of 8,192, 8.4
of 16,384 — the large temporaries cost fresh memory each time (tests/structure/test_evaluation.py
checks the bits)."""


def _condition(j_t: np.ndarray, inv_t: np.ndarray, col: np.ndarray) -> np.ndarray:
    """‖S‖_F ‖S⁻¹‖_F from the entries ``j_t``, ``inv_t (k, k, ...)`` and the column scales
    ``col``: with a_ij = |J_ij c_j| and each row's largest m_i, ‖S‖² = Σ_i (Σ_j a_ij²) / m_i²
    and ‖S⁻¹‖² = Σ_i (Σ_j (J⁻¹_ij m_j)²) / c_i² — five passes over the entries, the
    scaled blocks never formed (they took nine)."""
    a = j_t * col
    np.abs(a, out=a)
    norm = np.max(a, axis=1)
    norm = np.where(norm > 0, norm, 1.0)  # a zero row: S's row left unscaled, as D_r's
    a_sq = np.einsum("ij...,ij...->i...", a, a)
    a = np.multiply(inv_t, norm, out=a)  # J⁻¹_ij m_j (j the second axis, norm's first)
    inv_sq = np.einsum("ij...,ij...->i...", a, a)
    with np.errstate(over="ignore", invalid="ignore"):
        c = np.sqrt(np.sum(a_sq / (norm * norm), axis=0)) * np.sqrt(
            np.sum(inv_sq / (col * col), axis=0)
        )  # each norm on its own: their product overflows only past the largest float
    return np.where(np.isfinite(c), c, np.inf)


def block_condition(j_t: np.ndarray, inv_t: np.ndarray, l_ref: float) -> np.ndarray:
    """:func:`condition_number` of one model's blocks ``j_t`` and their inverses ``inv_t``
    ``(k, k, n)`` (entry-major), the group's columns taken in order (x, y, θ per link)."""
    col = np.where(np.arange(len(j_t)) % 3 == 2, 1.0, l_ref).reshape(-1, 1)
    return _condition(j_t, inv_t, col)


def traced_condition(lines: Lines, m: list, inv: list, l_ref: float, arrays: bool = False):
    """:func:`condition_number` of a group's block ``m`` and its inverse ``inv`` (traced
    values: :mod:`~kinetostatics.base.trace`), a number folded where the entries are:
    a_ij = |J_ij c_j|, each row's largest m_i (1 for a zero row), ‖S‖² = Σ_i (Σ_j a_ij²)
    / m_i², ‖S⁻¹‖² summed by columns, Σ_j m_j² Σ_i (J⁻¹_ij / c_i)², so that the inverse's
    entries that are numbers (a revolute pair's ±1) fold into one number per column, ∞
    where not finite; a_ij² is written (J_ij c_j)² and m_i² the largest of a row's, no
    |·| taken (the same numbers).  Written for a program of scalars (base/program.py), or
    over whole arrays (``arrays``: ``np.maximum``; ``sqrt`` and ``positive_or_one``
    the caller's names for :data:`WHOLE_ARRAY_NAMES`), where the positions whose
    entries are not all finite, or whose block is inverted again, get
    :func:`condition_number`'s own number after it (kinematics/plan_inverse.py): there a
    row's largest is not tested for zero where the row holds a positive number (it is
    positive wherever it is not NaN), nor the product for ∞ (it is finite or ∞ wherever
    it is not NaN)."""
    fmax = "np.maximum" if arrays else "max"
    k = len(m)
    col = [1.0 if j % 3 == 2 else l_ref for j in range(k)]
    scaled = [[m[i][j] * col[j] for j in range(k)] for i in range(k)]
    a2 = [[x * x for x in row] for row in scaled]  # a_ij², no |·| taken: (|x|)² is x²
    square = []  # m_i², the largest a_ij² (a square's order is its magnitude's)
    for row in a2:
        top = _largest(lines, row, fmax)
        if not (arrays and any(not isinstance(x, Sym) and x > 0 for x in row)):
            top = _unary(lines, "positive_or_one", top, lambda x: x if x > 0 else 1.0)
        square.append(top)
    first = _sum(_sum(row) / square[i] for i, row in enumerate(a2))
    by_col = [_sum(inv[i][j] * inv[i][j] / (col[i] * col[i]) for i in range(k)) for j in range(k)]
    second = _sum(square[j] * by_col[j] for j in range(k))
    c = _unary(lines, "sqrt", first, np.sqrt) * _unary(lines, "sqrt", second, np.sqrt)
    if arrays:
        return c
    return _unary(lines, "finite_or_inf", c, lambda x: x if abs(x) < np.inf else np.inf)


def _largest(lines: Lines, row: list, fn: str):
    """The largest of magnitudes (traced), NaN where one is: a zero beside them changes
    no maximum (nor a NaN)."""
    top, *rest = [x for x in row if isinstance(x, Sym) or x != 0.0] or [0.0]
    for x in rest:
        top = larger(lines, top, x, fn)
    return top


WHOLE_ARRAY_NAMES = {"sqrt": np.sqrt, "positive_or_one": lambda x: np.where(x > 0, x, 1.0)}
"""The functions :func:`traced_condition`'s lines call over whole arrays, by name."""


def _sum(terms):
    """Σ of traced terms in order, from the first (as ``einsum`` and ``np.sum`` add), the
    numbers among them first (added at once: one number, not a line each)."""
    terms = sorted(terms, key=lambda t: isinstance(t, Sym))  # stable: each kind in order
    acc = 0.0
    for t in terms:
        acc = acc + t
    return acc


def _unary(lines: Lines, name: str, x, of_number):
    return lines.value(f"{name}({x.name})") if isinstance(x, Sym) else float(of_number(x))


def group_condition(system: System, q: np.ndarray, plan: GroupPlan) -> np.ndarray:
    """Condition number of a group at positions q (see :func:`condition_number`)."""
    jac = jacobian(system, q, plan.constraints, plan.cols)
    try:
        inv = np.linalg.inv(jac)
    except np.linalg.LinAlgError:
        inv = np.full(jac.shape, np.inf)
    return condition_number(system, plan, jac, inv)


def group_signature(system: System, q: np.ndarray, plan: GroupPlan) -> np.ndarray:
    return np.sign(np.linalg.det(_scaled_group_jacobian(system, q, plan)))


def group_newton(
    system: System, q: np.ndarray, psi: np.ndarray, plan: GroupPlan, max_iter: int = MAX_ITER
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Batched Newton on one group (other columns fixed), ``q (..., n_q)``; a stacked
    system's variant axis stays aligned with its parameters (no subsets are taken).

    Returns (q, converged (...), iterations (...)).  Positions that converge
    stop updating; the batch iterates until all converged or ``max_iter``.
    """
    q = np.array(q, dtype=float)
    cols = plan.cols
    ang = np.arange(len(cols)) % 3 == 2
    l_ref = np.asarray(system.l_ref)
    l_col = l_ref[..., None] if l_ref.ndim else l_ref
    step_tol = np.where(ang, TOL, TOL * l_col)
    res_tol = TOL * l_ref
    batch = q.shape[:-1]
    done = np.zeros(batch, dtype=bool)
    iters = np.zeros(batch, dtype=int)
    active = np.ones(batch, dtype=bool)
    for _ in range(max_iter):
        run = active & ~done
        if not run.any():
            break
        r = phi(system, q, psi, plan.constraints)
        jac = jacobian(system, q, plan.constraints, cols)
        with np.errstate(all="ignore"):
            try:
                dx = np.linalg.solve(jac, -r[..., None])[..., 0]
            except np.linalg.LinAlgError:  # a singular matrix somewhere in the batch
                dx = (np.linalg.pinv(jac) @ -r[..., None])[..., 0]
        bad = ~np.all(np.isfinite(dx), axis=-1)
        dx = np.where((bad | ~run)[..., None], 0.0, dx)
        q[..., cols] += dx
        iters += run
        small = np.all(np.abs(dx) <= step_tol, axis=-1) & (
            np.max(np.abs(r), axis=-1) <= res_tol * 1e3
        )
        big = np.max(np.abs(dx) / np.where(ang, 1.0, l_col), axis=-1) > 1e3
        done |= run & small & ~bad
        active &= ~(run & (bad | big))
    # final residual check
    r = np.max(np.abs(phi(system, q, psi, plan.constraints)), axis=-1)
    return q, r <= res_tol, iters
