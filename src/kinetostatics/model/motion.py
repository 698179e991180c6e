"""The motion laws of a driver that fix their own run: ψ(t), ψ̇(t), ψ̈(t) exactly.

Constant speed is :class:`kinetostatics.model.MotionLaw`.  The laws here give the driver
coordinate ψ (rad, or m for a prismatic driver) as a function of the time t (s) from the
first position of the run, with its first and second derivatives in closed form (no
differences).  Each is plain frozen data (built by ``io`` from ``drivers.<name>.motion``)
and answers through the one interface of every motion law,
:class:`kinetostatics.model.Law`: every reader asks the law, never its class.  This module
is imported only when a file names one of its laws.

>>> law = HarmonicLaw(centre=1.0, amplitude=0.5, period=2.0)
>>> [round(float(x), 12) for x in law.value(0.0, 0.5)]
[1.5, 0.0, -4.934802200545]
>>> law.own_run, law.cyclic, law.duration
(True, True, 2.0)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from . import Law

__all__ = ["HarmonicLaw", "PolynomialLaw", "TableLaw", "LAWS", "turning_times"]

_SAMPLES = 4097  # points at which the peak speed of a polynomial/table law is sampled


def _peak(law, t: np.ndarray) -> float:
    """Signed reference speed: max |ψ̇| on the samples, sign of the first non-zero ψ̇
    (taken at construction: a law out of range overflows quietly, the loader refuses it)."""
    with np.errstate(all="ignore"):
        psi_d = law.value(0.0, t)[1]
    moving = np.nonzero(np.abs(psi_d) > 1e-12 * np.max(np.abs(psi_d), initial=0.0))[0]
    sign = np.sign(psi_d[moving[0]]) if moving.size else 1.0
    return float(sign * np.max(np.abs(psi_d), initial=0.0))


@dataclass(frozen=True)
class HarmonicLaw(Law):
    """ψ = centre + amplitude·sin(2π t / period + phase); one period is one cycle."""

    centre: float
    amplitude: float
    period: float  # s
    phase: float = 0.0  # rad
    kind: ClassVar[str] = "harmonic"
    cyclic: ClassVar[bool] = True

    @property
    def omega(self) -> float:
        return 2.0 * np.pi / self.period

    def value(self, start, t):
        arg = self.omega * np.asarray(t, dtype=float) + self.phase
        s, c = np.sin(arg), np.cos(arg)
        a, w = self.amplitude, self.omega
        return self.centre + a * s, a * w * c, -a * w * w * s

    @property
    def start(self) -> float:
        return float(self.value(0.0, 0.0)[0])

    @property
    def speed(self) -> float:
        c = np.cos(self.phase)
        sign = (
            np.sign(self.amplitude * c)
            if abs(c) > 1e-12
            else -np.sign(self.amplitude * np.sin(self.phase))
        )
        return float(sign * abs(self.amplitude) * self.omega)

    @property
    def duration(self) -> float:
        return self.period

    def to_spec(self) -> dict:
        return {
            "law": "harmonic",
            "centre": self.centre,
            "amplitude": self.amplitude,
            "period": self.period,
            "phase": self.phase,
        }


@dataclass(frozen=True)
class PolynomialLaw(Law):
    """ψ = Σ_k c_k t^k over 0 ≤ t ≤ ``duration``."""

    coefficients: tuple[float, ...]
    duration: float  # s
    kind: ClassVar[str] = "polynomial"
    speed: float | None = field(init=False, repr=False, compare=False)  # set at construction

    def __post_init__(self):
        """The reference speed, from the fields; None for a law stacked over variants
        (arrays in its fields, model/stacking.py), which only the per-variant analysis runs."""
        if np.ndim(self.duration) or any(np.ndim(c) for c in self.coefficients):
            object.__setattr__(self, "speed", None)
            return
        object.__setattr__(self, "speed", _peak(self, np.linspace(0.0, self.duration, _SAMPLES)))

    def value(self, start, t):
        t = np.asarray(t, dtype=float)
        c = np.asarray(self.coefficients, dtype=float)
        d1 = c[1:] * np.arange(1, len(c))
        d2 = d1[1:] * np.arange(1, len(d1))
        ev = lambda p: np.polynomial.polynomial.polyval(t, p) if len(p) else np.zeros_like(t)  # noqa: E731
        return ev(c), ev(d1), ev(d2)

    @property
    def start(self) -> float:
        return float(self.coefficients[0])

    def to_spec(self) -> dict:
        return {
            "law": "polynomial",
            "coefficients": list(self.coefficients),
            "duration": self.duration,
        }


@dataclass(frozen=True)
class TableLaw(Law):
    """ψ through the points (``time``, ``values``): a C² cubic spline (not-a-knot
    ends, or periodic when ``periodic``); time 0 of the run is ``time[0]``."""

    time: tuple[float, ...]
    values: tuple[float, ...]
    periodic: bool = False
    kind: ClassVar[str] = "table"
    _spline: object = field(default=None, init=False, repr=False, compare=False)
    speed: float = field(init=False, repr=False, compare=False)  # from the fields, at construction

    def __post_init__(self):
        from scipy.interpolate import CubicSpline  # only a table law needs it

        t = np.asarray(self.time, dtype=float)
        spline = CubicSpline(
            t - t[0],
            np.asarray(self.values, dtype=float),
            bc_type="periodic" if self.periodic else "not-a-knot",
        )
        object.__setattr__(self, "_spline", spline)
        object.__setattr__(self, "speed", _peak(self, np.linspace(0.0, self.duration, _SAMPLES)))

    @property
    def cyclic(self) -> bool:
        return self.periodic

    def value(self, start, t):
        t = np.asarray(t, dtype=float)
        s = self._spline
        return s(t), s(t, 1), s(t, 2)

    @property
    def start(self) -> float:
        return float(self.values[0])

    @property
    def duration(self) -> float:
        return float(self.time[-1] - self.time[0])

    @property
    def breaks(self) -> tuple[float, ...]:
        """Times (from the run's start) of the inner knots: ψ is a cubic between them, its
        third derivative jumps at each (ψ̈ has a kink there), so the cycle's quadrature is
        cut there."""
        t = np.asarray(self.time, dtype=float)
        return tuple(float(x) for x in t[1:-1] - t[0])

    def to_spec(self) -> dict:
        spec = {"law": "table", "time": list(self.time), "value": list(self.values)}
        if self.periodic:
            spec["periodic"] = True
        return spec


def turning_times(law, lo: float, hi: float, samples: int = 4097) -> np.ndarray:
    """Times in [lo, hi] where ψ̇ = 0 (the law turns back): sign changes of ψ̇ on
    ``samples`` points, refined by Newton's method on ψ̇ with the exact ψ̈.

    >>> turning_times(HarmonicLaw(0.0, 1.0, 4.0), 0.0, 4.0)
    array([1., 3.])
    """
    t = np.linspace(lo, hi, samples)
    v = law.value(0.0, t)[1]
    k = np.nonzero((v[:-1] * v[1:] < 0) | (v[:-1] == 0))[0]
    a, b = t[k], t[k + 1]
    r = np.where(
        v[k] == 0, a, a - v[k] * (b - a) / np.where(v[k + 1] != v[k], v[k + 1] - v[k], 1.0)
    )
    for _ in range(8):
        _, vd, vdd = law.value(0.0, r)
        r = np.clip(r - np.divide(vd, vdd, out=np.zeros_like(r), where=vdd != 0), a, b)
    return r


LAWS = {law.kind: law for law in (HarmonicLaw, PolynomialLaw, TableLaw)}
