"""The fatigue safety factor of a fibre's stress cycle (docs/sizing.md, "Fatigue").

A fibre's stress σ(t) over the cycle has the mean σ_m = (σ_max + σ_min)/2 and the
amplitude σ_a = (σ_max − σ_min)/2.  With the endurance limit S_e, the ultimate strength
S_ut and the yield strength S_y (Shigley, *Mechanical Engineering Design*, ch. 6):

- Goodman:    1/n = σ_a/S_e + σ_m/S_ut,
- Soderberg:  1/n = σ_a/S_e + σ_m/S_y,

for a tensile mean (σ_m ≥ 0); for a compressive mean the fatigue line is σ_a = S_e,
n = S_e/σ_a.  The section's factor is the least of its two outer fibres'.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cycle_of", "safety_factor"]


def cycle_of(stress) -> tuple[float, float]:
    """(σ_m, σ_a) of the stress samples ``stress`` over a cycle."""
    s = np.asarray(stress, float)
    hi, lo = float(np.max(s)), float(np.min(s))
    return (hi + lo) / 2.0, (hi - lo) / 2.0


def safety_factor(mean: float, amplitude: float, S_e: float, S_m: float) -> float:
    """n of the line through S_e on the amplitude axis and ``S_m`` (S_ut: Goodman, S_y:
    Soderberg) on the mean axis; inf for a cycle that loads nothing."""
    if mean <= 0.0:
        return S_e / amplitude if amplitude > 0.0 else float("inf")
    return 1.0 / (amplitude / S_e + mean / S_m)
