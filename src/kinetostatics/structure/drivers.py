"""Motion drivers as rheonomic constraints with the joint interface.

A motion driver adds one row to Φ: the joint's relative coordinate (plus the
driver's constant offset) minus the prescribed driver coordinate ψ.  Its
multiplier is the driver effort (torque or force applied by link i on link j).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.geometry import wrap_angle
from ..base.kernels import Kernels, compiled
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

    def kernels(self, k: int = 1) -> Kernels | None:
        """The compiled ``jacobian`` and ``acceleration_rhs`` (base/kernels.py): the joint's
        direction and bias kernels, or None where it has none."""
        cls, par = type(self.joint), self.joint.kernel_params(1)
        if cls.direction_kernel is None or cls.bias_kernel is None or par is None:
            return None
        direction, bias = compiled(cls.direction_kernel), compiled(cls.bias_kernel)

        def gamma(P, V, ends, extra, out):
            bias(par, P, V, ends, out[:, 0])
            np.subtract(extra, out[:, 0], out=out[:, 0])

        return Kernels(lambda P, ends, ji, jj: direction(par, P, ends, ji[:, 0], jj[:, 0]), gamma)
