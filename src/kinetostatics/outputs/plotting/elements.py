"""The springs and dampers of a drawing (``elements:``): a zig-zag between the two points of
a spring, a dashpot (a rod into an open box) for a damper, a spiral about the pin of a
torsion spring and a double arc for a rotary damper; in the element colour of the style."""

from __future__ import annotations

import numpy as np

from .style import ELEMENT_COLOR

__all__ = ["element_lines", "draw_elements"]


def _zigzag(a: np.ndarray, b: np.ndarray, width: float, turns: int = 6) -> np.ndarray:
    d = b - a
    length = float(np.hypot(*d))
    if length == 0.0:
        return np.array([a, b])
    n = np.array([-d[1], d[0]]) / length
    s = np.linspace(0.15, 0.85, 2 * turns + 1)
    side = np.where(np.arange(s.size) % 2 == 1, 1.0, -1.0) * width
    side[[0, -1]] = 0.0
    mid = a + s[:, None] * d + side[:, None] * n
    return np.vstack([a, mid, b])


def _dashpot(a: np.ndarray, b: np.ndarray, width: float) -> list[np.ndarray]:
    d = b - a
    length = float(np.hypot(*d))
    if length == 0.0:
        return [np.array([a, b])]
    n = np.array([-d[1], d[0]]) / length
    box0, box1, piston = a + 0.4 * d, a + 0.7 * d, a + 0.55 * d
    return [
        np.array([a, box0]),
        np.array([box1 + width * n, box0 + width * n, box0 - width * n, box1 - width * n]),
        np.array([piston + 0.7 * width * n, piston - 0.7 * width * n]),
        np.array([piston, b]),
    ]


def _spiral(c: np.ndarray, r: float, turns: float = 1.75) -> np.ndarray:
    t = np.linspace(0.0, 2 * np.pi * turns, 60)
    rad = r * (0.35 + 0.65 * t / t[-1])
    return c + np.stack([rad * np.cos(t), rad * np.sin(t)], axis=-1)


def element_lines(model, geo, size: float) -> list[np.ndarray]:
    """The polylines (m) that draw the elements of ``model`` at the row of ``geo``
    (:class:`~.scene.MechanismGeometry`); ``size`` the glyphs' width (m)."""
    lines: list[np.ndarray] = []
    for e in model.elements:
        if e.rotational:
            c = np.asarray(geo.joints[e.joint], dtype=float)
            if e.spring:
                lines.append(_spiral(c, 1.6 * size))
            else:
                t = np.linspace(0.2 * np.pi, 1.3 * np.pi, 30)
                for r in (1.5 * size, 2.0 * size):
                    lines.append(c + r * np.stack([np.cos(t), np.sin(t)], axis=-1))
            continue
        a, b = (
            np.asarray(geo.points[f"{link}.{p}"], dtype=float) for link, p in zip(e.links, e.points)
        )
        if e.spring:
            lines.append(_zigzag(a, b, size))
        else:
            lines += _dashpot(a, b, size)
    return lines


def draw_elements(ax, model, geo, size: float) -> list:
    """Draw the elements on ``ax`` (drawing units mm); returns the artists."""
    arts = []
    for line in element_lines(model, geo, size):
        p = line * 1e3
        arts += ax.plot(p[:, 0], p[:, 1], color=ELEMENT_COLOR, lw=1.1, zorder=3.5)
    return arts
