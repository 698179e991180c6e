"""The equations of motion of a model whose ``effort:`` drivers are free
(:class:`Dynamics`); see :mod:`kinetostatics.dynamics` for the method."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..errors import (
    KinetostaticsError,
    Location,
    LostInertiaError,
    SelfLockingError,
    SingularConfigurationError,
    StructureError,
)
from ..kinematics.derivatives import derivatives
from ..kinematics.positions import positions_near
from ..kinematics.schedule import schedule
from ..kinematics.start import start_pose
from ..kinetics.conditions import ZERO_SPEED, travel_extremes
from ..kinetics.elements import element_states
from ..kinetics.forces import mass_vector
from ..kinetics.inverse import kinetics
from ..kinetics.kinds import LOAD_KINDS
from ..kinetics.reactions import effort_joints
from ..model import Model, MotionLaw
from ..structure.system import System, build_system, coordinate_gradient
from . import switching
from .reduced import _law

__all__ = ["Dynamics", "STEP"]

STEP = np.radians(10.0)  # largest driver step of one position projection
JUMP = 0.35  # |corrector| / |move| above which a projection is a jump
PROBE = 1e-6  # probe speed at rest, × the reference speed


@dataclass
class _Eval:
    """The terms of the equations of motion at one state."""

    t: float
    psi: np.ndarray  # (n_d,) all driver coordinates
    psi_d: np.ndarray  # (n_d,) speeds used (a probe speed at rest)
    q: np.ndarray
    qd: np.ndarray
    qdd0: np.ndarray  # q̈ at zero free accelerations
    dqdd: np.ndarray  # (n_f, n_q) q̈ per unit free acceleration
    tau0: np.ndarray  # (n_d,) efforts at zero free accelerations
    dtau: np.ndarray  # (n_f, n_d) efforts per unit free acceleration
    tangent: np.ndarray  # (n_d, n_q) ∂q/∂ψ
    accel: np.ndarray | None = None  # free accelerations, once solved
    tau: np.ndarray | None = None  # efforts the linkage needs at accel (without J_x a)
    applied: np.ndarray | None = None
    effort: np.ndarray | None = None  # efforts applied: the laws (free), the required (prescribed)
    mode: tuple | None = None  # the loads' frozen switching state (None: from the state)


class Dynamics:
    """Equations of motion of a model whose ``effort:`` drivers are free.

    Parameters
    ----------
    model : Model
        At least one ``effort:`` driver; motion drivers + effort drivers = mobility.
    inertia : mapping, optional
        Added inertia (kg·m², or kg for a prismatic driver) on free coordinates by
        driver name: a flywheel on that shaft.
    friction : bool, optional
        Friction inside the equations of motion (default: when the model has
        friction).  Needs one free coordinate and no prescribed motion.
    sense : ±1
        The expected sense of motion of the first free coordinate (the sense in
        which ``angle`` load conditions are measured, as in ``analyze``).
    ref_speed : float, optional
        Speed scale (rad/s) of the zero-speed thresholds (docs/conventions.md: |x| ≤ 1e-9·x_ref
        counts as zero); default the largest prescribed speed, else 1 rad/s.
    """

    def __init__(
        self,
        model: Model,
        *,
        inertia: Mapping[str, float] | None = None,
        friction: bool | None = None,
        sense: float = 1.0,
        ref_speed: float | None = None,
    ):
        motion = [d for d in model.drivers if d.motion is not None]
        free = [d for d in model.drivers if d.motion is None]
        if not free:
            raise StructureError(
                [
                    (
                        Location(model.source, path="drivers"),
                        "nothing to simulate: every driver prescribes a motion; give "
                        "the driver(s) to be set free an effort: instead of a motion:",
                    )
                ]
            )
        self.original = model
        sense = 1.0 if sense >= 0 else -1.0
        drivers = tuple(motion) + tuple(
            replace(d, motion=MotionLaw(sense), effort=None) for d in free
        )
        self.model = replace(model, drivers=drivers)
        self.system = system = build_system(self.model)
        mobility = system.structure.mobility
        if len(drivers) != mobility:
            raise StructureError(
                [
                    (
                        Location(model.source, path="drivers"),
                        f"simulate needs one driver per degree of freedom (mobility "
                        f"{mobility}); the file has {len(drivers)}: each free "
                        "coordinate is an effort driver's (effort: 0 for a passive "
                        "joint)",
                    )
                ]
            )
        self.names = [d.name for d in drivers]
        self.free_names = [d.name for d in free]
        self.n_d, self.n_f = len(drivers), len(free)
        self.free = np.arange(len(motion), len(drivers))
        self.fixed = np.arange(len(motion))
        self.laws = [_law(d.effort) for d in free]
        cons = system.motion_drivers
        self.angular = np.array([c.joint.angular for c in cons])
        self.scale = np.where(self.angular, 1.0, system.l_ref)
        self.drive = schedule(system)
        self.added = np.zeros(self.n_f)
        for name, value in (inertia or {}).items():
            if name not in self.free_names:
                raise KeyError(
                    f"added inertia on '{name}': not a free (effort) driver; the free "
                    f"drivers are: {', '.join(self.free_names)}"
                )
            self.added[self.free_names.index(name)] += float(value)
        self.friction = (
            bool(model.has_friction if friction is None else friction) and model.has_friction
        )
        self.coulomb = self.friction or any(LOAD_KINDS[load.kind].opposes for load in model.loads)
        if self.friction and (self.n_f != 1 or motion):
            raise StructureError(
                [
                    (
                        Location(model.source, path="drivers"),
                        "forward dynamics with friction needs one free coordinate and "
                        "no prescribed motion; simulate with friction: false",
                    )
                ]
            )
        speeds = [abs(d.motion.speed) for d in motion]
        self.ref_speed = float(ref_speed or max(speeds, default=0.0) or 1.0)
        self.n_j = system.n_joint_rows
        # prescribed drivers whose effort is taken at another joint (balance_at): their
        # effort's power is effort × that joint's relative speed, not × the driver speed
        self._moved = [
            (d, k)
            for d, (c, k) in enumerate(zip(cons, effort_joints(system)))
            if c.driver.balance_at not in (None, c.joint.name)
        ]
        self.mass_vector = mass_vector(system)
        # a damper's dissipated work is integrated as one more state after the drivers' work
        self.dampers = any(not e.spring for e in model.elements)
        self.n_y = 2 * self.n_f + 1 + int(self.dampers)
        self.extremes = self._extremes()
        q0, _ = start_pose(system, self.drive)
        self._anchor = self._with_tangent(self.drive(np.array([0.0]))[0][0], q0)
        self._cache: dict = {}
        self._modes: dict = {}
        self.evaluations = 0
        self._switches = switching.switching_functions(
            system, self.model.loads, self.extremes, self.ref_speed, self.friction
        )

    # -- set-up ------------------------------------------------------------------
    def _extremes(self) -> dict:
        """Extremes of ``travel`` conditions over the whole motion (a cycle of the first
        driver, :func:`~kinetostatics.analysis.travel_extremes`)."""
        return travel_extremes(self.system, self.drive)

    def prescribed(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        p, pd, _ = self.drive(np.array([t]))
        return p[0][self.fixed], pd[0][self.fixed]

    def start(self) -> np.ndarray:
        """Default initial coordinates of the free drivers (the drive's start)."""
        return self.drive(np.array([0.0]))[0][0][self.free]

    def _full(self, t: float, psi_f: np.ndarray, psid_f: np.ndarray):
        psi, psid = np.empty(self.n_d), np.empty(self.n_d)
        psi[self.fixed], psid[self.fixed] = self.prescribed(t)
        psi[self.free], psid[self.free] = psi_f, psid_f
        return psi, psid

    # -- positions on the manifold and on the branch ----------------------------------
    def _with_tangent(self, psi, q):
        eye = np.eye(self.n_d)
        qd, qdd, _ = derivatives(
            self.system,
            np.broadcast_to(q, (self.n_d, q.size)).copy(),
            eye,
            np.zeros((self.n_d, self.n_d)),
        )
        return psi.copy(), q.copy(), qd, qdd

    def _weights(self):
        return np.tile(
            [1.0 / self.system.l_ref, 1.0 / self.system.l_ref, 1.0], len(self.system.links)
        )

    def positions(self, psi: np.ndarray) -> np.ndarray:
        """q at driver coordinates ``psi (n_d,)`` on the branch followed so far.

        Steps of ≤ 10° from the last solved state with a second-order predictor
        along ψ; a step whose Newton correction is large compared with the move
        (a jump to another branch) or that fails is halved.
        """
        p, q, tan, curv = self._anchor
        target = np.asarray(psi, dtype=float)
        w = self._weights()
        limit = STEP
        while True:
            d = target - p
            size = float(np.max(np.abs(d) / self.scale)) if d.size else 0.0
            if size == 0.0:
                return q
            if size > limit:
                d = d * (limit / size)
            pred = q + d @ tan + 0.5 * (d**2) @ curv
            try:
                qn = positions_near(self.system, (p + d)[None], pred[None], self.drive)[0]
                corr = np.max(np.abs((qn - pred) * w))
                move = np.max(np.abs((qn - q) * w))
                ok = corr <= JUMP * move or corr <= 1e-9
            except KinetostaticsError:
                ok = False
            if not ok:
                limit = min(limit, size) * 0.5
                if limit < 1e-7:
                    raise SingularConfigurationError(
                        "free coordinates",
                        ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.names, p + d)),
                        "the positions cannot be continued smoothly (a singular position: "
                        "the free coordinates do not describe the motion here)",
                    )
                continue
            p, q = p + d, qn
            if np.allclose(p, target, rtol=0, atol=1e-15):
                return q
            p, q, tan, curv = self._with_tangent(p, q)
            self._anchor = (p, q, tan, curv)
            limit = min(STEP, 2 * limit)

    # -- the terms of the equations of motion -------------------------------------
    def evaluate(
        self, t: float, psi_f, psid_f, direction: float = 0.0, mode: tuple | None = None
    ) -> _Eval:
        """Positions, velocities, M, h and the efforts at a state (no accelerations yet).

        ``direction``: at rest (|ψ̇_f| below the zero-speed threshold) the probe sense
        of the free coordinate used for friction and velocity-opposing loads.
        ``mode``: the loads' switching state frozen for an integration piece
        (:meth:`load_mode`); None decides it from the state.
        """
        psi_f = np.atleast_1d(np.asarray(psi_f, dtype=float))
        psid_f = np.atleast_1d(np.asarray(psid_f, dtype=float)).copy()
        if direction and self._at_rest(psid_f):
            psid_f = direction * PROBE * self.ref_speed * self.scale[self.free]
        psi, psid = self._full(t, psi_f, psid_f)
        q = self.positions(psi)
        nf, nd = self.n_f, self.n_d
        nb = 1 + nf + nd
        qb = np.broadcast_to(q, (nb, q.size)).copy()
        pd = np.concatenate((np.broadcast_to(psid, (1 + nf, nd)), np.eye(nd)))
        pdd = np.zeros((nb, nd))
        pdd[: 1 + nf, self.fixed] = self.drive(np.array([t]))[2][0][self.fixed]
        pdd[1 + np.arange(nf), self.free] = 1.0
        qd, qdd, lu = derivatives(self.system, qb, pd, pdd)
        self._anchor = (psi, q, qd[1 + nf :], qdd[1 + nf :])
        kin = kinetics(
            self._loaded(mode),
            qb,
            qd,
            qdd,
            np.broadcast_to(psi, (nb, nd)),
            lu=lu,
            ref_speed=self.ref_speed,
            extremes=self.extremes,
        )
        tau = kin.x0[:, self.n_j :]
        self.evaluations += 1
        return _Eval(
            t,
            psi,
            psid,
            q,
            qd[0],
            qdd[0],
            qdd[1 : 1 + nf] - qdd[0],
            tau[0],
            tau[1 : 1 + nf] - tau[0],
            qd[1 + nf :],
            mode=mode,
        )

    # -- loads frozen on an integration piece ------------------------------------------
    def load_mode(self, ev: _Eval) -> tuple:
        """The loads' switching state at an evaluated state: per load, whether it is
        active and (a resistance) the sign of the velocity it opposes."""
        return switching.load_mode(
            self.system, self.model.loads, ev.q, ev.qd, ev.psi, self.extremes, self.ref_speed
        )

    def _loaded(self, mode: tuple | None) -> System:
        """The system whose loads are those of ``mode``, held fixed
        (:func:`~.switching.frozen_loads`), cached per mode."""
        if mode is None or not self.model.loads:
            return self.system
        cached = self._modes.get(mode)
        if cached is None:
            cached = switching.frozen_loads(self.system, self.model.loads, mode)
            self._modes[mode] = cached
        return cached

    def _at_rest(self, psid_f) -> bool:
        thr = ZERO_SPEED * self.ref_speed * self.scale[self.free]
        return bool(np.all(np.abs(psid_f) <= thr))

    def applied(self, psi_f, psid_f) -> np.ndarray:
        """The applied efforts of the free drivers (their laws)."""
        return np.array(
            [
                law(p, v, 2 * np.pi if a else None)
                for law, p, v, a in zip(self.laws, psi_f, psid_f, self.angular[self.free])
            ],
            dtype=float,
        )

    def _required_friction(self, ev: _Eval, accel: np.ndarray) -> np.ndarray:
        """Efforts of all drivers with friction (consistent solution) at ``accel``."""
        qdd = ev.qdd0 + accel @ ev.dqdd
        kin = kinetics(
            self._loaded(ev.mode),
            ev.q[None],
            ev.qd[None],
            qdd[None],
            ev.psi[None],
            ref_speed=self.ref_speed,
            extremes=self.extremes,
            friction=True,
        )
        x = kin.friction["solution"].x[0, self.n_j :]
        if not np.all(np.isfinite(x)):
            at = ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.names, ev.psi))
            raise SelfLockingError(
                f"self-locking at {at}: the consistent friction solution does not exist"
            )
        return x

    def _check_inertia(self, ev: _Eval, mass: np.ndarray) -> None:
        """Refuse a state whose inertia M (the efforts per unit free acceleration,
        formed as a difference of efforts) is known to fewer than 3 digits: a free
        coordinate's efforts at zero acceleration are over 1e-3/eps times its own
        inertia (a stiff spring, a huge speed), and M would be round-off (or exactly
        singular).  Row by row: a nearly massless coordinate (a clearance link) with
        small efforts of its own is no sign, whatever the other rows carry."""
        tau = np.abs(ev.tau0[self.free])
        big = float(np.max(tau, initial=0.0))
        m = np.abs(np.diag(mass))
        if np.all(np.isfinite(mass)) and np.all(m > 1e3 * np.finfo(float).eps * tau):
            return
        at = ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.names, ev.psi))
        raise LostInertiaError(
            f"the motion cannot be integrated at t = {ev.t:.6g} s ({at}): the inertia of "
            f"the free coordinates ({np.min(m):.3g}) is lost to round-off against efforts "
            f"of {big:.3g} (a very stiff spring, a huge load or speed); make them smaller "
            "or the masses larger"
        )

    def accelerations(self, ev: _Eval, psid_f) -> _Eval:
        """Solve (M + J_x) a = τ_app − h (frictionless) or, with friction,
        τ_app − J_x a − τ_f(a) = 0 by Broyden's method."""
        free = self.free
        mass = ev.dtau[:, free].T + np.diag(self.added)
        applied = self.applied(ev.psi[free], psid_f)
        self._check_inertia(ev, mass)
        accel = np.linalg.solve(mass, applied - ev.tau0[free])
        tau = ev.tau0 + accel @ ev.dtau
        if self.friction:
            jac = -mass
            tau = self._required_friction(ev, accel)
            r = applied - self.added * accel - tau[free]
            for _ in range(50):
                scale = max(
                    np.max(np.abs(applied)),
                    np.max(np.abs(tau)),
                    np.max(np.abs(mass @ accel)),
                    1e-300,
                )
                if np.max(np.abs(r)) <= 1e-11 * scale:
                    break
                step = -np.linalg.solve(jac, r)
                accel = accel + step
                tau = self._required_friction(ev, accel)
                rn = applied - self.added * accel - tau[free]
                jac = jac + np.outer(rn - r - jac @ step, step) / (step @ step)
                r = rn
            else:
                raise SelfLockingError(
                    "the acceleration with friction did not converge at "
                    + ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.names, ev.psi))
                )
        ev.accel, ev.tau, ev.applied = accel, tau, applied
        ev.effort = tau.copy()
        ev.effort[free] = applied
        return ev

    def state(
        self, t: float, y: np.ndarray, direction: float = 0.0, mode: tuple | None = None
    ) -> _Eval:
        """The solved state (accelerations and efforts) at (t, y), cached."""
        nf = self.n_f
        key = (t, y[: 2 * nf].tobytes(), direction, mode)
        ev = self._cache.get(key)
        if ev is None or ev.accel is None:
            psid_f = y[nf : 2 * nf]
            ev = self.accelerations(ev or self.evaluate(t, y[:nf], psid_f, direction, mode), psid_f)
            if len(self._cache) > 8:
                self._cache.clear()
            self._cache[key] = ev
        return ev

    def rhs(
        self, t: float, y: np.ndarray, direction: float = 0.0, mode: tuple | None = None
    ) -> np.ndarray:
        """d/dt (ψ_f, ψ̇_f, W[, D]): W the work of all drivers, D (when ``y`` has it) the
        work dissipated by the dampers."""
        nf = self.n_f
        ev = self.state(t, y, direction, mode)
        power = float(ev.effort @ self._effort_speeds(ev, self._speeds(t, y)))
        extra = [self.dissipation(ev)] if y.size > 2 * nf + 1 else []
        return np.concatenate((y[nf : 2 * nf], ev.accel, [power], extra))

    def dissipation(self, ev: _Eval) -> float:
        """The power dissipated by the dampers at a state (W, ≥ 0)."""
        if not self.dampers:
            return 0.0
        return float(element_states(self.system, ev.q, ev.qd).total("power", springs=False))

    def elastic_energy(self, ev: _Eval) -> float:
        """The energy stored in the springs at a state (J)."""
        if not self.system.model.elements:
            return 0.0
        return float(element_states(self.system, ev.q, None).total("energy", springs=True))

    def _speeds(self, t, y):
        s = np.empty(self.n_d)
        s[self.fixed] = self.prescribed(t)[1]
        s[self.free] = y[self.n_f : 2 * self.n_f]
        return s

    def _effort_speeds(self, ev: _Eval, speeds: np.ndarray) -> np.ndarray:
        """The relative speeds of the joints that carry the efforts: the driver speeds,
        except for a driver whose effort is taken at another joint (``balance_at``)."""
        for d, k in self._moved:
            speeds[d] = float(coordinate_gradient(self.system, ev.q, k) @ ev.qd)
        return speeds

    # -- breakaway -------------------------------------------------------------------
    def breakaway(self, t: float, psi_f) -> dict[str, Any]:
        """At rest (one free coordinate): the efforts needed to start moving either way
        and the sense in which the applied effort starts the motion (0: stays at rest)."""
        if self.n_f != 1:
            return {"sense": 0.0, "checked": False}
        psi_f = np.atleast_1d(psi_f)
        zero = np.zeros(1)
        need = {}
        for s in (1.0, -1.0):
            ev = self.evaluate(t, psi_f, zero, direction=s)
            tau = self._required_friction(ev, zero) if self.friction else ev.tau0
            need[s] = float(tau[self.free][0])
        applied = float(self.applied(psi_f, zero)[0])
        sense = 1.0 if applied > need[1.0] else -1.0 if applied < need[-1.0] else 0.0
        return {
            "sense": sense,
            "applied": applied,
            "to_start_positive": need[1.0],
            "to_start_negative": need[-1.0],
            "checked": True,
        }

    # -- switching functions (:mod:`.switching`) -------------------------------------
    def switching_values(
        self, t: float, y: np.ndarray, direction: float = 0.0, mode: tuple | None = None
    ) -> np.ndarray:
        if not self._switches:
            return np.zeros(0)
        ev = self._evaluated(t, y, direction, mode)
        return np.array([f(ev.q, ev.qd, ev.psi) for _, f, _ in self._switches])

    def _evaluated(
        self, t: float, y: np.ndarray, direction: float = 0.0, mode: tuple | None = None
    ) -> _Eval:
        key = (t, y[: 2 * self.n_f].tobytes(), direction, mode)
        ev = self._cache.get(key)
        if ev is None:
            ev = self.evaluate(t, y[: self.n_f], y[self.n_f : 2 * self.n_f], direction, mode)
            self._cache[key] = ev
        return ev

    def mode_at(self, t: float, y: np.ndarray, direction: float = 0.0) -> tuple:
        """The loads' switching state decided from the state (t, y)."""
        return self.load_mode(self._evaluated(t, y, direction))

    # -- energy -----------------------------------------------------------------------
    def energy(self, ev: _Eval) -> tuple[float, float]:
        """(kinetic, potential) energy at a state: ½ q̇ᵀMq̇ + ½ J_x ψ̇_f², −Σ m g·r_S."""
        kinetic = 0.5 * float(
            np.sum(self.mass_vector * ev.qd**2) + np.sum(self.added * ev.psi_d[self.free] ** 2)
        )
        g = np.tile(np.append(self.system.model.gravity, 0.0), len(self.system.links))
        return kinetic, -float(np.sum(self.mass_vector * g * ev.q))
