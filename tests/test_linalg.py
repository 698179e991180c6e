"""The group-block inverses (base/linalg.py) against LAPACK, and the solves built on them.

The truth is ``np.linalg.inv`` (LAPACK's LU with partial pivoting) and the defining
identity A A⁻¹ = I; the analyses at many positions (where the blocks are inverted by
Gauss–Jordan across all positions) against the same positions analysed in small pieces
(where LAPACK inverts them).
"""

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base import linalg
from kinetostatics.base.linalg import BlockFactor, small_inverse

from .conftest import MECHANISMS

RNG = np.random.default_rng(11)


def _well_conditioned(count: int, n: int) -> np.ndarray:
    """Random matrices with condition numbers below ~10 (orthogonal × diag(1..10) × orthogonal)."""
    u, _ = np.linalg.qr(RNG.normal(size=(count, n, n)))
    v, _ = np.linalg.qr(RNG.normal(size=(count, n, n)))
    return u * RNG.uniform(1.0, 10.0, size=(count, 1, n)) @ v


@pytest.mark.parametrize("n", [1, 2, 3, 4, 6, 9])
@pytest.mark.parametrize("count", [5, 3000])
def test_inverse_agrees_with_lapack(n, count):
    a = _well_conditioned(count, n)
    x = small_inverse(a)
    np.testing.assert_allclose(x, np.linalg.inv(a), rtol=0, atol=1e-13 * np.abs(x).max())
    np.testing.assert_allclose(x @ a, np.broadcast_to(np.eye(n), a.shape), atol=1e-13)


def test_gauss_jordan_falls_back_where_the_first_matrix_pivots_do_not_serve():
    """The rows are ordered by the first matrix's pivots; a matrix needing another order
    (a zero where the first had its pivot) is inverted by LAPACK, not divided by zero."""
    a = _well_conditioned(linalg.GAUSS_JORDAN_FROM, 6)
    a[0] = np.diag([5.0, 4.0, 3.0, 2.0, 1.5, 1.0])
    a[7] = np.eye(6)[[1, 0, 2, 3, 4, 5]]  # a permutation: a zero on the first's pivot
    x = small_inverse(a)
    np.testing.assert_allclose(x[7], a[7].T, atol=1e-15)
    np.testing.assert_allclose(x @ a, np.broadcast_to(np.eye(6), a.shape), atol=1e-12)


@pytest.mark.parametrize("n", [2, 3, 6])
@pytest.mark.parametrize("count", [4, 3000])
def test_singular_and_nonfinite_blocks(n, count):
    """An exactly singular block gets its pseudo-inverse; a block with a NaN gives NaN
    there and leaves the others exact."""
    a = _well_conditioned(count, n)
    a[1] = 0.0
    a[1, 0, 0] = 2.0  # rank one: pinv = diag(1/2, 0, …)
    a[2, 0, 0] = np.nan
    x = small_inverse(a)
    np.testing.assert_allclose(x[1], np.linalg.pinv(a[1]), atol=1e-15)
    assert np.isnan(x[2]).any()
    keep = np.ones(count, dtype=bool)
    keep[[1, 2]] = False
    np.testing.assert_allclose(
        x[keep] @ a[keep], np.broadcast_to(np.eye(n), a[keep].shape), atol=1e-12
    )


def test_block_solves_match_a_dense_solve():
    """Forward and back substitution over the groups = the dense solves of the whole Φ_q."""
    blocks = [(np.arange(3), np.arange(3)), (np.arange(3, 9), np.arange(3, 9))]
    jac = np.zeros((50, 9, 9))
    jac[:, :3, :3] = _well_conditioned(50, 3)
    jac[:, 3:, 3:] = _well_conditioned(50, 6)
    jac[:, 3:, :3] = RNG.normal(size=(50, 6, 3))
    lu = BlockFactor(jac, blocks)
    rhs = RNG.normal(size=(50, 9))
    np.testing.assert_allclose(
        lu.solve(rhs), np.linalg.solve(jac, rhs[..., None])[..., 0], atol=1e-12
    )
    np.testing.assert_allclose(
        lu.solve_transposed(rhs),
        np.linalg.solve(np.swapaxes(jac, -1, -2), rhs[..., None])[..., 0],
        atol=1e-12,
    )


@pytest.mark.parametrize("name", ["slider_crank", "slotting_machine"])
def test_many_positions_equal_the_same_positions_in_pieces(name):
    """At 4,000 positions the 6×6 dyad blocks go through Gauss–Jordan, in pieces of 400
    through LAPACK: positions, velocities, accelerations and group conditions agree to
    round-off (of the largest value of each)."""
    model = ks.load(next(p for p in MECHANISMS if p.stem == name))
    phi = model.analysis.start + np.linspace(0.0, 2 * np.pi, 4000, endpoint=False)
    whole = ks.analyze(model, positions=phi, kinematics_only=True)
    conds = [c for c in whole.columns if c.endswith(".cond")]
    assert conds
    for k in range(0, 4000, 400):
        piece = ks.analyze(model, positions=phi[k : k + 400], kinematics_only=True)
        pairs = [(whole.q, piece.q), (whole.qd, piece.qd), (whole.qdd, piece.qdd)]
        pairs += [(np.asarray(whole[c]), np.asarray(piece[c])) for c in conds]
        for a, b in pairs:
            np.testing.assert_allclose(a[k : k + 400], b, rtol=0, atol=1e-12 * np.abs(a).max())
