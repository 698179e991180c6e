"""The run of the positions: the rows solved, or, where the linkage cannot follow the run
asked for, its reachable range.

:func:`solve_run` solves the positions of the rows; where the linkage does not assemble,
:func:`reachable_rows` recovers what a constant-speed crank that cannot turn fully can do
(the given rows moved behind the start, or a run over the reachable range between the
limit positions) or raises the error with the reachable range added.  Over one period of
a motion law, whether the pose repeats decides whether the run is a full cycle.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import AssemblyError, SingularConfigurationError
from ..kinematics.continuation import Singularity
from ..kinematics.newton import group_condition
from ..kinematics.positions import PositionSolution, reachable_range, solve_positions
from ..kinematics.schedule import Schedule
from ..structure.system import System, keep_poses

__all__ = ["Rows", "solve_run", "reachable_rows"]


@dataclass(frozen=True, eq=False)
class Rows:
    """The rows asked for, before they are solved: their times ``t``, which of them were
    given as driver coordinates (``given``), whether they cover a full cycle (``full``),
    how the caller asked for them (``given_as``: ``"positions"``, ``"times"``, or None for
    the file's ``analysis``) and whether a run the linkage cannot follow becomes one over
    its reachable range (``reachable``)."""

    t: np.ndarray
    given: np.ndarray
    full: bool
    given_as: str | None = None
    reachable: bool = False

    @property
    def by_coordinates(self) -> bool:
        return self.given_as == "positions"

    @property
    def by_times(self) -> bool:
        return self.given_as == "times"


def solve_run(
    system: System, sched: Schedule, rows: Rows
) -> tuple[np.ndarray, PositionSolution, bool]:
    """(t, solution, full): the positions of the ``rows``, or where the linkage cannot
    follow the run, those of :func:`reachable_rows`; over one period of a law, whether the
    pose repeats (a full cycle)."""
    t, full = rows.t, rows.full
    closing = full and sched.law is not None  # one period of the law: does the pose repeat?
    try:
        sol = solve_positions(system, np.append(t, sched.law.duration) if closing else t, sched)
    except AssemblyError as exc:
        t, sol, full = reachable_rows(system, sched, rows, exc)
    if closing:
        full = _same_pose(system, sol.q[-1], sol.q[0])
        pe = None if sol.poses is None else sol.poses[:-1]
        sol = replace(
            sol,
            q=sol.q[:-1],
            signatures=sol.signatures[:-1],
            iterations=sol.iterations[:-1],
            poses=pe,
        )
    sol.q.flags.writeable = False  # the rows every later stage reads (link_poses' key)
    if sol.poses is not None:  # their frames from the pass that placed them
        keep_poses(system, sol.q, sol.poses)
    return t, sol, full


def reachable_rows(
    system: System, sched: Schedule, rows: Rows, exc: AssemblyError
) -> tuple[np.ndarray, PositionSolution, bool]:
    """The recovery of a run the linkage cannot follow (``exc``): (t, solution, full) of
    the given rows moved behind the start (:func:`_positions_behind`) or of a run over
    the reachable range (:func:`_reachable_run`), for a constant-speed crank that cannot
    turn fully; otherwise ``exc``, with the reachable range where it is known."""
    t, given = rows.t, rows.given
    if sched.law is not None:
        raise _law_out_of_reach(system, sched, exc) from None
    if isinstance(exc, SingularConfigurationError) or rows.by_times:
        raise exc
    behind = (
        _positions_behind(system, sched, t, given, exc, sort=not rows.by_coordinates)
        if given.any()
        else None
    )
    if behind is not None:
        return (*behind, rows.full)
    if rows.by_coordinates:
        raise exc
    return _reachable_run(system, sched, t, exc, rows.reachable)


def _reachable_run(
    system: System, sched: Schedule, t: np.ndarray, exc: AssemblyError, reachable: bool
):
    """The run of a crank that cannot follow the sweep: ``exc`` with the reachable range
    added, or (``reachable``) (t, solution, full) over that range."""
    try:
        lo, hi = reachable_range(system, sched, float(np.max(t)) + 1e-9)
    except AssemblyError:
        raise exc from None  # not even the start assembles
    if not reachable:
        exc.reachable = tuple(sched(np.array([lo, hi]))[0][:, 0])
        exc.args = (
            f"{exc.args[0]}; the reachable range is {_range_text(system, sched, lo, hi)}"
            " (`kinetostatics run --reachable` or analyze(..., reachable=True) analyses it)",
        )
        raise exc
    margin = 1e-6 * (hi - lo)  # the limits themselves are singular
    t = np.linspace(lo + margin, hi - margin, system.model.analysis.positions)
    sol = solve_positions(system, t, sched)
    plan = next(p for p in system.plans if p.group.label == exc.group)
    for k, tk in ((0, lo), (-1, hi)):  # the limit positions are singular positions
        sol.singular.append(
            Singularity(
                exc.group,
                tk,
                float(sched(np.array([tk]))[0][0, 0]),
                float(group_condition(system, sol.q[k], plan)),
            )
        )
    return t, sol, False


def _positions_behind(
    system: System,
    sched: Schedule,
    t: np.ndarray,
    given: np.ndarray,
    exc: AssemblyError,
    sort: bool,
):
    """Rows given as driver coordinates (``positions=``, ``at``) for a constant-speed crank
    that cannot turn fully: ``sample_times`` placed them up to a turn ahead of the start, where
    the linkage does not reach; a coordinate behind the start is reached running
    backwards on the same branch (a negative time).  Each given row beyond the reachable
    range [lo, hi] is moved a turn back when that lands inside it (otherwise to whichever
    of the two is nearer the start).  Returns (t, solution), sorted by time if ``sort``,
    or None where that does not apply (a full-turn crank, a prismatic driver); raises
    ``exc`` with the reachable range when a given row lies outside it either way."""
    if not system.motion_drivers[0].joint.angular or len(system.motion_drivers) != 1:
        return None
    period = 2 * np.pi / sched.reference
    try:
        lo, hi = reachable_range(system, sched, period)
    except AssemblyError:
        return None
    if hi - lo >= period:
        return None  # it turns fully: the failure is elsewhere
    tol = 1e-12 * period
    inside = lambda x: (x >= lo - tol) & (x <= hi + tol)  # noqa: E731
    back = t - period
    move = given & ~inside(t) & (inside(back) | (~inside(back) & (np.abs(back) < np.abs(t))))
    t = np.where(move, back, t)
    if np.any(~given & ~inside(t)):
        return None  # the grid itself leaves the range
    if np.any(given & ~inside(t)):
        k = int(np.argmax(given & ~inside(t)))
        far = float(sched(t[k : k + 1])[0][0, 0])
        exc.reachable = tuple(sched(np.array([lo, hi]))[0][:, 0])
        exc.args = (
            f"{system.motion_drivers[0].name} = {np.degrees(far) % 360:.6g}° is out of "
            f"reach ({exc.args[0]}); the reachable range is "
            f"{_range_text(system, sched, lo, hi)}, running forwards or backwards from "
            "analysis.start",
        )
        raise exc
    if sort:
        t = np.sort(t, kind="stable")
    return t, solve_positions(system, t, sched)


def _same_pose(system: System, qa: np.ndarray, qb: np.ndarray) -> bool:
    """Whether two poses agree (lengths to 1e-9·L_ref, angles to 1e-9 rad, modulo 2π): a law
    that is periodic need not bring the linkage back (it may cross to the other assembly)."""
    d = qa - qb
    d[2::3] = (d[2::3] + np.pi) % (2 * np.pi) - np.pi
    d[0::3] /= system.l_ref
    d[1::3] /= system.l_ref
    return bool(np.max(np.abs(d)) <= 1e-9)


def _law_out_of_reach(system: System, sched: Schedule, exc: AssemblyError) -> AssemblyError:
    """``exc`` with the law's range and the linkage's reachable range of the driver coordinate
    added (from a constant-speed sweep of the first driver from the law's start)."""
    law, d = sched.law, system.motion_drivers[0]
    psi = law.value(0.0, np.linspace(0.0, law.duration, 4097))[0]
    text = (
        f"{exc.args[0]}; following the {law.kind} law of {d.name} in time, the linkage "
        f"assembles up to t = {getattr(exc, 't_reached', float('nan')):.6g} s; the law spans "
        f"{_coordinate_range(d, psi.min(), psi.max())}"
    )
    if len(system.motion_drivers) == 1:
        sweep = Schedule(np.array([law.start]), np.array([1.0]))
        span = 2 * np.pi if d.joint.angular else 2 * float(np.ptp(psi)) + system.l_ref
        try:
            lo, hi = reachable_range(system, sweep, span)
        except AssemblyError:
            lo = hi = None
        if lo is not None:
            exc.reachable = (law.start + lo, law.start + hi)
            text += f", the linkage reaches only {_coordinate_range(d, *exc.reachable)}"
    exc.args = (text,)
    return exc


def _coordinate_range(d, a: float, b: float) -> str:
    if d.joint.angular:
        return f"{d.name} from {np.degrees(a):.4f}° to {np.degrees(b):.4f}°"
    return f"{d.name} from {a * 1e3:.6g} mm to {b * 1e3:.6g} mm"


def _range_text(system: System, sched: Schedule, lo: float, hi: float) -> str:
    a, b = sched(np.array([lo, hi]))[0][:, 0]
    d = system.motion_drivers[0]
    if d.joint.angular:
        return f"{d.name} from {np.degrees(a) % 360:.4f}° to {np.degrees(b) % 360:.4f}°"
    return f"{d.name} from {a * 1e3:.6g} mm to {b * 1e3:.6g} mm"
