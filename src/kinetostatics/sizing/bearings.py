"""Bearing life and plain-bearing loading over the cycle: pure functions of arrays
(docs/sizing.md, "Bearings").

Rolling bearings (ISO 281): for a load |F(t)| varying with the relative rotation
speed |ω(t)| over a cycle, the equivalent dynamic load is the mean of |F|^p weighted by the
relative rotation,

    P = ( ∫ |F|^p |ω| dt / ∫ |ω| dt )^(1/p),   p = 3 (ball), 10/3 (roller),

and the basic rating life L10 = (C/P)^p · 10⁶ revolutions, in hours at the mean speed
n = ∫|ω| dt / (2π·T) rev/s: L10h = L10 / (3600·n).  An oscillating joint (a rocker's pin)
turns ∫|ω| dt = 2φ per cycle for a swing φ: the same integral is the equivalent-speed
rule of ISO 281 and the bearing makers (n_eq = f·2φ/360° for an oscillation frequency f
and a swing φ in degrees).

Plain bearings: the mean pressure p = |F|/(d·b), the sliding speed v = |ω|·d/2 and pv.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "EXPONENTS",
    "equivalent_load",
    "rating_life",
    "equivalent_speed",
    "plain_loading",
]

EXPONENTS = {"ball": 3.0, "roller": 10.0 / 3.0}
MILLION = 1e6


def equivalent_load(force, speed, weights, p: float) -> float:
    """P (N): the mean of ``|force|**p`` weighted by ``|speed| * weights`` (the relative
    rotation of each node), to the power 1/p; NaN where the joint does not turn."""
    f, w = np.abs(np.asarray(force, float)), np.abs(np.asarray(speed, float)) * weights
    turn = float(np.sum(w))
    if not turn > 0.0:
        return float("nan")
    return float((np.sum(w * f**p) / turn) ** (1.0 / p))


def rating_life(C: float, P: float, p: float) -> float:
    """L10 (revolutions) = (C/P)^p · 10⁶; inf for no load."""
    if P == 0.0:
        return float("inf")
    return float((C / P) ** p * MILLION)


def equivalent_speed(speed, weights) -> float:
    """The mean relative speed (rev/s) over the span of ``weights``: ∫|ω| dt / (2π·T)."""
    span = float(np.sum(weights))
    return float(np.sum(np.abs(speed) * weights) / (2 * np.pi * span)) if span > 0 else 0.0


def plain_loading(force, speed, diameter: float, width: float):
    """(p in Pa, v in m/s, pv in Pa·m/s) arrays of a plain bearing of bore ``diameter``
    and length ``width``."""
    p = np.abs(np.asarray(force, float)) / (diameter * width)
    v = np.abs(np.asarray(speed, float)) * diameter / 2.0
    return p, v, p * v
