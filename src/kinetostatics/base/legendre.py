"""The interpolants of the cycle's quadrature (internal): on each piece of the cycle
integral, the Legendre series through the values at its n Gauss–Legendre nodes — the
polynomial the quadrature integrates exactly — and the roots of many such series at once.
The flywheel takes the energy's extremes from them, the cuts the zeros of an effort that
dips through zero and back between two nodes."""

from __future__ import annotations

import numpy as np
import numpy.polynomial.legendre as leg

__all__ = ["piece_series", "series_roots", "padded_roots", "inner_roots"]


def piece_series(n_pieces: int, values: np.ndarray) -> np.ndarray:
    """Per piece (t₀, t₁) of the cycle nodes, the Legendre series through its n node values
    (``values``, piece after piece, n = values.size / n_pieces): ``(P, n)`` coefficients in
    x = (2t − t₀ − t₁)/(t₁ − t₀)."""
    n = values.size // n_pieces
    x, _ = leg.leggauss(n)
    vander = leg.legvander(x, n - 1)
    return np.linalg.solve(vander, values.reshape(n_pieces, n).T).T


def series_roots(coefs: np.ndarray) -> list[np.ndarray]:
    """``[leg.legroots(c) for c in coefs]`` (``coefs (P, n)``) in one eigenvalue call per
    degree: the companion matrices legcompanion builds, by the same operations, each solved
    by the same LAPACK routine — the same roots to the bit."""
    return [r[~np.isnan(r)] for r in padded_roots(coefs)]


def padded_roots(coefs: np.ndarray) -> np.ndarray:
    """:func:`series_roots` as one complex array ``(P, n − 1)``, each series' roots sorted
    and followed by NaN where it has fewer (trailing zero coefficients)."""
    n = coefs.shape[1] - 1
    out = np.full((len(coefs), max(n, 0)), np.nan, dtype=complex)
    full = coefs[:, -1] != 0  # of degree n - 1 (legroots trims trailing zeros)
    for p in np.flatnonzero(~full):
        r = leg.legroots(coefs[p])
        out[p, : len(r)] = r
    rows = np.flatnonzero(full)
    if n == 1:
        out[rows, 0] = -coefs[rows, 0] / coefs[rows, 1]
    elif n > 1 and rows.size:
        c = coefs[rows]
        scl = 1.0 / np.sqrt(2 * np.arange(n) + 1)
        mats = np.repeat(leg.legcompanion(np.eye(n + 1)[n])[None], len(rows), axis=0)
        mats[:, :, -1] -= (c[:, :-1] / c[:, -1:]) * (scl / scl[-1]) * (n / (2 * n - 1))
        out[rows] = np.sort(np.linalg.eigvals(mats[:, ::-1, ::-1]), axis=-1)
    return out


def inner_roots(roots: np.ndarray) -> np.ndarray:
    """Of each series' roots (:func:`padded_roots`, ``(P, m)``), its real ones inside
    (−1, 1), sorted and followed by NaN: ``(P, m)``."""
    inside = (roots.imag == 0) & (np.abs(roots.real) < 1)  # the NaN padding is not
    return np.sort(np.where(inside, roots.real, np.nan), axis=1)
