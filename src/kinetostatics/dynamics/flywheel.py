"""Flywheel sizing for a coefficient of speed fluctuation δ (the energy method).

From the balancing moment M_b(φ) of a 1-DOF machine at its nominal constant
crank speed ω_m (``analyze``: the driver torque, link inertia torques included,
frictionless by default) and a constant driving moment equal to its cycle mean
M_d, the energy surplus ΔW(φ) = ∫₀^φ (M_d − M_b) dφ' is integrated exactly on the
cycle integrator's pieces (:func:`~kinetostatics.analysis.cycle.cycle_pieces`: cut
at the load events, where M_b jumps, and at the friction reversals and kinks): on
each piece M_d − M_b is the polynomial through its Gauss–Legendre nodes, ΔW its
integral, and the extremes of ΔW lie at the pieces' ends or at the polynomials'
roots, and

    ΔW_max = max ΔW − min ΔW,   J_F = ΔW_max / (ω_m² δ)

(first order in δ; ω_m = (ω_max + ω_min)/2).  ``inertia`` neglects the
machine's own inertia; ``inertia_net`` = J_F − J_e,mean subtracts its cycle-mean
equivalent inertia.  Referred to a motor shaft turning ``ratio`` times faster:
J/ratio².  Angles here run in the sense of motion ("travel" φ); M in that sense.

The moment on a fine grid (:func:`energy_curve`) is for the pictures only, computed
when a design's ``curve`` is first asked for.  Numpy only: ``kinetostatics run``
computes this without scipy.  The check by
simulation (:func:`verify`) needs scipy.integrate and lives outside ``run``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import numpy.polynomial.legendre as leg

from ..analysis import analyze
from ..analysis.cycle import Quadrature, cycle_quadrature, cycle_stats
from ..analysis.pipeline import analyze_near
from ..analysis.results import Result
from ..base.arguments import real_number
from ..base.legendre import inner_roots, padded_roots, piece_series
from ..errors import AssemblyError, Location, StructureError
from ..kinematics.schedule import schedule
from ..kinetics.reactions import effort_ratio
from ..model import EffortLaw, Model
from ..structure.system import System, build_system
from .flywheel_texts import ASSUMPTIONS, TORQUE_PHRASE, assumption_texts
from .reduced import equivalent, equivalent_inertia, with_effort

__all__ = [
    "FlywheelDesign",
    "design",
    "verify",
    "energy_curve",
    "ASSUMPTIONS",
    "TORQUE_PHRASE",
    "assumption_texts",
]

EPS = 1e-7  # rad: the one-sided values at an event are taken this far from it
SELF_LOCKED = (
    "no energy swing with friction: the machine self-locks over part of the cycle "
    "(self_locking), where no balancing moment exists; size the flywheel without friction "
    "(flywheel: {friction: false})"
)


@dataclass(frozen=True)
class FlywheelDesign:
    """The flywheel for δ on the crank shaft (and on a motor shaft through ``ratio``)."""

    delta: float
    driver: str
    sense: float  # +1 CCW, −1 CW
    omega_m: float  # rad/s, nominal crank speed (magnitude)
    mean_torque: float  # M_d, N·m in the sense of motion
    work_per_cycle: float  # J
    energy_swing: float  # ΔW_max, J
    at_max: float  # driver coordinate (rad) of the maximum stored energy
    at_min: float  # ... of the minimum
    inertia: float  # J_F = ΔW_max/(ω_m² δ), machine inertia neglected, kg·m²
    machine_inertia: dict  # J_e over the cycle: mean, min, max
    inertia_net: float  # J_F − J_e,mean
    ratio: float | None = None
    friction: bool = False
    positions: int = 0
    events: tuple = ()  # driver coordinates (rad) of the load events used
    assumptions: tuple = ()
    system: Any = field(default=None, repr=False, compare=False)  # for the curve, on demand
    undefined: str | None = None  # why ΔW_max (and J_F) is not defined, else None
    energy: dict | None = field(default=None, repr=False, compare=False)  # with_curve()'s

    @property
    def curve(self) -> dict[str, np.ndarray]:
        """The driving moment and J_e over the cycle on :attr:`positions` positions (plus
        both sides of every load event), for the pictures (:func:`energy_curve`): the one
        the record carries (:meth:`with_curve`), else computed at each call (not by the
        design's numbers; nothing is kept on the frozen record)."""
        if self.energy is not None:
            return self.energy
        return energy_curve(
            self.system, list(self.events), friction=self.friction, positions=self.positions
        )

    def with_curve(self) -> FlywheelDesign:
        """The design carrying its :attr:`curve`, computed once here: what a caller passes
        to the pictures, which then solve nothing."""
        return self if self.energy is not None else replace(self, energy=self.curve)

    @property
    def motor_inertia(self) -> float | None:
        return None if self.ratio is None else self.inertia / self.ratio**2

    @property
    def motor_inertia_net(self) -> float | None:
        return None if self.ratio is None else self.inertia_net / self.ratio**2

    def to_dict(self) -> dict[str, Any]:
        deg = lambda x: float(np.degrees(x) % 360.0)  # noqa: E731
        out = {
            "delta": self.delta,
            "driver": self.driver,
            "speed": {
                "omega_m": self.omega_m,
                "rpm": self.omega_m * 30.0 / np.pi,
                "sense": "ccw" if self.sense > 0 else "cw",
            },
            "torque": "with friction (consistent)" if self.friction else "frictionless",
            "mean_torque": self.mean_torque,
            "work_per_cycle": self.work_per_cycle,
            "energy_swing": self.energy_swing,
            "max_energy_at": deg(self.at_max),
            "min_energy_at": deg(self.at_min),
            "machine_inertia": dict(self.machine_inertia),
            "inertia": {"crank": self.inertia, "crank_net": self.inertia_net},
            "ratio": self.ratio,
            "events_at": [deg(e) for e in self.events],
            "positions": self.positions,
            "assumptions": list(self.assumptions),
            "units": {
                "omega_m": "rad/s",
                "mean_torque": "N*m",
                "work_per_cycle": "J",
                "energy_swing": "J",
                "max_energy_at": "deg",
                "min_energy_at": "deg",
                "inertia": "kg*m^2",
                "machine_inertia": "kg*m^2",
            },
        }
        if self.ratio is not None:
            out["inertia"].update(motor=self.motor_inertia, motor_net=self.motor_inertia_net)
        if self.undefined is not None:
            out["undefined"] = self.undefined
        return out


def _one_dof(system: System):
    drivers = system.motion_drivers
    model = system.model
    if (
        len(drivers) != 1
        or system.structure.mobility != 1
        or not drivers[0].joint.angular
        or drivers[0].driver.motion.own_run
    ):
        raise StructureError(
            [
                (
                    Location(model.source, path="flywheel"),
                    "a flywheel needs a 1-DOF machine driven by one revolute "
                    "motion driver (a crank at constant speed)",
                )
            ]
        )
    return drivers[0]


def energy_curve(
    system: System, events: list[float], *, friction: bool = False, positions: int = 3600
) -> dict[str, np.ndarray]:
    """The driving moment over a cycle, sorted by travel φ ∈ [0, 2π) from the start,
    with the one-sided values at every event (φ_e ∓ EPS).  Keys: ``travel``,
    ``coordinate``, ``moment`` (in the sense of motion), ``inertia`` (J_e), ``result``.

    ``moment`` is the balancing moment referred to the driver's (crank) shaft: with
    ``balance_at`` the effort τ at that joint times its relative speed per unit crank
    speed ρ (the input power over the crank speed), so the moment, the energy swing and
    J_F do not depend on where the effort is taken.  Where that joint is (nearly) at rest
    (a singular equilibrium row, no effort there) the frictionless moment is the input
    power from the power balance over the crank speed."""
    drv = _one_dof(system)
    sense = float(np.sign(drv.driver.motion.speed))
    start = system.model.analysis.start
    phi = np.arange(positions) * 2 * np.pi / positions
    phi_e = np.sort(np.mod((np.asarray(events, dtype=float) - start) * sense, 2 * np.pi))
    if phi_e.size:
        gap = np.min(
            np.abs(np.mod(phi[:, None] - phi_e[None, :] + np.pi, 2 * np.pi) - np.pi), axis=1
        )
        phi = np.concatenate((phi[gap > 2 * EPS], phi_e - EPS, phi_e + EPS))
    phi = np.sort(np.mod(phi, 2 * np.pi))
    coords = start + sense * phi
    r = analyze(system, positions=coords, friction=friction, events=False)
    moment, inertia = _moment(system, r, friction)
    return {
        "travel": phi,
        "coordinate": coords,
        "moment": moment,
        "inertia": inertia,
        "result": r,
        "events": phi_e,
    }


def _moment(system: System, r: Result, friction: bool) -> tuple[np.ndarray, np.ndarray]:
    """(M, J_e) over the rows of ``r``: the driving moment on the crank shaft in the sense
    of motion (:func:`energy_curve`) and the equivalent inertia."""
    drv = _one_dof(system)
    sense = float(np.sign(drv.driver.motion.speed))
    name = drv.name
    model = system.model
    word = "torque" if model.joint(drv.driver.balance_at or drv.joint.name).angular else "force"
    tau = r[f"{name}.{word}_friction"] if friction else r[f"{name}.{word}"]
    law = drv.driver.motion
    if law.acceleration == 0:  # ψ̇ = speed on every row: ∂q/∂ψ = q̇/ψ̇ from the rows' own q̇
        tangent = r.qd / law.speed
        eq = {
            "inertia": equivalent_inertia(system, tangent),
            "effort_ratio": effort_ratio(system, r.q, tangent),
        }
    else:
        eq = equivalent(system, r.q, r.coordinate, speed=law.speed, extremes=r.extremes)
    moment = sense * tau * eq["effort_ratio"]
    if not friction:  # singular equilibrium rows (the balance_at joint at or
        # next to rest, no effort there): the moment on the crank is still the input power
        # over the crank speed, which the power balance gives, (dT/dt + dV/dt + P_ext)/|ω|
        gap = ~np.isfinite(moment)
        power = r["power.kinetic"] + r["power.potential"] + r["power.external"]
        moment = np.where(gap, power / abs(drv.driver.motion.speed), moment)
    return moment, eq["inertia"]


def _swing(phi: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, float, float, float, float]:
    """Cumulative ∫ f over the periodic sorted samples (trapezoid) and the exact
    extremes of the piecewise-quadratic integral: (F, F_max, φ_max, F_min, φ_min)."""
    x = np.append(phi, phi[0] + 2 * np.pi)
    y = np.append(f, f[0])
    h = np.diff(x)
    big_f = np.concatenate(([0.0], np.cumsum(0.5 * h * (y[:-1] + y[1:]))))
    cand_x, cand_f = list(x), list(big_f)
    cross = np.nonzero(y[:-1] * y[1:] < 0)[0]
    s = y[cross] / (y[cross] - y[cross + 1])  # root of the linear interpolant
    cand_x += list(x[cross] + s * h[cross])
    cand_f += list(big_f[cross] + 0.5 * y[cross] * s * h[cross])
    cand_x, cand_f = np.array(cand_x), np.array(cand_f)
    kmax, kmin = _extremes(cand_x, cand_f)
    return big_f, cand_f[kmax], cand_x[kmax], cand_f[kmin], cand_x[kmin]


TIE = 1e-9
"""Extremes of ΔW within ``TIE`` of ΔW_max of each other are a tie: the first in the cycle is
reported (docs/dynamics.md), so that round-off does not choose between two equal maxima."""


def _extremes(at: np.ndarray, w: np.ndarray) -> tuple[int, int]:
    """The indices of the largest and least ``w`` (candidates at the times ``at``), a tie
    (within ``TIE`` of the swing) going to the earliest."""
    tol = TIE * (np.max(w) - np.min(w))
    order = np.argsort(at, kind="stable")
    kmax = order[np.argmax(w[order] >= np.max(w) - tol)]
    kmin = order[np.argmax(w[order] <= np.min(w) + tol)]
    return int(kmax), int(kmin)


def _energy_extremes(pieces: np.ndarray, t: np.ndarray, rate: np.ndarray, partial=None):
    """((t, ΔW) at the largest and at the smallest ΔW(t) = ∫ rate dt from the span's start):
    ΔW is the integral of each piece's interpolant, so its extremes are at the pieces' ends
    or at the interpolants' real roots inside — no trapezoid rule.  At a piece's end ΔW
    is the quadrature's sum (exact to round-off); inside one, the interpolant's integral
    up to the root is only as exact as the interpolation, so there ``partial(t₀, t)``, the
    integral of the rate from the piece's start t₀ by the quadrature on [t₀, t], replaces
    it (the root misplaced by δ costs O(δ²) there; both extremes' in one call)."""
    coef = piece_series(len(pieces), rate)
    half = 0.5 * (pieces[:, 1] - pieces[:, 0])
    mid = 0.5 * (pieces[:, 1] + pieces[:, 0])
    anti = leg.legint(coef, lbnd=-1, axis=1)  # every piece's antiderivative, 0 at its start
    ends = np.cumsum(half * leg.legval(1.0, anti.T))  # ΔW at each piece's end, in turn
    starts = np.concatenate(([0.0], ends[:-1]))
    p, r = _inner(padded_roots(coef), np.any(coef[:, 1:], axis=1))
    # the candidates piece after piece, each piece's inner roots before its end
    at_root = starts[p] + half[p] * leg.legval(r, anti[p].T, tensor=False)
    order = np.lexsort((np.concatenate((np.arange(len(p)), np.full(len(pieces), len(p)))),
                        np.concatenate((p, np.arange(len(pieces))))))  # fmt: skip
    cand_t = [pieces[0, 0], *np.concatenate((mid[p] + half[p] * r, pieces[:, 1]))[order]]
    cand_w = np.concatenate(([0.0], np.concatenate((at_root, ends))[order]))
    inner = [(int(k), float(w)) for k, w in zip(p, starts[p])] + [None] * len(pieces)
    cand_in: list[tuple[int, float] | None] = [None, *(inner[k] for k in order)]
    # where: the tie rule's (the first of extremes within TIE); how much: the extreme itself
    # (a tie's values differ by up to TIE·swing: seed 1008810, ΔW's minimum 2.2e-6 s after
    # a piece's start and 2.6e-9 J below it, the start chosen and its value reported)
    at = list(_extremes(np.asarray(cand_t, dtype=float), cand_w))
    ks = [int(np.argmax(cand_w)), int(np.argmin(cand_w))]
    out = [(cand_t[a], float(cand_w[k])) for a, k in zip(at, ks)]
    inside = [i for i, k in enumerate(ks) if partial is not None and cand_in[k] is not None]
    if inside:  # both extremes' integrals from their pieces' starts at once
        starts = np.array([pieces[cand_in[ks[i]][0], 0] for i in inside])
        parts = partial(starts, np.array([cand_t[ks[i]] for i in inside]))
        for i, part in zip(inside, parts):
            out[i] = (out[i][0], cand_in[ks[i]][1] + float(part))
    return out[0], out[1]


def _on_the_grid(system, events, friction, positions, w):
    """The trapezoid rule on :func:`energy_curve`'s grid, where the exact pieces cannot
    serve (a moment missing at some nodes): ((t, ΔW) at the largest and the smallest ΔW,
    (J_e mean, min, max)); NaN where the moment is missing."""
    c = energy_curve(system, events, friction=friction, positions=positions)
    x = np.append(c["travel"], 2 * np.pi + c["travel"][0])
    y = np.append(c["moment"], c["moment"][0])  # ΔW closes with its own rule's mean
    m_closed = float(np.sum(0.5 * np.diff(x) * (y[:-1] + y[1:]))) / (2 * np.pi)
    _, f_max, phi_max, f_min, phi_min = _swing(c["travel"], m_closed - c["moment"])
    je = np.append(c["inertia"], c["inertia"][0])
    je_mean = float(np.sum(0.5 * np.diff(x) * (je[:-1] + je[1:])) / (2 * np.pi))
    return (
        (phi_max / w, f_max),
        (phi_min / w, f_min),
        (je_mean, float(np.min(c["inertia"])), float(np.max(c["inertia"]))),
    )


def _inner(roots: np.ndarray, any_: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The real roots inside (−1, 1) of the series whose ``roots`` (``padded_roots``) are
    taken (``any_``), as (series, root) arrays, each series' in ascending order."""
    inner = inner_roots(roots)
    p, k = np.nonzero(any_[:, None] & np.isfinite(inner))
    return p, inner[p, k]


def _value_extremes(pieces: np.ndarray, values: np.ndarray) -> tuple[float, float]:
    """(min, max) of the pieces' interpolants of ``values`` (at their ends and where their
    derivatives vanish inside)."""
    coef = piece_series(len(pieces), values)
    ders = leg.legder(coef, axis=1)
    p, r = _inner(padded_roots(ders), np.any(ders, axis=1))
    cand = np.concatenate(
        (leg.legval(-1.0, coef.T), leg.legval(1.0, coef.T), leg.legval(r, coef[p].T, tensor=False))
    )
    return float(np.min(cand)), float(np.max(cand))


def design(
    source: Result | Model | System,
    delta: float | None = None,
    *,
    ratio: float | None = None,
    friction: bool | None = None,
    positions: int = 3600,
    quadrature: tuple[int, int] | None = None,
    nodes: Quadrature | None = None,
) -> FlywheelDesign:
    """Size the flywheel for ``delta`` (default the model's ``flywheel.delta``).

    ``source``: a full-cycle :class:`Result` (its events are reused), a model or a
    system.  ``ratio``: motor speed / crank speed (default ``flywheel.ratio``);
    ``friction``: size from the balancing moment with friction (consistent).
    ``quadrature``: the cycle integrator's (nodes, pieces), another than the default only
    to check that the design has converged (:func:`~kinetostatics.analysis.cycle.cycle_nodes`).
    ``nodes``: the cycle's quadrature of ``source`` already computed
    (:func:`~kinetostatics.analysis.cycle.cycle_quadrature`), used when it serves (the
    nodes with friction serve a frictionless design).
    """
    system, base = _system_and_base(source)
    delta, ratio, friction = _settings(system.model.flywheel, delta, ratio, friction)
    drv = _one_dof(system)
    if base is None:
        base = analyze(system, friction=False)
    events = [e.coordinate for e in base.events]
    w = abs(drv.driver.motion.speed)
    # M_d: the cycle mean of the one function every output uses (analysis/cycle.py)
    quad = cycle_quadrature(
        base, friction=friction, quadrature=quadrature, given=nodes if base is source else None
    )
    moment, je = _moment(system, quad.nodes, friction)
    exact = quad.pieces is not None and np.all(np.isfinite(moment)) and np.all(np.isfinite(je))
    m_d = _mean_moment(base, quad, moment if exact else None, friction, quadrature)
    undefined = None
    if exact:
        energy, machine = _exact_extremes(base, quad, (moment, je), m_d, friction)
    elif friction and not np.all(np.isfinite(moment)):  # self-locked at some nodes
        # no balancing moment there, so no energy over the cycle: said, not computed
        energy, machine, undefined = _self_locked(je)
    else:  # no moment somewhere (a self-locked zone with friction): the fine grid's rule
        *energy, machine = _on_the_grid(system, events, friction, positions, w)
    (t_max, swing_max), (t_min, swing_min) = energy
    je_mean, je_min, je_max = machine
    swing = swing_max - swing_min
    j_f = swing / (w**2 * delta)
    psi = schedule(system)
    return FlywheelDesign(
        delta=float(delta),
        driver=drv.name,
        sense=float(np.sign(drv.driver.motion.speed)),
        omega_m=w,
        mean_torque=m_d,
        work_per_cycle=2 * np.pi * m_d,
        energy_swing=float(swing),
        at_max=float(psi(np.array([t_max]))[0][0, 0]),
        at_min=float(psi(np.array([t_min]))[0][0, 0]),
        inertia=float(j_f),
        machine_inertia={"mean": je_mean, "min": je_min, "max": je_max},
        inertia_net=float(j_f - je_mean),
        ratio=ratio,
        friction=friction,
        positions=positions,
        events=tuple(events),
        assumptions=assumption_texts(friction, w, positions),
        system=system,
        undefined=undefined,
    )


def _system_and_base(source: Result | Model | System) -> tuple[System, Result | None]:
    """The system of ``source`` and the full-cycle result it is (None: to be analysed)."""
    if isinstance(source, Result):
        return source.system, source if source.full_cycle else None
    return source if isinstance(source, System) else build_system(source), None


def _self_locked(je: np.ndarray):
    """A design self-locked at some nodes: no energy extremes (NaN), the machine's inertia
    over the nodes where it is finite, and the sentence saying why."""
    finite = je[np.isfinite(je)]
    energy = ((float("nan"), float("nan")), (float("nan"), float("nan")))
    return energy, tuple(float(f(finite)) for f in (np.mean, np.min, np.max)), SELF_LOCKED


def _mean_moment(base: Result, quad: Quadrature, moment, friction: bool, quadrature) -> float:
    """M_d, the balancing moment's cycle mean: by the integrator's own weights from its
    values at the nodes (``moment``; cycle_stats' sum, once), or with ``moment`` None over
    the part of the cycle where the moment exists (:func:`cycle_stats`)."""
    if moment is not None:
        return float(np.sum(quad.weights * moment) / np.sum(quad.weights))
    return cycle_stats(
        base,
        {"M": lambda r: _moment(base.system, r, friction)[0]},
        friction=friction,
        quadrature=quadrature,
        given=quad,
    )["M"]["mean"]


def _settings(
    spec, delta: float | None, ratio: float | None, friction: bool | None
) -> tuple[float, float | None, bool]:
    """The design's δ, ratio and friction: each given, else the file's ``flywheel:``
    section's (``spec``, may be None); δ in (0, 1) and the ratio positive, checked."""
    delta = delta if delta is not None else (spec.delta if spec else None)
    if delta is None:
        raise ValueError("no delta: give flywheel: {delta: ...} in the file or delta=")
    delta = real_number(
        "delta",
        delta,
        low=0.0,
        high=1.0,
        strict_low=True,
        strict_high=True,
        why="the coefficient of speed fluctuation",
    )
    if ratio is not None:
        ratio = real_number("ratio", ratio, low=0.0, strict_low=True)
    ratio = ratio if ratio is not None else (spec.ratio if spec else None)
    friction = bool(friction if friction is not None else (spec.friction if spec else False))
    return delta, ratio, friction


def _exact_extremes(base: Result, quad: Quadrature, curves, m_d: float, friction: bool):
    """The energy's extremes ``((t_max, swing_max), (t_min, swing_min))`` and the machine's
    inertia ``(mean, min, max)`` over the cycle, from the quadrature's nodes and its
    ``curves`` (the moment M and J_e at the nodes), M_d the mean moment."""
    system = base.system
    moment, je = curves
    w = abs(_one_dof(system).driver.motion.speed)
    weights, nodes, pieces = quad.weights, quad.nodes, quad.pieces
    x, wx = leg.leggauss(len(weights) // len(pieces))

    def partial(a: np.ndarray, b: np.ndarray) -> np.ndarray:  # ∫ w·(M_d − M) from a to b
        times = (a[:, None] + 0.5 * (b - a)[:, None] * (x + 1.0)).ravel()  # pieces' parts
        try:  # each position continued from the nearest node (all parts in one call): the
            # nodes resolve the effort, the rows may not (a branch near a dead point)
            m = _moment(system, analyze_near(nodes, times, friction=friction), friction)[0]
        except AssemblyError:  # the whole run's way (its rows in time order)
            o, m = np.argsort(times, kind="stable"), np.empty(len(times))
            run = analyze(system, times=times[o], friction=friction, events=False)
            m[o] = _moment(system, run, friction)[0]
        return 0.5 * (b - a) * np.sum(wx * w * (m_d - m.reshape(len(a), -1)), axis=1)

    energy = _energy_extremes(pieces, np.asarray(nodes.t), w * (m_d - moment), partial)
    je_mean = float(np.sum(weights * je) / np.sum(weights))
    je_min, je_max = _value_extremes(pieces, je)
    je_min = max(je_min, 0.0)  # J_e = 2T/ψ̇² ≥ 0: an interpolant's −1e-32 is round-off
    return energy, (je_mean, je_min, je_max)


def verify(
    model: Model,
    fw: FlywheelDesign,
    *,
    torque: str = "constant",
    slip: float = 0.05,
    inertia: float | None = None,
    cycles: int = 1,
    start: str = "max_energy",
    method: str = "RK45",
    rtol: float = 1e-8,
    friction: bool = False,
    speed: float | None = None,
) -> dict[str, Any]:
    """Check a flywheel by simulation (needs scipy.integrate).

    The motor driver is set free with the flywheel ``inertia`` (default the net
    design value) on the crank shaft, driven by the constant mean moment M_d
    (``torque="constant"``) or by the motor curve τ(ω) = M_d·[1 + (ω_m − ω)/(s·ω_m)]
    (``torque="motor"``, slip s).  ``start="max_energy"``: at the position of the
    maximum stored energy with speed ω_m; ``"rest"``: from rest at the analysis
    start (``speed``: the start speed magnitude instead of ω_m).  Runs ``cycles``
    crank revolutions past the first mark (the position of maximum stored energy)
    and measures δ = (ω_max − ω_min)/ω_mean over the last one.
    """
    from .integration import simulate  # scipy.integrate: not on `run`'s path
    from .simulation import speed_fluctuation

    m_d = fw.sense * fw.mean_torque
    law = (
        EffortLaw("constant", value=m_d)
        if torque == "constant"
        else EffortLaw("motor", value=m_d, speed=fw.sense * fw.omega_m, slip=slip)
    )
    free = with_effort(model, fw.driver, law)
    j = fw.inertia_net if inertia is None else inertia
    if start == "max_energy":
        psi0, w0, turns = fw.at_max, fw.sense * (speed or fw.omega_m), cycles
    else:
        psi0, w0, turns = model.analysis.start, 0.0, cycles + 1
    period = 2 * np.pi / fw.omega_m
    sim = simulate(
        free,
        3 * period * (turns + 1),
        initial={fw.driver: (psi0, w0)},
        inertia={fw.driver: j},
        friction=friction,
        method=method,
        rtol=rtol,
        stop_at=psi0 + fw.sense * 2 * np.pi * turns,
        mark=fw.at_max,
        ref_speed=fw.omega_m,
    )
    if sim.status != "stopped":
        raise RuntimeError("the machine did not complete the cycles (it stalled or stopped)")
    marks = np.sort(np.concatenate((sim.marks, [0.0, sim.t_end] if start == "max_energy" else [])))
    marks = marks[np.concatenate(([True], np.diff(marks) > 1e-6 * period))]
    last = speed_fluctuation(sim, marks[-2], marks[-1])
    return {
        "delta": last["delta"],
        "last_cycle": last,
        "cycles": len(marks) - 1,
        "inertia": j,
        "torque": torque,
        "slip": slip if torque == "motor" else None,
        "simulation": sim,
        "marks": marks,
    }
