"""The cycle quadrature's interpolants (base/legendre.py)."""

from __future__ import annotations

import numpy as np
import numpy.polynomial.legendre as leg

from kinetostatics.base.legendre import inner_roots, padded_roots, piece_series


def test_a_pieces_series_is_the_polynomial_through_its_nodes():
    """On each piece the series through the n Gauss–Legendre node values of a polynomial
    of degree n − 1 is that polynomial: (x − 0.3)(x + 0.5)(x − 0.9) on two pieces, its
    roots inside (−1, 1) found again."""
    x, _ = leg.leggauss(4)
    p = np.polynomial.Polynomial.fromroots([0.3, -0.5, 0.9])
    coef = piece_series(2, np.concatenate((p(x), 2 * p(x))))
    np.testing.assert_allclose(leg.legval(0.1, coef[0]), p(0.1), rtol=1e-14)
    for inner in inner_roots(padded_roots(coef)):
        np.testing.assert_allclose(inner, [-0.5, 0.3, 0.9], atol=1e-14)
    assert np.isnan(inner_roots(np.array([[1.5, 0.2 + 1e-3j, -1.0, np.nan]]))).all()


def test_the_pieces_roots_are_numpys_legroots():
    """The roots of all pieces' series in one eigenvalue call per degree (the flywheel's
    extremes, the cuts' dips): each the roots numpy's legroots gives, to the bit (trailing zeros, a
    constant and a zero series included)."""
    import numpy.polynomial.legendre as leg

    from kinetostatics.base.legendre import series_roots

    rng = np.random.default_rng(11)
    for n in (1, 2, 3, 6, 9):
        c = rng.standard_normal((40, n)) * np.logspace(-6, 6, 40)[:, None]
        c[3, -1] = 0.0
        c[4, 1:] = 0.0
        c[5] = 0.0
        for mine, theirs in zip(series_roots(c), [leg.legroots(row) for row in c]):
            np.testing.assert_array_equal(mine, theirs)
            assert mine.shape == theirs.shape
