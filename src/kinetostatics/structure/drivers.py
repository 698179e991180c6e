"""Motion drivers as rheonomic constraints with the joint interface.

A motion driver adds one row to Φ: the joint's relative coordinate (plus the
driver's constant offset) minus the prescribed driver coordinate ψ.  Its
multiplier is the driver effort (torque or force applied by link i on link j).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..base.geometry import wrap_angle
from ..joints import Joint
from ..model import Driver

__all__ = ["DriverConstraint"]


@dataclass(frozen=True)
class DriverConstraint:
    """Φ = c(q_i, q_j) + offset − ψ, with ψ, ψ̇, ψ̈ given per position."""

    driver: Driver
    joint: Joint
    n_eq = 1

    @property
    def name(self) -> str:
        return self.driver.name

    @property
    def links(self) -> tuple[str, str]:
        return self.joint.links

    def coordinate(self, qi, qj):
        return self.joint.coordinate(qi, qj) + self.driver.offset

    def residual(self, qi, qj, psi):
        r = self.coordinate(qi, qj) - psi
        return (wrap_angle(r) if self.joint.angular else r)[..., None]

    def jacobian(self, qi, qj):
        gi, gj = self.joint.motion_direction(qi, qj)
        return gi[..., None, :], gj[..., None, :]

    def acceleration_rhs(self, qi, qj, vi, vj, psi_dd):
        return (psi_dd - self.joint.coordinate_bias(qi, qj, vi, vj))[..., None]
