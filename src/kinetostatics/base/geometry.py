"""Planar geometry helpers broadcasting over leading axes (internal)."""

from __future__ import annotations

import numpy as np

from .arrays import entries_last

__all__ = [
    "rotate",
    "rotated",
    "turn",
    "turn_back",
    "poses",
    "framed_poses",
    "perp",
    "dot",
    "cross",
    "wrap_angle",
    "stack_xy",
]


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


def rotated(c: np.ndarray, s: np.ndarray, p: np.ndarray) -> np.ndarray:
    """:func:`rotate` by an angle given as its (cos, sin), computed once by the caller:
    the same numbers as ``rotate(theta, p)`` with ``c, s = cos θ, sin θ``."""
    px, py = p[..., 0], p[..., 1]
    x = c * px - s * py
    out = np.empty(np.shape(x) + (2,))
    out[..., 0] = x
    out[..., 1] = s * px + c * py
    return out


def _frame(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(cos θ, sin θ) of a pose: carried at ``q[..., 3:5]``, or computed from ``q[..., 2]``."""
    if q.shape[-1] == 5:
        return q[..., 3], q[..., 4]
    return np.cos(q[..., 2]), np.sin(q[..., 2])


def turn(q: np.ndarray, p: np.ndarray) -> np.ndarray:
    """A link's local vectors ``p (..., 2)`` in world axes at its pose ``q``: rotated by
    θ = ``q[..., 2]``.  ``q`` is ``(..., 3)`` (x, y, θ), or ``(..., 5)`` carrying its frame
    (cos θ, sin θ) after them, computed once per state (:func:`poses`) — the same
    numbers as :func:`rotate` without evaluating cos and sin again.

    >>> turn(np.array([0.0, 0.0, np.pi / 2]), np.array([1.0, 0.0])).round(12)
    array([0., 1.])
    """
    c, s = _frame(q)
    return rotated(c, s, p)


def turn_back(q: np.ndarray, p: np.ndarray) -> np.ndarray:
    """World vectors ``p (..., 2)`` in the axes of a link at pose ``q`` (rotated by −θ)."""
    c, s = _frame(q)
    return rotated(c, -s, p)


def poses(q: np.ndarray, n_links: int) -> np.ndarray:
    """Link coordinates ``q (..., 3 n)`` as poses with their frames, ``(..., n + 1, 5)``:
    (x, y, θ, cos θ, sin θ) per link, the ground's (0, 0, 0, 1, 0) last.

    Stored component-major (a view of ``(n + 1, 5, ...)``): each link's x, y, θ, cos θ,
    sin θ is one contiguous run over the positions, the operands of the joints' formulas
    (``q[..., 3]``…) — strided by 5 (n + 1) numbers otherwise, which over 36,000
    positions costs the slotting machine's kinematics ~10 %."""
    lead = q.shape[:-1]
    out = entries_last(np.empty((n_links + 1, 5) + lead))
    out[..., :n_links, :3] = q.reshape(q.shape[:-1] + (n_links, 3))
    theta = out[..., :n_links, 2]
    out[..., :n_links, 3] = np.cos(theta)
    out[..., :n_links, 4] = np.sin(theta)
    out[..., n_links, :] = (0.0, 0.0, 0.0, 1.0, 0.0)
    return out


def framed_poses(q_t: np.ndarray, frames: np.ndarray) -> np.ndarray:
    """:func:`poses` from coordinates and frames already at hand: ``q_t (3 n, ...)`` the
    links' (x, y, θ) and ``frames (n, 2, ...)`` their cos θ and sin θ, each component one
    array over the positions (component-major), in :func:`poses`' layout ``(..., n + 1,
    5)``: copies, no cosine or sine evaluated."""
    n, lead = len(frames), q_t.shape[1:]
    out = np.empty((n + 1, 5) + lead)
    out[:n, :3] = q_t.reshape((n, 3) + lead)
    out[:n, 3:] = frames
    out[n] = np.reshape((0.0, 0.0, 0.0, 1.0, 0.0), (5,) + (1,) * len(lead))
    return entries_last(out)


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
