"""Integration of the motion in pieces between the load switches (:func:`simulate`).

``scipy.integrate`` is imported only when :func:`simulate` runs.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..base.arguments import real_number
from ..model import Model
from .engine import Dynamics
from .reduced import _law
from .simulation import Simulation, _Segment

__all__ = ["simulate"]


def simulate(  # noqa: PLR0913  the public keywords (docs/dynamics.md)
    model: Model | Dynamics,
    until: float,
    *,
    initial: Mapping[str, float | tuple[float, float]] | None = None,
    inertia: Mapping[str, float] | None = None,
    friction: bool | None = None,
    method: str = "RK45",
    rtol: float = 1e-8,
    atol: float | None = None,
    max_step: float = np.inf,
    stop_at: float | None = None,
    mark: float | None = None,
    ref_speed: float | None = None,
    progress: bool = False,
) -> Simulation:
    """Integrate the motion of the free (``effort:``) coordinates from t = 0 to ``until`` s.

    Parameters
    ----------
    model : Model or Dynamics
    initial : mapping, optional
        Per free driver, its initial coordinate (rad or m) or (coordinate, speed);
        default the analysis start (or the sketch) at rest.
    inertia, friction, ref_speed
        See :class:`Dynamics` (ignored when a Dynamics is given).
    method, rtol, atol, max_step
        ``scipy.integrate.solve_ivp`` options; ``atol`` defaults to ``rtol`` for
        coordinates (rad, or × L_ref m) and ``rtol`` × the reference speed for speeds.
    stop_at : float, optional
        Stop when the first free coordinate reaches this value (rad or m).
    mark : float, optional
        Record the times at which the first free coordinate passes ``mark`` (mod 2π
        for a revolute): the cycle boundaries, ``Simulation.marks``.
    progress : bool
        Show the simulated time on stderr (a tqdm bar, moved at the end of each piece
        between load switches).
    """
    from scipy.integrate import solve_ivp

    until, rtol, atol, initial = _checked(
        until, rtol, atol, max_step, stop_at, mark, ref_speed, initial
    )
    if isinstance(model, Dynamics):
        dyn = model
    else:
        dyn = _dynamics(model, initial, inertia, friction, ref_speed)
    y = _initial_state(dyn, initial)
    scale = dyn.scale[dyn.free]
    tol = rtol if atol is None else atol
    atol_v = np.concatenate(
        (tol * scale, tol * dyn.ref_speed * scale, [np.inf] * (dyn.n_y - 2 * dyn.n_f))
    )
    sim = Simulation(dyn, [], options=dict(method=method, rtol=rtol, atol=atol))
    evaluations0 = dyn.evaluations
    run = _Run(
        solve_ivp,
        dyn,
        sim,
        until,
        y,
        dict(method=method, rtol=rtol, atol=atol_v),
        max_step,
        mark_event=_mark_event(dyn, mark),
        stop_event=None if stop_at is None else _event(lambda tt, yy: yy[0] - stop_at, True),
    )
    bar = _progress_bar(until, progress)
    try:
        for _ in range(100_000):
            done = run.t >= until or run.step()
            bar.update(min(run.t, until) - bar.n)  # a piece ends at a load switch or mark
            if done:
                break
        else:
            raise RuntimeError("too many integration pieces (chattering load switches?)")
    finally:
        bar.close()
    sim.nfev = dyn.evaluations - evaluations0
    sim.marks = np.array(run.marks)
    return sim


def _progress_bar(until: float, enabled: bool):
    """The simulated time so far, on stderr (tqdm), moved at the end of each piece."""
    from tqdm import tqdm

    return tqdm(
        total=until,
        desc="simulate",
        disable=not enabled,
        bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.4g}/{total:.4g} s [{elapsed}]",
        mininterval=0.2,
        dynamic_ncols=True,
    )


def _checked(until, rtol, atol, max_step, stop_at, mark, ref_speed, initial):
    """The options of :func:`simulate` checked: ``until``, ``rtol``, ``atol`` as numbers
    and ``initial`` as a dict."""
    until = real_number("until", until, low=0.0, strict_low=True, why="s")
    rtol = real_number("rtol", rtol, low=0.0, high=1.0, strict_low=True)
    if atol is not None:
        atol = real_number("atol", atol, low=0.0, strict_low=True)
    if not (isinstance(max_step, (int, float, np.integer, np.floating)) and max_step > 0):
        raise ValueError(f"max_step = {max_step!r}: expected a positive number (or inf)")
    for name, v in (("stop_at", stop_at), ("mark", mark)):
        if v is not None:
            real_number(name, v)
    if ref_speed is not None:
        real_number("ref_speed", ref_speed, low=0.0, strict_low=True)
    initial = dict(initial or {})
    for name, v in initial.items():
        for k, x in enumerate(v if isinstance(v, (tuple, list)) else (v,)):
            real_number(
                f"initial['{name}']" + (f"[{k}]" if isinstance(v, (tuple, list)) else ""), x
            )
    return until, rtol, atol, initial


def _dynamics(model: Model, initial: dict, inertia, friction, ref_speed) -> Dynamics:
    """The Dynamics of ``model``, its sense that of the first free driver's initial speed
    (else of its effort) and its reference speed ``ref_speed`` or that initial speed."""
    free = [d.name for d in model.drivers if d.motion is None]
    v = initial.get(free[0]) if free else None
    first_speed = float(v[1]) if isinstance(v, (tuple, list)) else 0.0
    sense = np.sign(first_speed) or _sense_of_effort(model, free)
    return Dynamics(
        model,
        inertia=inertia,
        friction=friction,
        sense=sense,
        ref_speed=ref_speed or (abs(first_speed) or None),
    )


def _initial_state(dyn: Dynamics, initial: dict) -> np.ndarray:
    """The state (coordinates, speeds, work[, dissipated work]) at t = 0: the start at rest,
    then ``initial``."""
    nf = dyn.n_f
    psi0, psid0 = dyn.start(), np.zeros(nf)
    for name, v in initial.items():
        if name not in dyn.free_names:
            raise KeyError(
                f"initial state of '{name}': not a free (effort) driver; the free "
                f"drivers are: {', '.join(dyn.free_names)}"
            )
        k = dyn.free_names.index(name)
        psi0[k], psid0[k] = v if isinstance(v, (tuple, list)) else (v, 0.0)
    return np.concatenate((psi0, psid0, np.zeros(dyn.n_y - 2 * nf)))


def _mark_event(dyn: Dynamics, mark: float | None):
    """The event of the first free coordinate passing ``mark`` (mod 2π for a revolute)."""
    if mark is None:
        return None
    return _event(
        (lambda tt, yy: np.sin(0.5 * (yy[0] - mark)))
        if dyn.angular[dyn.free[0]]
        else (lambda tt, yy: yy[0] - mark),
        False,
    )


class _Run:
    """One integration in pieces: the time, state and sense of motion reached, the loads'
    state known just past a switch, and the pieces and events recorded in ``sim``."""

    def __init__(self, solve_ivp, dyn, sim, until, y, options, max_step, *, mark_event, stop_event):  # noqa: PLR0913  one integration's state, set once
        self.solve_ivp = solve_ivp
        self.dyn, self.sim, self.until = dyn, sim, until
        self.options = options  # method, rtol, atol of solve_ivp
        self.max_step = max_step
        self.mark_event, self.stop_event = mark_event, stop_event
        self.short = [e for e in (mark_event, stop_event) if e is not None]  # on a nudge too
        self.thresholds = np.array([thr for _, _, thr in dyn._switches])
        self.nf = dyn.n_f
        self.t, self.y, self.direction, self.first_step = 0.0, y, 0.0, None
        self.pending = None  # the loads' state just past a switch (known from the last piece)
        self.marks: list[float] = []

    def _rhs(self, d, m):
        dyn = self.dyn
        return lambda tt, yy: dyn.rhs(tt, yy, d, m)

    def _add_marks(self, found):
        marks = self.marks
        for x in found:  # a mark at a switch is seen by both pieces
            if not marks or abs(float(x) - marks[-1]) > 1e-9 * max(1.0, abs(float(x))):
                marks.append(float(x))

    def step(self) -> bool:
        """A restart at rest, a nudge off the switches at their threshold, one piece to
        the next event.  True when the integration ends."""
        dyn, nf = self.dyn, self.nf
        if self.t > 0 and self._at_stop():  # a switch ended the last piece on the stop
            self.sim.events.append({"t": self.t, "kind": "stop"})
            self.sim.status = "stopped"
            return True
        if nf == 1 and dyn._at_rest(self.y[nf : 2 * nf]):
            if self._restart_at_rest():
                return True
        elif not dyn._at_rest(self.y[nf : 2 * nf]):
            self.direction = 0.0
        # switching functions at their threshold now (a start at rest, or on a band
        # edge): first a short piece without events carries them off zero
        near = np.abs(dyn.switching_values(self.t, self.y, self.direction)) <= 2 * self.thresholds
        if near.any() and self._nudge(near):
            return True
        return self._piece(near)

    def _at_stop(self) -> bool:
        """The state lies on the stop (to round-off): a load switch at the same position ended
        the piece first, and the next piece would start past the stop's root unseen."""
        if self.stop_event is None:
            return False
        return abs(self.stop_event(self.t, self.y)) <= 1e-12 * max(1.0, abs(self.y[0]))

    def _restart_at_rest(self) -> bool:
        """At rest (one free coordinate): the sense it breaks away in, or stuck (True)."""
        nf, t = self.nf, self.t
        check = self.dyn.breakaway(t, self.y[:nf])
        self.direction = check.pop("sense")
        self.sim.events.append({"t": t, "kind": "rest", "sense": self.direction, **check})
        self.y[nf : 2 * nf] = 0.0
        if self.direction == 0.0:
            self.sim.segments.append(_Segment(t, self.until, None, self.y.copy()))
            self.sim.status = "stuck"
            return True
        return False

    def _nudge(self, near: np.ndarray) -> bool:
        """A short piece without switch events, lengthened until the switches ``near``
        their threshold are off it; ``near`` keeps (in place) those still on it.  True
        when the integration ends (a stop in the nudge, or ``until`` reached)."""
        dyn, nf, thresholds = self.dyn, self.nf, self.thresholds
        t, y, until = self.t, self.y, self.until
        tau = 1e-10 / dyn.ref_speed
        for _ in range(30):
            tau = min(tau, until - t)
            sol0 = self.solve_ivp(
                self._rhs(self.direction, self.pending),
                (t, t + tau),
                y,
                **self.options,
                dense_output=True,
                events=self.short or None,
            )
            if sol0.status == 1:  # the stop lies in the nudge
                break
            y0 = sol0.y[:, -1]
            g0 = dyn.switching_values(t + tau, y0, self.direction)
            if np.all(np.abs(g0[near]) > 2 * thresholds[near]) or t + tau >= until:
                break
            tau *= 4.0
        if self.mark_event is not None:
            self._add_marks(sol0.t_events[0])
        if sol0.status == 1:
            t_s = float(sol0.t[-1])
            self.sim.segments.append(_Segment(t, t_s, sol0.sol, mode=self.pending))
            self.sim.events.append({"t": t_s, "kind": "stop"})
            self.t, self.y = t_s, sol0.y[:, -1].copy()
            self.sim.status = "stopped"
            return True
        self.sim.segments.append(_Segment(t, t + tau, sol0.sol, mode=self.pending))
        self.t, self.y = t + tau, y0.copy()
        near &= np.abs(g0) <= 2 * thresholds  # still on zero: not watched here
        if not dyn._at_rest(self.y[nf : 2 * nf]):
            self.direction = 0.0
        return self.t >= until

    def _events(self, near: np.ndarray, mode) -> tuple[list, list]:
        """The events watched on a piece and their kinds: the switches not ``near`` their
        threshold, the coming to rest (Coulomb friction, one free coordinate), the stop
        and the mark."""
        dyn, nf, direction = self.dyn, self.nf, self.direction
        events, kinds = [], []
        for k in range(len(dyn._switches)):
            if not near[k]:
                events.append(
                    _event(
                        lambda tt, yy, k=k, d=direction, m=mode: dyn.switching_values(tt, yy, d, m)[
                            k
                        ],
                        True,
                    )
                )
                kinds.append(("switch", k))
        if dyn.coulomb and nf == 1:
            s = direction or np.sign(self.y[nf])
            events.append(_event(lambda tt, yy: yy[nf], True, -s))
            kinds.append(("rest", None))
        if self.stop_event is not None:
            events.append(self.stop_event)
            kinds.append(("stop", None))
        if self.mark_event is not None:
            events.append(self.mark_event)
            kinds.append(("mark", None))
        return events, kinds

    def _piece(self, near: np.ndarray) -> bool:
        """One piece from t towards ``until``, ended by the first event.  True when the
        integration ends (``until`` or the stop reached)."""
        dyn, nf, t, y, until = self.dyn, self.nf, self.t, self.y, self.until
        # the loads' state is held fixed on the piece: its right-hand side is smooth and
        # extends smoothly past the next switch, where the event is located
        mode = self.pending if self.pending is not None else dyn.mode_at(t, y, self.direction)
        self.pending = None
        events, kinds = self._events(near, mode)
        first = self.first_step
        opts = {} if first is None else {"first_step": min(first, until - t)}
        sol = self.solve_ivp(
            self._rhs(self.direction, mode),
            (t, until),
            y,
            **self.options,
            dense_output=True,
            events=events or None,
            max_step=self.max_step,
            **opts,
        )
        if sol.status == -1:
            raise RuntimeError(f"integration failed at t = {sol.t[-1]:.6g} s: {sol.message}")
        for (kind, _), te in zip(kinds, sol.t_events or []):
            if kind == "mark":
                self._add_marks(te)
        if len(sol.t) > 2:
            self.first_step = float(sol.t[-2] - sol.t[-3]) or None
        t_e, y_e = float(sol.t[-1]), sol.y[:, -1].copy()
        self.sim.segments.append(_Segment(t, t_e, sol.sol, mode=mode))
        self.t, self.y = t_e, y_e
        if sol.status == 0:
            return True
        fired = [
            (kind, k)
            for (kind, k), te in zip(kinds, sol.t_events)
            if kind != "mark" and te.size and abs(te[-1] - t_e) <= 1e-12 * max(1.0, t_e)
        ]
        if any(kind == "stop" for kind, _ in fired):
            self.sim.events.append({"t": t_e, "kind": "stop"})
            self.sim.status = "stopped"
            return True
        if any(kind == "rest" for kind, _ in fired):
            self.y[nf : 2 * nf] = 0.0
            return False
        self._switch(sol, t_e, mode, [k for kind, k in fired if kind == "switch"])
        return False

    def _switch(self, sol, t_e: float, mode, idx: list[int]) -> None:
        """A load switch at ``t_e``: the next piece starts from the state there (the root
        found on this piece's dense output: its right-hand side is smooth through the
        event).  Which side the loads take next is read a little past the event on this
        piece's smooth continuation; the state is not moved there."""
        dyn, direction = self.dyn, self.direction
        self.sim.events.append(
            {"t": t_e, "kind": "switch", "what": [dyn._switches[k][0] for k in idx]}
        )
        tau = 1e-10 / dyn.ref_speed
        for _ in range(17):  # at most ~1e-5 s × (1 rad/s / ref_speed)
            y_p = np.asarray(sol.sol(t_e + tau), dtype=float)
            g = dyn.switching_values(t_e + tau, y_p, direction, mode)
            if all(abs(g[k]) > 2 * self.thresholds[k] for k in idx):
                break
            tau *= 2.0
        self.pending = dyn.load_mode(dyn._evaluated(t_e + tau, y_p, direction, mode))


def _sense_of_effort(model: Model, free: list[str]) -> float:
    """The sense in which the first free driver's effort pushes (at rest), else +1."""
    if not free:
        return 1.0
    law = _law(next(d for d in model.drivers if d.name == free[0]).effort)
    v = float(law(0.0, 0.0))
    return float(np.sign(v)) or 1.0


def _bisect(f, a: float, b: float) -> float:
    fa = f(a)
    for _ in range(200):
        m = 0.5 * (a + b)
        if m in (a, b):
            break
        if fa * f(m) <= 0:
            b = m
        else:
            a, fa = m, f(m)
    return 0.5 * (a + b)


def _event(f, terminal: bool, direction: float = 0.0):
    f.terminal, f.direction = terminal, float(direction)
    return f
