"""What the toothed higher pairs (``gear``, ``rack``) share: their YAML readers,
the wrap of a row to the tooth period, and the mesh-efficiency friction.

The friction model is derived in ``gear.py``'s docstring: a mesh efficiency η
gives the friction effort |e| = ζ cos α |λ| with ζ = 2(1 − η)/(1 + η), the loss
over the power of the tooth force, so that P_out/P_in = η whichever side drives.
"""

from __future__ import annotations

import math

import numpy as np

from ..base.keys import NUMBER, Keys, enum
from .base import Friction

__all__ = [
    "FLANKS",
    "MESH_FRICTION_KEYS",
    "MESH_KEYS",
    "MeshFriction",
    "read_flank",
    "read_length",
    "read_shift",
    "read_tooth_form",
    "read_loss",
    "read_pressure_angle",
    "read_teeth",
    "wrap",
]

FLANKS = {"ccw": 1, "cw": -1}
MESH_FRICTION_KEYS = Keys({"efficiency": NUMBER, "coefficient": NUMBER})
# the keys a gear and a rack share, after their own
MESH_KEYS = {
    "pressure_angle": NUMBER,
    "flank": enum(FLANKS),
    "phase": NUMBER,
    "friction": MESH_FRICTION_KEYS,
    "addendum": NUMBER,
    "clearance": NUMBER,
}


def wrap(x, period):
    """``x`` wrapped into [−period/2, period/2)."""
    return (x + 0.5 * period) % period - 0.5 * period


# -- YAML helpers of the toothed pairs ------------------------------------------
def read_teeth(entry, n: int) -> list[int] | None:
    """``n`` tooth numbers (positive integers) from a scalar or a list."""
    items = [entry] if n == 1 else entry.seq()
    if items is None:
        return None
    if len(items) != n:
        entry.error(f"expected a list of {n} tooth numbers, got {len(items)}")
        return None
    out = []
    for e in items:
        z = e.number(None, minimum=1)
        if z is None:
            return None
        if not (math.isfinite(z) and float(z).is_integer() and z <= 100000):
            e.error(f"a number of teeth must be a whole number from 1 to 100000, got {z:g}")
            return None
        out.append(int(z))
    return out


def read_length(entry) -> float | None:
    """A positive, finite length in SI."""
    v = entry.number("length", minimum=0.0, strict=True)
    if v is not None and not math.isfinite(v):
        entry.error("must be a finite length")
        return None
    return v


def read_pressure_angle(entry) -> float | None:
    """``pressure_angle`` in rad (default 20°), from 0 up to 45°."""
    if (e := entry.get("pressure_angle")) is None:
        return math.radians(20.0)
    a = e.number("angle", minimum=0.0)
    if a is not None and not a < math.radians(45.0):
        e.error(f"a pressure angle must be below 45°, got {math.degrees(a):g}°")
        return None
    return a


def read_tooth_form(entry) -> tuple[float, float] | None:
    """(h_a*, c*): ``addendum`` (default 1, above 0 up to 2) and ``clearance`` (default
    0.25, from 0 up to 1), the reference profile's coefficients (multiples of the module)."""
    out = []
    for key, default, low, high in (("addendum", 1.0, 0.0, 2.0), ("clearance", 0.25, 0.0, 1.0)):
        if (e := entry.get(key)) is None:
            out.append(default)
            continue
        v = e.number(None, minimum=low, strict=key == "addendum")
        if v is None:
            return None
        if not v <= high:
            e.error(f"the {key} coefficient must be at most {high:g} (a multiple of the module)")
            return None
        out.append(v)
    return out[0], out[1]


def read_shift(entry, n: int) -> tuple[float, ...] | None:
    """``shift``: ``n`` profile shift coefficients x (default 0), each from −3 to 3."""
    if (e := entry.get("shift")) is None:
        return (0.0,) * n
    items = [e] if n == 1 else e.seq()
    if items is None:
        return None
    if len(items) != n:
        e.error(f"expected a list of {n} profile shift coefficients, got {len(items)}")
        return None
    out = []
    for item in items:
        x = item.number(None)
        if x is None:
            return None
        if not abs(x) <= 3.0:
            item.error(f"a profile shift coefficient must be from -3 to 3, got {x:g}")
            return None
        out.append(float(x))
    return tuple(out)


def read_flank(entry) -> int | None:
    if (e := entry.get("flank")) is None:
        return 1
    text = e.text()
    if text is None:
        return None
    if text not in FLANKS:
        e.error(
            f"flank must be ccw or cw (the sense in which the tooth force turns "
            f"link j about its centre), got '{text}'"
        )
        return None
    return FLANKS[text]


def read_loss(entry, loss_per_mu: float | None) -> float | None:
    """1 − η from ``friction: {efficiency: η}`` or ``{coefficient: μ}`` (0 without).

    ``loss_per_mu`` is the loss ratio ζ per unit μ (``None``: teeth unknown).
    """
    if (f := entry.get("friction")) is None:
        return 0.0
    if not f.check(MESH_FRICTION_KEYS):
        return None
    eff, mu = f.get("efficiency"), f.get("coefficient")
    if (eff is None) == (mu is None):
        f.error(
            "give efficiency (the mesh efficiency η, 0 < η ≤ 1) or coefficient "
            "(the tooth friction coefficient μ)"
        )
        return None
    if eff is not None:
        eta = eff.number(None, minimum=0.0, strict=True)
        if eta is not None and not eta <= 1.0:
            eff.error(f"a mesh efficiency must be in (0, 1], got {eta:g}")
            return None
        return None if eta is None else 1.0 - eta
    m = mu.coefficient()
    if m is None:
        return None
    if loss_per_mu is None:
        mu.error(
            "a friction coefficient needs the number of teeth (key teeth); "
            "or give the mesh efficiency"
        )
        return None
    zeta = m * loss_per_mu
    if not zeta < 2.0:
        mu.error(
            f"this coefficient gives a loss ratio ζ = {zeta:g} ≥ 2 (no efficiency "
            "left); the model is ζ = (π/2) μ (1/z_i ± 1/z_j)"
        )
        return None
    return 2.0 * zeta / (2.0 + zeta)  # 1 − η with η = (2 − ζ)/(2 + ζ)


def _friction_kernel(par, x, rows, out):
    """``friction_magnitude`` for the compiled backend (base/kernels.py): ``par[m]`` =
    (ζ cos α,), the same product as the NumPy formula's."""
    for m in range(rows.shape[0]):
        a, c = rows[m, 0], par[m, 0]
        for p in range(x.shape[0]):
            out[m, p] = c * abs(x[p, a])


class MeshFriction(Friction):
    """Friction of a toothed pair as a mesh efficiency (the :class:`~.base.Friction` part);
    the pair keeps ``loss`` = 1 − η and its pressure angle ``alpha`` (rad).  Put it before
    ``Joint`` in the bases."""

    friction_kernel = staticmethod(_friction_kernel)
    friction_reads_poses = False  # ζ cos α |F|

    loss: float
    alpha: float

    @property
    def has_friction(self) -> bool:
        return self.loss > 0.0

    @property
    def loss_ratio(self) -> float:
        """ζ: the friction loss over the power of the tooth force, 2(1 − η)/(1 + η)."""
        return 2.0 * self.loss / (2.0 - self.loss)

    def friction_magnitude(self, lam, qi, qj):
        return self.loss_ratio * math.cos(self.alpha) * np.abs(lam[..., 0])

    def friction_kernel_params(self, k: int) -> np.ndarray | None:
        """(ζ cos α,) of the pair; None for a stack or for variants that differ in it."""
        if k != 1 or np.size(self.loss) != 1 or np.size(self.alpha) != 1:
            return None
        return np.array([[self.loss_ratio * math.cos(self.alpha)]])

    def friction_kinks(self, lam, qi, qj):
        return lam[..., :1]

    def friction_gradient(self, lam, qi, qj):
        return self.loss_ratio * math.cos(self.alpha) * np.sign(lam)

    def friction_constants(self) -> tuple:
        return (self.loss,)
