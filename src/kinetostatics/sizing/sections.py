"""A link's cross-section: its area A and elastic section modulus Z = I/c for bending in
the plane of motion (docs/sizing.md, "Sections").

- rectangle (width b, height h in the plane): A = b·h, Z = b·h²/6;
- circle (diameter d): A = πd²/4, Z = πd³/32;
- tube (outer diameter D, wall t; bore d = D − 2t): A = π(D² − d²)/4,
  Z = π(D⁴ − d⁴)/(32·D);
- I (height h, flange width b, web thickness t_w, flange thickness t_f):
  A = 2·b·t_f + (h − 2t_f)·t_w, I = [b·h³ − (b − t_w)(h − 2t_f)³]/12, Z = 2I/h.
"""

from __future__ import annotations

import math

from ..model.sizing import SectionSpec

__all__ = ["section_properties"]


def section_properties(section: SectionSpec) -> tuple[float, float]:
    """(A in m², Z in m³) of ``section``."""
    d = section.dimensions
    if section.shape == "rectangle":
        b, h = d["width"], d["height"]
        return b * h, b * h * h / 6.0
    if section.shape == "circle":
        D = d["diameter"]
        return math.pi * D * D / 4.0, math.pi * D**3 / 32.0
    if section.shape == "tube":
        D = d["diameter"]
        di = D - 2.0 * d["thickness"]
        return math.pi * (D * D - di * di) / 4.0, math.pi * (D**4 - di**4) / (32.0 * D)
    h, b, tw, tf = d["height"], d["width"], d["web"], d["flange"]
    inertia = (b * h**3 - (b - tw) * (h - 2 * tf) ** 3) / 12.0
    return 2 * b * tf + (h - 2 * tf) * tw, 2.0 * inertia / h
