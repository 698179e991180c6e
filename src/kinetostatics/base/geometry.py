"""Planar geometry helpers broadcasting over leading axes (internal)."""

from __future__ import annotations

import numpy as np

__all__ = ["rotate", "perp", "dot", "cross", "wrap_angle", "stack_xy"]


def rotate(theta: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Rotate local vectors ``p (..., 2)`` by angles ``theta (...)`` (CCW, rad).

    >>> rotate(np.pi / 2, np.array([1.0, 0.0])).round(12)
    array([0., 1.])
    """
    c, s = np.cos(theta), np.sin(theta)
    px, py = p[..., 0], p[..., 1]
    x = c * px - s * py  # its shape is the broadcast one (cheaper than asking)
    out = np.empty(np.shape(x) + (2,))
    out[..., 0] = x
    out[..., 1] = s * px + c * py
    return out


def perp(v: np.ndarray) -> np.ndarray:
    """``v`` rotated by +90°: (x, y) -> (−y, x)."""
    out = np.empty(v.shape)
    out[..., 0] = -v[..., 1]
    out[..., 1] = v[..., 0]
    return out


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Scalar product of planar vectors ``(..., 2)``."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Scalar planar cross product a × b."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def wrap_angle(a: np.ndarray) -> np.ndarray:
    """Angles wrapped into [−π, π)."""
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def stack_xy(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.stack((x, y), axis=-1)
