"""The kinematic plan's written block inverses against ``small_inverse``, which they stand
for: its numbers (the same operations) wherever ``small_inverse`` would run the same
elimination, and ``small_inverse`` itself elsewhere."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base.arrays import entries_first
from kinetostatics.base.linalg import small_inverse
from kinetostatics.base.trace import Lines
from kinetostatics.kinematics import plan
from kinetostatics.kinematics.newton import block_condition
from kinetostatics.kinematics.plan_buffers import NOZERO
from kinetostatics.kinematics.plan_inverse import RUNTIME, TRACED_FROM, inverse_line
from kinetostatics.structure.system import system_of

ROOT = Path(__file__).resolve().parents[2]


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """The same inverses ``(N, n, n)``: NaN where small_inverse gives NaN, elsewhere each
    matrix within 1e-13 of its own largest entry (the operations are the same; the bound
    holds on any CPU)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape or not np.array_equal(np.isnan(a), np.isnan(b)):
        return False
    scale = np.nanmax(np.abs(b), axis=(-2, -1), initial=0.0)
    err = np.nanmax(np.abs(a - b), axis=(-2, -1), initial=0.0)
    return bool(np.all(err <= 1e-13 * scale))


def _written(m: list[list], first: np.ndarray, l_ref: float | None = None):
    """The function inverse_line writes for the block ``m`` (its leaves the locals
    ``e<k>`` of the entries marked "x", RUNTIME read from the buffer), and a caller:
    ``call(stack (N, n, n)) -> inverses (N, n, n)``."""
    outer, env = Lines(), {}
    names = iter(range(99))
    block = [[outer.value(f"X{next(names)}") if x == "x" else x for x in row] for row in m]
    n = len(m)
    written = inverse_line(env, 0, (0, n, n), "VIEW", block, first, l_ref)
    call, source = written.call, written.source
    exec("\n".join(source), env)  # noqa: S102  the test's own generated text
    args = re.findall(r"\be\d+\b", call)
    where = {
        s.name: (i, j)
        for i, row in enumerate(block)
        for j, s in enumerate(row)
        if hasattr(s, "name")
    }

    def run(stack: np.ndarray) -> np.ndarray:
        view = np.ascontiguousarray(stack.transpose(1, 2, 0)).transpose(2, 0, 1)
        buf = np.ascontiguousarray(stack.reshape(len(stack), -1).T)  # entry (i, j) at i·n + j
        out = np.zeros((n, n, len(stack)))
        leaves = [view[:, i, j] for i, j in map(where.get, args)]
        run.cnd = np.full(len(stack), -1.0)  # written with the inverse, given l_ref
        cnd = [] if l_ref is None else [run.cnd]
        run.redone = env["INVERSE0"](view, out, buf, NOZERO, *cnd, *leaves)  # inverted again
        return out.transpose(2, 0, 1)

    return run


DYAD = [  # a dyad's 6×6 block: revolute ±1 rows and the links' lever arms
    [-1.0, 0.0, "x", 0.0, 0.0, 0.0],
    [0.0, -1.0, "x", 0.0, 0.0, 0.0],
    [1.0, 0.0, "x", -1.0, 0.0, "x"],
    [0.0, 1.0, "x", 0.0, -1.0, "x"],
    [0.0, 0.0, 0.0, "x", "x", RUNTIME],
    [0.0, 0.0, "x", 0.0, 0.0, 1.0],
]


def _dyads(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    pattern = np.array([[x != 0.0 for x in row] for row in DYAD])
    numbers = np.array([[x if isinstance(x, float) else 0.0 for x in row] for row in DYAD])
    stack = np.where(pattern, rng.uniform(-2.0, 2.0, (n, 6, 6)), 0.0)
    fixed = np.array([[isinstance(x, float) for x in row] for row in DYAD])
    return np.where(fixed, numbers, stack)


def test_a_dyad_s_block_is_inverted_as_small_inverse_inverts_it():
    """Hundreds of dyad blocks, a few of them spoilt — a pivot far below its column (sent
    to LAPACK), a NaN entry, an exactly singular matrix — give small_inverse's numbers;
    so does a stack whose first matrix picks another row order, and one of fewer matrices
    than the elimination pays for (both then small_inverse's own call)."""
    stack = _dyads(400, 1)
    run = _written(DYAD, stack[0])
    alike = np.repeat(stack[:1], 400, axis=0)  # the matrix that chose the row order
    assert _same(run(alike), small_inverse(alike)) and run.redone is False
    stack[7, 4, 3], stack[7, 4, 4] = 1e-9, 1e-9  # a pivot ~0 beside larger entries
    stack[11, 2, 5] = np.nan
    stack[13, 3, 2], stack[13, 1, 2] = 0.0, 0.0  # singular: column 2 with row 5's alone
    stack[13, 5, 2] = 0.0
    assert _same(run(stack), small_inverse(stack))
    assert run.redone is True  # the plan's substitutions then take the whole blocks
    other = _dyads(400, 2)
    other[0] = other[0][[1, 0, 2, 3, 4, 5]][:, [0, 1, 2, 3, 4, 5]]  # another first order
    assert _same(run(other), small_inverse(other))
    assert _same(run(stack[:12]), small_inverse(stack[:12]))  # LAPACK below 32 matrices


@pytest.mark.parametrize("n", [TRACED_FROM + 100, 400, 12])
def test_the_condition_numbers_written_with_an_inverse_are_condition_number_s(n):
    """With L_ref the written inverse also gives each block's condition number — traced
    from the same entries at any number of matrices, over TRACED_FROM as below it —
    condition_number's numbers (1e-12 of each), ∞ where it gives ∞, at the
    matrices inverted again too (a pivot ~0, a NaN entry, an exactly singular block) and
    where the whole call is small_inverse's (fewer matrices than pay)."""
    stack = _dyads(TRACED_FROM + 100, 4)[:n]
    stack[7, 4, 3], stack[7, 4, 4] = 1e-9, 1e-9
    stack[11, 2, 5] = np.nan
    stack[10, 3, 2], stack[10, 1, 2], stack[10, 5, 2] = 0.0, 0.0, 0.0
    run = _written(DYAD, stack[0], l_ref=0.35)
    inv = run(stack)
    want = block_condition(entries_first(stack), entries_first(inv), 0.35)
    assert _same(inv, small_inverse(stack)) and run.redone is True
    assert np.array_equal(np.isfinite(run.cnd), np.isfinite(want))
    ok = np.isfinite(want)
    assert np.all(np.abs(run.cnd[ok] - want[ok]) <= 1e-12 * want[ok])
    assert (run.cnd >= 1.0).all()  # none left unwritten


def test_a_three_by_three_block_is_the_adjugate_with_singular_matrices_pseudo_inverted():
    """Up to 3×3 the adjugate, at any number of matrices; an exactly singular one gets its
    pseudo-inverse and one with a NaN entry NaN, as small_inverse gives them."""
    m = [[-1.0, 0.0, "x"], [0.0, -1.0, "x"], [0.0, 0.0, RUNTIME]]
    rng = np.random.default_rng(3)
    stack = np.zeros((50, 3, 3))
    stack[:, 0, 0] = stack[:, 1, 1] = -1.0
    stack[:, :, 2] = rng.uniform(-1.0, 1.0, (50, 3))
    stack[5, 2, 2] = 0.0
    stack[7, 1, 2] = np.nan  # NaN through every entry the adjugate divides by its det
    run = _written(m, None)
    assert _same(run(stack), small_inverse(stack)) and run.redone is True
    assert _same(run(stack[:3]), small_inverse(stack[:3])) and run.redone is False


@pytest.mark.parametrize(
    "name",
    ["slider_crank", "slotting_machine", "jaw_crusher", "stephenson_sixbar", "geared_fivebar"],
)
def test_the_plan_s_inverses_are_small_inverse_s(name, monkeypatch):
    """On shipped files, once the plan is made (by its eighth analysis, PLAN_AFTER as
    (8, 5000) here; a triad's too, PLANNED_BLOCKS lifted), every group block's inverse it
    gives equals small_inverse of the same block, a zero's sign aside, at 10, 360 and
    1,000 positions (one chunk); the written inverses are in the plan's text."""
    monkeypatch.setattr(plan, "PLAN_AFTER", (8, 5000))
    monkeypatch.setattr(plan, "PLANNED_BLOCKS", 10**9)  # the triad's too
    got = []
    made = plan.BlockFactor
    monkeypatch.setattr(plan, "BlockFactor", lambda *a, **k: got.append(made(*a, **k)) or got[-1])
    text = (ROOT / "mechanisms" / f"{name}.yaml").read_text(encoding="utf-8")
    for n in (10, 360, 1000):
        model = ks.loads(re.sub(r"positions: \d+", f"positions: {n}", text))
        for _ in range(9):
            ks.analyze(model, kinematics_only=True)
        lu = got[-1]
        for d, inv in zip(lu.diag, lu.inv):
            assert _same(inv, small_inverse(np.array(d)))
        source = plan.kinematic_plan(system_of(model)).source
        assert "def INVERSE0(" in source
