"""The group-block inverses (base/linalg.py) against LAPACK, and the solves built on them.

The truth is ``np.linalg.inv`` (LAPACK's LU with partial pivoting), ``np.linalg.pinv``
for singular blocks, and the defining identity A A⁻¹ = I; the analyses at many positions
with the blocks inverted by the elimination over their nonzeros against the same
analyses with LAPACK inverting them.
"""

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base import blocks as blocks_module
from kinetostatics.base import linalg
from kinetostatics.base.blocks import BlockFactor
from kinetostatics.base.linalg import small_inverse
from tests.helpers import MECHANISMS

RNG = np.random.default_rng(11)


def _well_conditioned(count: int, n: int) -> np.ndarray:
    """Random matrices with condition numbers below ~10 (orthogonal × diag(1..10) × orthogonal)."""
    u, _ = np.linalg.qr(RNG.normal(size=(count, n, n)))
    v, _ = np.linalg.qr(RNG.normal(size=(count, n, n)))
    return u * RNG.uniform(1.0, 10.0, size=(count, 1, n)) @ v


def _dominant(count: int, n: int, density: float) -> np.ndarray:
    """Random matrices ``(count, n, n)`` sharing a random sparsity pattern, each strictly
    diagonally dominant by columns (|diagonal| in [n, 2n], the others in [−1, 1]) and
    then all with their rows in one random order: partial pivoting picks the same rows
    for every one of them (a column-dominant matrix needs no interchange), and the
    condition numbers stay below ~10."""
    mask = (RNG.random((n, n)) < density) | np.eye(n, dtype=bool)
    a = RNG.uniform(-1.0, 1.0, size=(count, n, n)) * mask
    diag = RNG.uniform(n, 2 * n, size=(count, n)) * RNG.choice([-1.0, 1.0], size=(count, n))
    a[:, np.arange(n), np.arange(n)] = diag
    return a[:, RNG.permutation(n)]


def _sparse(a: np.ndarray) -> np.ndarray:
    """small_inverse's elimination over the pattern, whatever the count (no choice)."""
    n = a.shape[-1]
    m = np.moveaxis(a, (-2, -1), (0, 1)).reshape(n, n, -1)
    plan = linalg._plan(np.any(m != 0, axis=-1), linalg._first_pivots(m[:, :, 0]))
    return np.moveaxis(linalg._sparse_gauss_jordan(m, plan), -1, 0).reshape(a.shape)


def _assert_inverse(x: np.ndarray, a: np.ndarray, factor: float = 50.0) -> None:
    """x = LAPACK's inverse and x·a = I, each matrix to factor·ε·cond(a) of its scale."""
    cond = np.linalg.cond(a)[:, None, None]
    ref = np.linalg.inv(a)
    scale = np.abs(ref).max(axis=(-2, -1), keepdims=True)
    tol = factor * np.finfo(float).eps * cond
    assert np.all(np.abs(x - ref) <= tol * scale)
    assert np.all(np.abs(x @ a - np.eye(a.shape[-1])) <= tol)


def _takes_elimination(a: np.ndarray) -> None:
    """small_inverse will invert this stack by the elimination (else the test would
    not test it)."""
    n = a.shape[-1]
    plan = linalg._plan(np.any(a != 0, axis=0), linalg._first_pivots(a[0]))
    assert len(a) >= linalg.SPARSE_FROM and linalg._sparse_pays(n, len(a), plan)


@pytest.fixture
def no_lapack(monkeypatch):
    """Every matrix through the elimination: a fall back to LAPACK fails the test."""

    def refuse(a):
        raise AssertionError(f"{len(a)} matrices fell back to LAPACK")

    monkeypatch.setattr(linalg, "_lapack_inverse", refuse)


@pytest.mark.parametrize("n", [1, 2, 3, 4, 6, 9])
@pytest.mark.parametrize("count", [5, 3000])
def test_inverse_agrees_with_lapack(n, count):
    a = _well_conditioned(count, n)
    x = small_inverse(a)
    np.testing.assert_allclose(x, np.linalg.inv(a), rtol=0, atol=1e-13 * np.abs(x).max())
    np.testing.assert_allclose(x @ a, np.broadcast_to(np.eye(n), a.shape), atol=1e-13)


@pytest.mark.parametrize("n", [4, 6, 9])
@pytest.mark.parametrize("density", [0.0, 0.25, 0.5, 1.0])
@pytest.mark.parametrize("count", [5, 3000])
def test_elimination_over_random_patterns(n, density, count, no_lapack):
    """Random sparsity patterns, rows permuted: the elimination over the nonzeros alone
    (fill-in included) gives LAPACK's inverse, for few matrices and for thousands."""
    a = _dominant(count, n, density)
    with np.errstate(all="raise"):
        x = _sparse(a)
    _assert_inverse(x, a)


@pytest.mark.parametrize("n", [4, 6, 9])
def test_small_inverse_takes_the_elimination_for_many_sparse_blocks(n, no_lapack):
    a = _dominant(3000, n, 0.3)
    _takes_elimination(a)
    x = small_inverse(a)  # LAPACK refused: the elimination served all
    _assert_inverse(x, a)
    assert np.moveaxis(x, (-2, -1), (0, 1)).flags.c_contiguous  # entry-major


def test_an_entry_zero_in_some_matrices_only(no_lapack):
    """The pattern is the union over the stack: an entry zero in the first matrix (and
    every other one) but not in the rest is still eliminated."""
    a = _dominant(3000, 6, 0.3)
    zero = np.argwhere(np.abs(a[0]) < 2.0)  # off-diagonal entries of the pattern or not
    i, j = zero[len(zero) // 2]
    a[:, i, j] = RNG.uniform(0.5, 1.0, size=3000)
    a[::2, i, j] = 0.0
    assert a[0, i, j] == 0.0 and a[1, i, j] != 0.0
    x = small_inverse(a)
    _assert_inverse(x, a)


def test_first_pivots_are_those_of_lu_with_partial_pivoting():
    """The row order read off LAPACK's getrf (scipy.linalg.lu_factor's interchanges)."""
    scipy_linalg = pytest.importorskip("scipy.linalg")
    for n in (4, 6, 9):
        for _ in range(20):
            mask = RNG.random((n, n)) < 0.6
            a = RNG.normal(size=(n, n)) * mask + np.diag(RNG.normal(size=n)) * 1e-3
            _, piv = scipy_linalg.lu_factor(a)
            order = list(range(n))
            for k, p in enumerate(piv):
                order[k], order[p] = order[p], order[k]
            assert linalg._first_pivots(a) == order


def test_elimination_falls_back_where_the_first_matrix_pivots_do_not_serve():
    """The rows are ordered by the first matrix's pivots; a matrix needing another order
    is inverted by LAPACK: one with a zero where the first had its pivot (not divided by
    zero), one where that pivot is 1e-13 of its column (eliminated on it, it would lose
    ~13 digits)."""
    a = _dominant(3000, 6, 0.3)
    a[:, 0, 1] = RNG.uniform(0.5, 1.0, size=3000)  # nonzero somewhere in the stack
    a[0] = np.diag([5.0, 4.0, 3.0, 2.0, 1.5, 1.0])
    a[7] = np.eye(6)[[1, 0, 2, 3, 4, 5]]  # a permutation: a zero on the first's pivot
    a[9] = np.eye(6)
    a[9, :2, :2] = [[1e-13, 1.0], [1.0, 1.0]]
    _takes_elimination(a)
    x = small_inverse(a)
    np.testing.assert_allclose(x[7], a[7].T, atol=1e-15)
    np.testing.assert_allclose(x[9], np.linalg.inv(a[9]), rtol=1e-15, atol=1e-15)
    _assert_inverse(x, a)


@pytest.mark.parametrize("n", [2, 3, 4, 6, 9])
@pytest.mark.parametrize("count", [4, 3000])
def test_singular_and_nonfinite_blocks(n, count):
    """An exactly singular block gets its pseudo-inverse; a block with a NaN gives NaN
    there and leaves the others exact."""
    a = _dominant(count, n, 0.3) if n > 3 else _well_conditioned(count, n)
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


def test_a_nan_anywhere_in_the_pattern_gives_nan():
    """A NaN on each nonzero of the pattern in turn (a pivot, below or above one, or an
    entry that only feeds fill-in): that matrix's inverse has NaN, the others are exact."""
    a = _dominant(200, 6, 0.4)
    for i, j in np.argwhere(np.any(a != 0, axis=0)):
        b = a.copy()
        b[50, i, j] = np.nan
        x = _sparse(b)
        assert np.isnan(x[50]).any(), (i, j)
        assert not np.isnan(np.delete(x, 50, axis=0)).any()


@pytest.mark.parametrize("density", [0.0, 0.3])
def test_a_zero_pivot_is_caught_even_alone_in_its_column(density):
    """One matrix with a zero where the others have their pivot — alone in its column
    when the pattern is diagonal: it is singular and gets its pseudo-inverse, not 1/0."""
    a = _dominant(3000, 6, density)
    _takes_elimination(a)
    k = int(np.argmax(np.abs(a[50, :, 3])))  # column 3's pivot (its dominant entry)
    a[50, k, 3] = 0.0
    x = small_inverse(a)
    np.testing.assert_allclose(x[50], np.linalg.pinv(a[50]), atol=1e-14)
    _assert_inverse(np.delete(x, 50, axis=0), np.delete(a, 50, axis=0))


def test_all_singular_in_the_first_matrix_order():
    """A column zero in every matrix (no pivot there for any of them): every matrix
    singular, each gets its pseudo-inverse."""
    a = _dominant(2500, 6, 0.3)
    a[:, :, 2] = 0.0
    assert not linalg._plan(np.any(a != 0, axis=0), linalg._first_pivots(a[0])).feasible
    x = small_inverse(a)
    np.testing.assert_allclose(x, np.linalg.pinv(a), atol=1e-13)


def test_layouts_give_the_same_inverses_and_leave_the_input():
    """Entries position-fastest (as the blocks are built), position-major, and stacked
    variants ``(V, N, n, n)``: the same inverses to the bit, each entry contiguous over
    the positions (as the blocks; the solves run on it); the input untouched."""
    a = _dominant(3000, 6, 0.3)
    _takes_elimination(a)
    keep = a.copy()
    component_major = np.ascontiguousarray(np.moveaxis(a, 0, -1))
    x = small_inverse(a)
    assert np.array_equal(a, keep)
    y = small_inverse(np.moveaxis(component_major, -1, 0))
    z = small_inverse(np.moveaxis(component_major.reshape(6, 6, 3, 1000), (0, 1), (-2, -1)))
    assert np.array_equal(x, y) and np.array_equal(x.reshape(z.shape), z)
    for inv in (x, y, z):
        assert np.moveaxis(inv, (-2, -1), (0, 1)).flags.c_contiguous
    _assert_inverse(x, a)
    b = _well_conditioned(3000, 3)
    small = small_inverse(b)  # the adjugate's, likewise
    assert np.moveaxis(small, (-2, -1), (0, 1)).flags.c_contiguous
    _assert_inverse(small, b)


@pytest.mark.parametrize("rows_from", [None, 0])
def test_block_solves_match_a_dense_solve(rows_from, monkeypatch):
    """Forward and back substitution over the groups = the dense solves of the whole Φ_q
    (the back substitution also as it runs over many positions: component-major, as
    ``solve_transposed_rows`` with one right-hand side, ``rows_from`` 0)."""
    if rows_from is not None:
        monkeypatch.setattr(blocks_module, "TRANSPOSED_ROWS_FROM", rows_from)
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
    rows = RNG.normal(size=(50, 4, 9))  # four right-hand sides at once, as rows
    np.testing.assert_allclose(
        lu.solve_transposed_rows(rows),
        np.swapaxes(np.linalg.solve(np.swapaxes(jac, -1, -2), np.swapaxes(rows, -1, -2)), -1, -2),
        atol=1e-12,
    )


@pytest.mark.parametrize("name", ["slider_crank", "slotting_machine"])
def test_elimination_and_lapack_give_the_same_analysis(name, monkeypatch):
    """At 4,000 positions the 6×6 dyad blocks are inverted by the elimination over their
    nonzeros, and with it disabled by LAPACK: positions, velocities, accelerations and
    group conditions agree to round-off (of the largest value of each)."""
    path = next(p for p in MECHANISMS if p.stem == name)
    phi = ks.load(path).analysis.start + np.linspace(0.0, 2 * np.pi, 4000, endpoint=False)
    calls = []
    sparse = linalg._sparse_gauss_jordan
    monkeypatch.setattr(linalg, "_sparse_gauss_jordan", lambda *a: calls.append(1) or sparse(*a))
    whole = ks.analyze(ks.load(path), positions=phi, kinematics_only=True)
    assert calls
    monkeypatch.setattr(linalg, "SPARSE_FROM", 10**9)
    lapack = ks.analyze(ks.load(path), positions=phi, kinematics_only=True)
    conds = [c for c in whole.columns if c.endswith(".cond")]
    assert conds
    pairs = [(whole.q, lapack.q), (whole.qd, lapack.qd), (whole.qdd, lapack.qdd)]
    pairs += [(np.asarray(whole[c]), np.asarray(lapack[c])) for c in conds]
    for a, b in pairs:
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(a).max())


@pytest.mark.parametrize("name", ["slider_crank", "slotting_machine", "watt_sixbar"])
def test_products_by_the_blocks_equal_the_dense_transpose(name):
    """Φ_qᵀ y by the group blocks (the friction solutions' A x, with coupling blocks over
    the touched columns only) against the dense Φ_q assembled entry by entry."""
    from kinetostatics.structure.system import jacobian, jacobian_blocks, system_of

    model = ks.load(MECHANISMS[0].parent / f"{name}.yaml")
    system = system_of(model)
    q = ks.analyze(model, positions=np.linspace(0.0, 6.0, 50), kinematics_only=True).q
    blocks = [(p.rows, p.cols) for p in system.plans]
    lu = BlockFactor(None, blocks, jacobian_blocks(system, q))
    dense = jacobian(system, q)
    y = RNG.normal(size=q.shape[:-1] + (dense.shape[-2],))
    want = np.einsum("...ji,...j->...i", dense, y)
    np.testing.assert_allclose(
        lu.product_transposed(y), want, rtol=0, atol=1e-13 * np.abs(want).max()
    )
    # the same stored component-major (the friction residual's): y and the product (n, ...)
    got = lu.product_transposed_components(np.ascontiguousarray(np.moveaxis(y, -1, 0)))
    np.testing.assert_allclose(
        np.moveaxis(got, 0, -1), want, rtol=0, atol=1e-13 * np.abs(want).max()
    )
    np.testing.assert_array_equal(lu.transposed_at(7), dense[7].T)
    # Φ_qᵀ yᵢ = rᵢ for several right-hand sides as rows (the friction efforts'), by the blocks
    r = RNG.normal(size=q.shape[:-1] + (3, dense.shape[-1]))
    want = np.swapaxes(np.linalg.solve(np.swapaxes(dense, -1, -2), np.swapaxes(r, -1, -2)), -1, -2)
    np.testing.assert_allclose(
        lu.solve_transposed_rows(r), want, rtol=0, atol=1e-11 * np.abs(want).max()
    )
    # right-hand sides stored as the friction setup stores its gradients (a view of
    # component-major storage with more columns) give the same numbers, to the bit
    stored = np.zeros((3, dense.shape[-1] + 3) + q.shape[:-1])
    stored[:, : dense.shape[-1]] = np.moveaxis(r, (-2, -1), (0, 1))
    view = np.moveaxis(stored[:, : dense.shape[-1]], (0, 1), (-2, -1))
    np.testing.assert_array_equal(lu.solve_transposed_rows(view), lu.solve_transposed_rows(r))


@pytest.mark.parametrize("n", [3, 6])
@pytest.mark.parametrize("count", [5, 3000])
@pytest.mark.parametrize("layout", ["a slice of a longer run", "axes out of order"])
def test_inverse_written_into_a_given_output(n, count, layout):
    """With ``out`` (entry-major ``(n, n, count)``), the adjugate, the elimination and
    LAPACK write the inverses there, whatever the output's strides (a chunk of a longer
    run, as the kinematic plan gives; axes a reshape cannot merge), and return its view."""
    a = _dominant(count, n, 0.3) if n > 3 else _well_conditioned(count, n)  # 6x6: sparse
    # (last in the module: its draws leave the shared generator's sequence of the others)
    if layout == "a slice of a longer run":
        out = np.zeros((n, n, count + 7))[..., 3 : 3 + count]
    else:
        out = np.zeros((n, count, n)).transpose(0, 2, 1)
    x = small_inverse(a, out=out)
    assert np.shares_memory(x, out)
    want = np.linalg.inv(a)
    np.testing.assert_allclose(x, want, rtol=0, atol=1e-13 * np.abs(want).max())
    np.testing.assert_array_equal(out.transpose(2, 0, 1), x)
