"""The motion drivers' schedule in time, and the times of the analysed positions.

:class:`Schedule` gives ψ(t), ψ̇(t), ψ̈(t) of every motion driver (a ``Drive`` of
:mod:`~kinetostatics.kinematics.positions`); :func:`schedule` builds it from a system, and
:func:`sample_times` turns ``analysis.positions``/``at`` (or driver coordinates) into
times of the run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..structure.system import System
from .start import initial_guess

__all__ = ["Schedule", "schedule", "sample_times"]


@dataclass(frozen=True)
class Schedule:
    """Motion drivers' laws: ψ_d(t) = start_d + speed_d·t + ½·acceleration_d·t² (constant
    speed or acceleration), or the driver's motion law (``laws[d]``,
    :mod:`kinetostatics.model.motion`) where one is given."""

    start: np.ndarray  # (n_d,) ψ(0)
    speed: np.ndarray  # (n_d,) speed at t = 0, or a law's signed reference speed
    laws: tuple = ()  # per driver: a motion law, or None for constant speed; () if none
    acceleration: np.ndarray | None = None  # (n_d,); None: constant speeds

    def __call__(self, t):
        t = np.asarray(t, dtype=float)[..., None]
        psi = self.start + self.speed * t
        psi_d = np.broadcast_to(self.speed, t.shape[:-1] + self.speed.shape)
        psi_dd = np.zeros(t.shape[:-1] + self.speed.shape)
        if self.acceleration is not None:
            a = self.acceleration
            psi, psi_d, psi_dd = psi + 0.5 * a * t * t, psi_d + a * t, psi_dd + a
        if self.laws:
            psi_d = psi_d.copy()
            for k, law in enumerate(self.laws):
                if law is not None:
                    psi[..., k], psi_d[..., k], psi_dd[..., k] = law.value(0.0, t[..., 0])
        return psi, psi_d, psi_dd

    @property
    def reference(self) -> float:
        """|speed| of the first driver (a law's largest |ψ̇|), rad/s or m/s."""
        return float(abs(self.speed[0]))

    @property
    def law(self):
        """The first driver's motion law, or None for constant speed."""
        return self.laws[0] if self.laws else None

    def turning_times(self, lo: float, hi: float) -> np.ndarray:
        """Times in [lo, hi] where a driver's law turns back (ψ̇ = 0); none at constant speed."""
        if not any(law is not None for law in self.laws):
            return np.zeros(0)
        from ..model.motion import turning_times  # a law is there: its module is loaded

        return np.concatenate(
            [np.zeros(0)] + [turning_times(law, lo, hi) for law in self.laws if law is not None]
        )

    def breaks(self, lo: float, hi: float) -> np.ndarray:
        """Times in [lo, hi] where a driver's law has a jump in a derivative of ψ (a table
        law's knots, every period of a cyclic one); none at constant speed."""
        out = [np.zeros(0)]
        for law in self.laws:
            if law is None:
                continue
            b = np.asarray(law.breaks, dtype=float)
            if not b.size:
                continue
            if law.cyclic:
                d = law.duration
                k = np.arange(np.floor(lo / d) - 1, np.ceil(hi / d) + 1)
                b = (b[None, :] + d * k[:, None]).ravel()
            out.append(b[(b >= lo) & (b <= hi)])
        return np.concatenate(out)

    @property
    def period(self) -> float:
        """Time of one cycle (s): one turn at constant speed, a cyclic law's duration."""
        if self.law is not None:
            return self.law.duration if self.law.cyclic else np.inf
        return 2 * np.pi / self.reference


def schedule(system: System) -> Schedule:
    """The schedule of ``system``'s motion drivers: the first starts at ``analysis.start``
    (or its law's own start), a later one at its own start or where the sketch puts it."""
    drivers = system.motion_drivers
    q0 = None
    starts = []
    for k, d in enumerate(drivers):
        if d.driver.motion.start is not None:  # a constant-speed law's own start, or a law's
            starts.append(d.driver.motion.start)
        elif k == 0:
            starts.append(system.model.analysis.start)
        else:
            q0 = initial_guess(system) if q0 is None else q0
            qe = np.concatenate((q0, np.zeros(3)))
            i, j = system.ends[system.constraints.index(d)]
            starts.append(float(d.coordinate(qe[3 * i : 3 * i + 3], qe[3 * j : 3 * j + 3])))
    laws = tuple(d.driver.motion if d.driver.motion.own_run else None for d in drivers)
    accel = np.array(
        [d.driver.motion.acceleration if law is None else 0.0 for d, law in zip(drivers, laws)]
    )
    return Schedule(
        np.array(starts),
        np.array([d.driver.motion.speed for d in drivers]),
        laws if any(law is not None for law in laws) else (),
        accel if np.any(accel) else None,
    )


def sample_times(
    system: System, sched: Schedule, coordinates: np.ndarray | None
) -> tuple[np.ndarray, bool]:
    """Times of the requested positions (``analysis.positions`` and ``at``, or the driver
    ``coordinates`` given); whether they cover a full cycle."""
    a = system.model.analysis
    if sched.law is not None:
        if coordinates is not None:
            raise ValueError(
                f"driver '{system.motion_drivers[0].name}' follows a {sched.law.kind} "
                "motion law: give the positions as times, analyze(..., times=...)"
            )
        n, law = a.positions, sched.law
        t = (
            np.arange(n) * law.duration / n
            if law.cyclic
            else np.linspace(0.0, law.duration, n)
            if n > 1
            else np.zeros(1)
        )
        return t, law.cyclic
    w = sched.speed[0]
    period = 2 * np.pi if system.motion_drivers[0].joint.angular else np.inf
    if coordinates is not None:
        d = (np.asarray(coordinates, dtype=float) - a.start) * np.sign(w)
        if np.isfinite(period):
            d = np.mod(d, period)
        return d / abs(w), False
    step = a.sweep / a.positions
    d = np.arange(a.positions) * step
    extra = np.array([(c - a.start) * np.sign(w) for c in a.at])
    if np.isfinite(period) and extra.size:
        extra = np.mod(extra, period)
    full = np.isfinite(period) and abs(a.sweep - period) < 1e-9
    return np.concatenate((d, extra)) / abs(w), full
