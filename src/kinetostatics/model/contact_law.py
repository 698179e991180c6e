"""The Lankarani–Nikravesh contact law of a clearance joint, as model data: the
Hertzian stiffness and the effort law (:mod:`kinetostatics.dynamics.contact` integrates the
motion with it; the formulas are in its docstring)."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from . import EffortLaw

__all__ = ["ContactLaw", "hertz_stiffness"]


def hertz_stiffness(
    journal_radius: float, clearance: float, young=(2.07e11, 2.07e11), poisson=(0.3, 0.3)
) -> float:
    """K = (4/3) E* √R* (N/m^1.5) of a journal of radius R_j in a bushing of R_j + e."""
    e_star = 1.0 / sum((1.0 - nu**2) / E for E, nu in zip(young, poisson))
    rb = journal_radius + clearance
    return 4.0 / 3.0 * e_star * np.sqrt(journal_radius * rb / clearance)


@dataclass(frozen=True)
class ContactLaw(EffortLaw):
    """The Lankarani–Nikravesh contact effort of a clearance
    (see :mod:`kinetostatics.dynamics.contact`).

    ``stiffness`` None: from ``journal_radius``, ``young``, ``poisson`` and the
    clearance by :func:`hertz_stiffness` (:meth:`for_clearance`); ``scale`` multiplies it.
    """

    kind: str = "contact"
    clearance: float = 0.0
    journal_radius: float = 0.02
    young: tuple = (2.07e11, 2.07e11)
    poisson: tuple = (0.3, 0.3)
    restitution: float = 0.9
    exponent: float = 1.5
    stiffness: float | None = None
    scale: float = 1.0
    impact_speed: float = 0.0
    floor: float = 1e-3

    def for_clearance(self, clearance: float) -> ContactLaw:
        """This law for clearance ``clearance`` (m), with its Hertzian stiffness."""
        return replace(self, clearance=float(clearance))

    @property
    def k(self) -> float:
        base = (
            self.stiffness
            if self.stiffness is not None
            else (
                hertz_stiffness(self.journal_radius, self.clearance, self.young, self.poisson)
                if self.clearance > 0
                else np.inf
            )
        )
        return base * self.scale

    def force(self, delta, delta_d):
        """F_n ≥ 0 at penetration ``delta`` and its rate (arrays)."""
        delta, delta_d = np.asarray(delta, float), np.asarray(delta_d, float)
        v0 = max(self.impact_speed, self.floor)
        damp = 1.0 + 0.75 * (1.0 - self.restitution**2) * delta_d / v0
        pen = np.maximum(delta, 0.0)
        return np.where(delta > 0, np.maximum(self.k * pen**self.exponent * damp, 0.0), 0.0)

    def partials(self, delta: float, delta_d: float) -> tuple[float, float]:
        """(∂F_n/∂δ, ∂F_n/∂δ̇) at one state (0 where the force is 0): the stiff part of
        the equations of motion, for an implicit integrator's Jacobian."""
        if delta <= 0:
            return 0.0, 0.0
        v0 = max(self.impact_speed, self.floor)
        c = 0.75 * (1.0 - self.restitution**2) / v0
        damp = 1.0 + c * delta_d
        if damp <= 0:
            return 0.0, 0.0
        k = self.k
        return (
            k * self.exponent * delta ** (self.exponent - 1.0) * damp,
            k * delta**self.exponent * c,
        )

    def __call__(self, psi, psi_d, period=None):
        return -self.force(np.asarray(psi, float) - self.clearance, psi_d)
