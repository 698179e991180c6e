"""The record of a forward-dynamics run (:class:`Simulation`), its ``simulation.csv``
and the speed fluctuation of the first free coordinate (:func:`speed_fluctuation`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from ..base.tables import write_columns
from .engine import Dynamics

__all__ = ["Simulation", "speed_fluctuation", "write_csv"]


@dataclass
class _Segment:
    t0: float
    t1: float
    sol: Callable | None  # OdeSolution, or None for a constant state
    y: np.ndarray | None = None  # the constant state
    mode: tuple | None = None  # the loads' switching state on this piece


@dataclass
class Simulation:
    """A forward-dynamics run: the state over time and what happened.

    ``sample(t)`` gives (ψ_f, ψ̇_f, W) at any times (the solver's dense output);
    ``table(t)`` the columns of ``simulation.csv``; ``events`` the load switches,
    stops and breakaway checks; ``nfev`` right-hand-side evaluations.
    """

    dynamics: Dynamics
    segments: list
    events: list = field(default_factory=list)
    nfev: int = 0
    status: str = "done"
    marks: np.ndarray = field(default_factory=lambda: np.zeros(0))
    options: dict = field(default_factory=dict)

    @property
    def t_end(self) -> float:
        return self.segments[-1].t1

    @property
    def stuck(self) -> bool:
        return self.status == "stuck"

    def sample(self, t) -> np.ndarray:
        """States (len(t), 2 n_f + 1, + 1 with dampers) at times t (within [0, t_end])."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        first = self.segments[0]
        width = first.y.size if first.sol is None else np.size(first.sol(first.t0))
        out = np.empty((t.size, width))
        idx = self._pieces(t)
        for k in np.unique(idx):
            seg, sel = self.segments[k], idx == k
            out[sel] = (
                np.broadcast_to(seg.y, (int(sel.sum()), seg.y.size))
                if seg.sol is None
                else seg.sol(t[sel]).T
            )
        return out

    def _pieces(self, t: np.ndarray) -> np.ndarray:
        """Index of the piece holding each time (a piece's start belongs to it)."""
        starts = np.array([s.t0 for s in self.segments])
        return np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(self.segments) - 1)

    def table(self, t=None, points: int = 501) -> tuple[dict[str, np.ndarray], dict[str, str]]:
        """Columns over time: driver coordinates, speeds, accelerations and efforts
        (applied; for a free driver also ``_linkage``, the effort passed on to the
        linkage, applied − J_x a, with an added inertia J_x), the equivalent inertia
        (one free coordinate), energies (``energy.elastic``: the springs', part of
        ``energy.total``) and the work of the drivers (and that dissipated by the dampers,
        ``work.dampers``): ``work.drivers`` = Δ``energy.total`` + ``work.dampers``."""
        dyn = self.dynamics
        t = np.linspace(0.0, self.t_end, points) if t is None else np.asarray(t, dtype=float)
        y = self.sample(t)
        cols: dict[str, list] = {}
        units: dict[str, str] = {"time": "s"}
        cons = dyn.system.motion_drivers
        for tk, yk, piece in zip(t, y, self._pieces(np.atleast_1d(t))):
            direction = self._direction_at(tk)
            ev = dyn.state(float(tk), yk, direction, self.segments[piece].mode)
            acc = np.zeros(dyn.n_d)
            acc[dyn.free] = ev.accel
            speeds = dyn._speeds(tk, yk)
            row = {"time": tk}
            for d, name in enumerate(dyn.names):
                ang = cons[d].joint.angular
                row[f"{name}.{'angle' if ang else 'position'}"] = (
                    np.degrees(ev.psi[d]) if ang else ev.psi[d]
                )
                row[f"{name}.speed"] = speeds[d]
                row[f"{name}.acceleration"] = acc[d]
                word = "torque" if ang else "force"
                row[f"{name}.{word}"] = ev.effort[d]
                if d in dyn.free:
                    row[f"{name}.{word}_linkage"] = ev.tau[d]
                    units[f"{name}.{word}_linkage"] = "N*m" if ang else "N"
                units.update(
                    {
                        f"{name}.angle": "deg",
                        f"{name}.position": "m",
                        f"{name}.speed": "rad/s" if ang else "m/s",
                        f"{name}.acceleration": "rad/s^2" if ang else "m/s^2",
                        f"{name}.torque": "N*m",
                        f"{name}.force": "N",
                    }
                )
            if dyn.n_f == 1:
                row["equivalent.inertia"] = float(ev.dtau[0, dyn.free[0]])
                units["equivalent.inertia"] = "kg*m^2" if dyn.angular[dyn.free[0]] else "kg"
            kin, pot = dyn.energy(replace(ev, psi_d=speeds))
            nf2 = 2 * dyn.n_f
            row.update({"energy.kinetic": kin, "energy.potential": pot})
            if dyn.system.model.elements:  # springs: their energy is part of the total
                row["energy.elastic"] = dyn.elastic_energy(ev)
            row["energy.total"] = kin + pot + row.get("energy.elastic", 0.0)
            row["work.drivers"] = yk[nf2]
            if yk.size > nf2 + 1:  # dampers: the work they dissipated since t = 0
                row["work.dampers"] = yk[nf2 + 1]
            for k, v in row.items():
                cols.setdefault(k, []).append(float(v))
        units.update(
            {
                "energy.kinetic": "J",
                "energy.potential": "J",
                "energy.elastic": "J",
                "energy.total": "J",
                "work.drivers": "J",
                "work.dampers": "J",
            }
        )
        return {k: np.array(v) for k, v in cols.items()}, {k: units[k] for k in cols}

    def _direction_at(self, t: float) -> float:
        for e in reversed(self.events):
            if e["t"] <= t and "sense" in e:
                return e["sense"]
        return 0.0

    def to_csv(self, path, t=None, points: int = 501) -> None:
        """Write ``simulation.csv``: a ``# units:`` line, the header, one row per time."""
        write_csv(path, *self.table(t, points))


def write_csv(path, cols: dict, units: dict) -> None:
    """Columns (see :meth:`Simulation.table`) as CSV with a ``# units:`` line."""
    write_columns(path, cols, units, blank_nonfinite=False)


def speed_fluctuation(sim: Simulation, t0: float, t1: float, samples: int = 4001) -> dict:
    """ω_max, ω_min, ω_mean (= travel / time) and δ = (ω_max − ω_min)/ω_mean of the first
    free coordinate over [t0, t1].

    The extremes are those of the solution itself: on every integration piece the
    speed is smooth, so its extremes are the piece's ends (the load switches, where ω
    has a corner, and t0, t1) and the interior stationary points (ω̇ = 0), each located
    on the piece's dense output by a bounded scalar search around the sampled local
    extreme; ``samples`` (spread over [t0, t1]) only brackets them.
    """
    from scipy.optimize import minimize_scalar

    nf = sim.dynamics.n_f
    bounds = [s.t0 for s in sim.segments[1:]]
    edges = np.unique(np.clip([t0, t1] + [b for b in bounds if t0 < b < t1], t0, t1))
    candidates: list[float] = []
    for a, b in zip(edges[:-1], edges[1:]):
        seg = sim.segments[int(sim._pieces(np.array([0.5 * (a + b)]))[0])]
        n = max(16, int(np.ceil(samples * (b - a) / (t1 - t0))))
        t = np.linspace(a, b, n)
        w = np.abs(seg.sol(t)[nf]) if seg.sol is not None else np.full(n, abs(seg.y[nf]))
        candidates += [w[0], w[-1]]  # the piece's own values at its ends
        if seg.sol is None:
            continue
        for k in range(n):
            for sign in (1.0, -1.0):
                # a sampled local extreme, or an extreme just inside a piece end (where
                # ω may turn within the first or last sampling interval)
                if (
                    k == 0
                    or k == n - 1
                    or sign * (w[k] - w[k - 1]) > 0
                    and sign * (w[k] - w[k + 1]) >= 0
                ):
                    lo, hi = t[max(k - 1, 0)], t[min(k + 1, n - 1)]
                    r = minimize_scalar(
                        lambda tt, sign=sign, seg=seg: -sign * abs(float(seg.sol(tt)[nf])),
                        bounds=(lo, hi),
                        method="bounded",
                        options={"xatol": 1e-14 * max(1.0, abs(b))},
                    )
                    candidates.append(max(w[k], -r.fun) if sign > 0 else min(w[k], r.fun))
    w_max, w_min = max(candidates), min(candidates)
    travel = sim.sample([t0, t1])[:, 0]
    mean = abs(travel[-1] - travel[0]) / (t1 - t0)
    return {
        "omega_max": float(w_max),
        "omega_min": float(w_min),
        "omega_mean": float(mean),
        "omega_average": 0.5 * float(w_max + w_min),
        "delta": float((w_max - w_min) / mean),
        "t0": float(t0),
        "t1": float(t1),
    }
