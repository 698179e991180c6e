"""``analyze``: the pipeline from a model to a :class:`~kinetostatics.analysis.results.Result`.

Read :func:`analyze` top to bottom, one call per stage: schedule (:mod:`.schedule`) →
rows in time → positions, with the reachable range where the linkage cannot follow the
run (:mod:`.reachable`) → velocities/accelerations → load events and travel extremes
(:mod:`.conditions`) → event rows → loads, reactions, friction and power
(:mod:`.inverse`) → result columns (:mod:`.results`).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..base.arguments import real_array
from ..base.limits import MAGNITUDE, MAX_TRAVEL, MAX_TURNS
from ..base.memory import BYTES_PER_LINK_POSITION, BYTES_PER_POSITION, memory_shortfall
from ..errors import (
    AssemblyError,
    ElementWarning,
    JointWarning,
    Location,
    ModelError,
    NearSingularWarning,
    NonFiniteResultError,
    StructureError,
)
from ..kinematics.continuation import Singularity
from ..kinematics.differences import difference_derivatives
from ..kinematics.events import state_near
from ..kinematics.motion import Motion, motion_at
from ..kinematics.newton import condition_number, group_condition
from ..kinematics.positions import PositionSolution, positions_near, solve_positions
from ..kinematics.schedule import Schedule, sample_times, schedule
from ..kinematics.start import initial_guess
from ..kinetics.conditions import Event, load_events, travel_extremes, whole_motion
from ..kinetics.inverse import Kinetics, inverse_dynamics, kinetics
from ..kinetics.reactions import ground_reaction
from ..model import Model
from ..structure.system import System, jacobian, system_of
from .columns import build_columns, element_warnings, joint_warnings
from .reachable import Rows, solve_run
from .results import Result

__all__ = [
    "analyze",
    "kinetics",
    "Kinetics",
    "Motion",
    "Schedule",
    "Event",
    "numerical_mobility",
    "travel_extremes",
    "whole_motion",
]


def analyze(  # noqa: PLR0913  the public keywords of analyze (docs/python.md)
    model: Model | System,
    *,
    positions: np.ndarray | None = None,
    times: np.ndarray | None = None,
    friction: bool | None = None,
    events: bool | None = None,
    derivatives_by: str = "jacobian",
    step: float = np.radians(1.0),
    reachable: bool = False,
    kinematics_only: bool = False,
) -> Result:
    """Analyse the kinematics and kinetostatics over the positions of ``model.analysis``.

    Parameters
    ----------
    model : Model or System
        A loaded model (its system is built once and reused while the model is
        unchanged), or a system built from one with ``build_system``.
    positions : array, optional
        Driver coordinates (rad, or m for a prismatic driver) to analyse instead
        of ``analysis.positions``/``at`` (constant-speed drivers only).
    times : array, optional
        Times (s, from the start of the run) to analyse instead — for any
        motion law; a non-monotone law is followed in time.
    friction : bool, optional
        Solve the friction solutions (default: when the model has friction).
    events : bool, optional
        Add rows at the exact positions where loads switch (default
        ``analysis.events``).
    derivatives_by : {"jacobian", "forward", "central"}
        Velocities and accelerations from the constraint Jacobian (exact), or
        — as a comparison mode only — by the source text's forward difference
        quotients or by central differences with driver step ``step`` (rad or m).
    step : float
        The driver step of ``derivatives_by="central"`` (rad or m; default 1°).
    reachable : bool
        If the linkage cannot follow the whole sweep (a crank that cannot fully
        rotate), analyse ``analysis.positions`` positions spread over the
        reachable range between its limit positions instead of raising.
    kinematics_only : bool
        Positions, velocities and accelerations only: no loads, events,
        reactions, friction or power are computed (and no such columns exist).

    Returns
    -------
    Result
        Named arrays over the positions (CSV names and units), raw arrays
        ``q``, ``qd``, ``qdd``, ``lam``, the events and the structure.

    Raises
    ------
    ValueError
        ``positions`` or ``times`` not a non-empty 1-D list of finite real numbers
        in range (times from 0; limits in docs/errors.md), naming the entry.
    NonFiniteResultError
        A NaN or infinity in the results that neither self-locking nor a singular
        position explains (a model built in Python beyond the file limits).

    See Also
    --------
    load : Read the model from a file.
    Result.summary : The extremes of every column.

    Examples
    --------
    >>> import numpy as np
    >>> import kinetostatics as ks
    >>> model = ks.load("mechanisms/slider_crank.yaml")  # doctest: +SKIP
    >>> result = ks.analyze(model)  # doctest: +SKIP
    >>> result["motor.torque"].shape  # doctest: +SKIP
    (360,)
    >>> ks.analyze(model, positions=np.radians([0.0, 90.0]), friction=False)  # doctest: +SKIP
    <Result 'offset slider-crank': 2 positions, 81 columns, 14 members; checks ok>
    """
    system = model if isinstance(model, System) else system_of(model)
    _require_motion_drivers(system)
    sched = schedule(system)
    rows = _rows(system, sched, positions, times, reachable)
    t, sol, full = solve_run(system, sched, rows)
    motion = _motion(system, sched, t, sol.q, derivatives_by, step, not kinematics_only)
    if kinematics_only:
        return _result(system, sol, motion, full)
    extremes, found, states = load_events(system, sched, motion, full)
    if (system.model.analysis.events if events is None else events) and found:
        motion = _with_event_rows(system, sched, found, states, motion)
    kin = inverse_dynamics(
        system,
        motion,
        extremes=extremes,
        ref_speed=sched.reference,
        friction=system.model.has_friction if friction is None else friction,
    )
    return _result(system, sol, motion, full, kin, found)


def analyze_near(result: Result, times: np.ndarray, *, friction: bool) -> Result:
    """The pipeline at ``times`` inside the run of ``result``, each position continued from
    its nearest row (as :func:`~kinetostatics.kinematics.positions.state_at` does: the
    same branch, without the run's continuation from the start) and the loads with the run's
    travel extremes: the rows on which the cycle's integrator locates a kink
    (analysis/cycle.py).  No event rows.  Raises AssemblyError where a position would
    not be on its row's branch (:func:`~kinetostatics.kinematics.positions.positions_near`):
    the callers then analyse the times along the whole run."""

    system = result.system
    sched = schedule(system)
    t = np.asarray(times, dtype=float)
    rows = np.asarray(result.t, dtype=float)
    gap = np.abs(rows[None, :] - t[:, None])
    tol = 1e-9 * max(float(np.ptp(rows)), 1e-300)
    moving = [s.t for s in result.singular if s.group != "equilibrium"]  # kinematic ones
    for ts in moving:  # not from a row a singular position separates from the time, nor
        # from one on it: the branch may change there (a change point, where a
        # parallelogram's two branches meet)
        rs, ds = rows[None, :] - ts, t[:, None] - ts
        gap[(rs * ds < 0) | (np.abs(rs) <= tol)] = np.inf
    if not np.all(np.isfinite(gap.min(axis=1))):
        raise AssemblyError(
            "the run", "a time between singular positions", "no row to continue from"
        )
    n = np.argmin(gap, axis=1)
    h = (t - rows[n])[:, None]  # Taylor from the nearest row, then Newton (state_at)
    guess = result.q[n] + h * result.qd[n] + 0.5 * h * h * result.qdd[n]
    q = positions_near(
        system, sched(t)[0], guess, sched, reference=result.q[n], changes=bool(moving)
    )
    motion = motion_at(system, sched, t, q)
    kin = inverse_dynamics(
        system, motion, extremes=result.extremes, ref_speed=sched.reference, friction=friction
    )
    n = len(t)
    sol = PositionSolution(motion.q, np.zeros((n, 0)), np.zeros(n, dtype=int))
    with warnings.catch_warnings():  # the run warned about its own rows
        warnings.simplefilter("ignore")
        return _result(system, sol, motion, False, kin)


def with_friction(result: Result) -> Result:
    """:func:`analyze` of the rows of ``result`` (an ``analyze`` at ``times`` without event
    rows and without the friction solutions) again with them, on the same motion: the
    positions are not solved again (the cycle's quadrature nodes, analysed frictionless
    to place the pieces, then with friction at the same times: analysis/cycle.py)."""
    system = result.system
    sched = schedule(system)
    motion = motion_at(system, sched, result.t, result.q)
    kin = inverse_dynamics(
        system,
        motion,
        extremes=result.extremes or None,  # analyze's: the whole motion's travel extremes
        ref_speed=sched.reference,
        friction=True,
    )
    n = len(result.t)
    singular = [s for s in result.singular if s.group != "equilibrium"]  # _result adds them
    sol = PositionSolution(result.q, np.zeros((n, 0)), np.zeros(n, dtype=int), singular)
    return _result(system, sol, motion, result.full_cycle, kin, result.events)


# -- the stages -------------------------------------------------------------------------
def _require_motion_drivers(system: System) -> None:
    """StructureError unless the motion drivers are as many as the mobility (at least one)."""
    n_motion = len(system.motion_drivers)
    if n_motion != system.structure.mobility or n_motion == 0:
        effort = [d.name for d in system.model.drivers if d.effort is not None]
        if effort and n_motion < system.structure.mobility:
            message = (
                f"the file is effort-driven ({', '.join(effort)}: effort:, a given force or "
                f"torque, not a motion): its motion follows from the forces, so use "
                f"`kinetostatics simulate` (dynamics.simulate); run and analyze need as many "
                f"motion drivers as the mobility ({system.structure.mobility}), the file has "
                f"{n_motion}"
            )
        else:
            message = (
                f"analyze needs as many motion drivers as the mobility "
                f"({system.structure.mobility}); the file has {n_motion}"
            )
        raise StructureError([(Location(system.model.source, path="drivers"), message)])


def _rows(system: System, sched: Schedule, positions, times, reachable: bool) -> Rows:
    """The rows asked for (``analysis.positions`` and ``at``, or ``positions=``/``times=``,
    checked): their times, which of them were given as driver coordinates, and whether
    they cover a full cycle."""
    if times is not None and positions is not None:
        raise ValueError("give positions (driver coordinates) or times, not both")
    if positions is not None:
        positions = _checked_positions(system, positions)
    if times is not None:
        t, full = _checked_times(system, sched, times), False
    else:
        t, full = sample_times(system, sched, positions)
    given_as = "positions" if positions is not None else ("times" if times is not None else None)
    _check_memory(system, len(t), given_as)
    # rows given as driver coordinates (positions=, `at`), placed a turn ahead by sample_times
    given = np.zeros(len(t), dtype=bool)
    if positions is not None:
        given[:] = True
    elif times is None and system.model.analysis.at:
        given[len(t) - len(system.model.analysis.at) :] = True
        order = np.argsort(t, kind="stable")  # `at` rows take their place in the run
        t, given = t[order], given[order]
    return Rows(t, given, full, given_as, reachable)


ALWAYS_FITS = 8 * 2**20  # bytes: rows that need less are not checked (1,024 positions)


def _check_memory(system: System, n: int, given: str | None) -> None:
    """Refuse ``n`` rows, before any is analysed, when they would need more memory
    than is available (:func:`~kinetostatics.base.memory.memory_shortfall`, the
    estimate of a batch's): a ModelError naming ``analysis.positions``, or a
    ValueError naming the ``positions``/``times`` argument.  Rows that need less than
    :data:`ALWAYS_FITS` are not checked: reading the memory available (``/proc/meminfo``
    and the cgroup's files) costs ~50 µs, ~2 % of an analysis at 360 positions, and a
    process with less than that free could not have imported NumPy."""
    links = len(system.links)
    if n * max(BYTES_PER_POSITION, links * BYTES_PER_LINK_POSITION) <= ALWAYS_FITS:
        return
    if (why := memory_shortfall(n, "the analysis", links)) is None:
        return
    if given is None:
        where = Location(system.model.source, path="analysis.positions")
        raise ModelError([(where, f"{why}; analyse fewer positions")])
    raise ValueError(f"{given}: {why}")


def _motion(system: System, sched: Schedule, t, q, by: str, step: float, factors: bool) -> Motion:
    """The :class:`~kinetostatics.kinematics.motion.Motion` of the rows: the drivers'
    coordinates and the velocities and accelerations, from the constraint Jacobian (``lu``:
    its factors, kept only if ``factors``) or by differences (no factors: the reactions
    build their own)."""
    if by == "jacobian":
        return motion_at(system, sched, t, q, factors)
    psi, psi_d, psi_dd = sched(t)
    qd, qdd = difference_derivatives(system, sched, t, q, by, step)
    return Motion(t, psi, q, qd, qdd, psi_d, psi_dd, None)


def _with_event_rows(system: System, sched: Schedule, found, states, motion: Motion) -> Motion:
    """``motion`` with a row added at each load switch ``found`` (its state from
    :func:`~kinetostatics.kinetics.conditions.load_events`, or continued from the nearest row),
    sorted by time; without the kinematic factors (the equilibrium is assembled anew)."""
    t, q, qd, qdd = motion.times, motion.q, motion.qd, motion.qdd
    te = np.array([e.t for e in found])
    qe, qde, qdde = zip(
        *(
            tuple(x[None] for x in st)
            if st is not None
            else state_near(system, sched, e.t, t, q, qd, qdd)
            for e, st in zip(found, states)
        )
    )
    t = np.concatenate((t, te))
    q, qd, qdd = (
        np.concatenate((a, np.concatenate(b))) for a, b in ((q, qe), (qd, qde), (qdd, qdde))
    )
    order = np.argsort(t, kind="stable")
    t = t[order]
    psi, psi_d, psi_dd = sched(t)
    return Motion(t, psi, q[order], qd[order], qdd[order], psi_d, psi_dd, None)


def _result(system: System, sol, motion: Motion, full, kin=None, found=()) -> Result:
    """The :class:`~kinetostatics.analysis.results.Result` of the rows (kinematics only if
    no ``kin``; ``found`` the load switches): group conditions (warned about near a
    singular position), the singular positions of the equilibrium, the guard against
    unexplained NaN, the columns."""
    t, psi, q, qd, qdd, lu = motion.times, motion.psi, motion.q, motion.qd, motion.qdd, motion.lu
    if kin is not None:
        sol.singular.extend(
            Singularity("equilibrium", float(t[k]), float(psi[k, 0]), float(kin.condition[k]))
            for k in np.nonzero(kin.singular)[0]
        )
    cond = _conditions(system, q, lu)
    _warn_near_singular(system, cond, psi[..., 0])
    if kin is not None and q.ndim == 2:
        for message in joint_warnings(system, q, kin.x0):
            warnings.warn(message, JointWarning, stacklevel=3)  # the caller of analyze
    if q.ndim == 2:
        for message in element_warnings(system, q, psi[..., 0]):
            warnings.warn(message, ElementWarning, stacklevel=3)
    # the shaking force is computed when its columns are first read (lazy, as every column)
    shaking = None if kin is None else (lambda: ground_reaction(system, q, kin.x0))
    _check_finite(system, motion, kin, cond, sol.singular)
    columns, units = build_columns(system, motion, kin, cond=cond, shaking=shaking)
    return Result(
        system=system,
        t=t,
        coordinate=psi[..., 0],
        q=q,
        qd=qd,
        qdd=qdd,
        lam=np.zeros(q.shape[:-1] + (0,)) if kin is None else kin.x0,
        columns=columns,
        units=units,
        events=tuple(found),
        singular=tuple(sol.singular),
        indeterminate=False if kin is None else kin.indeterminate,
        full_cycle=full,
        extremes={} if kin is None or kin.extremes is None else kin.extremes,
        lam_friction=None if kin is None or kin.friction is None else kin.friction.solution.x,
    )


def _checked_positions(system: System, positions) -> np.ndarray:
    """``analyze(positions=...)``: finite driver coordinates within the file's limits (a revolute's
    |ψ| as an angle of the file, a prismatic's distance from ``analysis.start`` as its sweep)."""

    if system.motion_drivers[0].joint.angular:
        limit = MAGNITUDE["angle"][1]
        return real_array(
            "positions",
            positions,
            low=-limit,
            high=limit,
            why="rad; larger angles have lost their precision",
        )
    start, reach = system.model.analysis.start, MAX_TRAVEL * float(np.max(system.l_ref))
    return real_array(
        "positions",
        positions,
        low=start - reach,
        high=start + reach,
        why=f"m: at most {MAX_TRAVEL} times the largest link from analysis.start",
    )


def _checked_times(system: System, sched: Schedule, times) -> np.ndarray:
    """``analyze(times=...)``: finite times up to the time of the longest run a file may ask
    for (:data:`~kinetostatics.yaml_io.MAX_TURNS` periods of a law or turns of a crank,
    :data:`~kinetostatics.yaml_io.MAX_TRAVEL` times the largest link of a slider).  A motion
    law is not defined before its start: its times count from 0.  A constant-speed driver is:
    a negative time is a position before the start, reached by running the linkage backwards
    (as far back as forwards)."""

    if sched.law is not None:
        high, why = MAX_TURNS * sched.law.duration, f"s: {MAX_TURNS} times the law's duration"
    elif system.motion_drivers[0].joint.angular:
        high = MAX_TURNS * 2 * np.pi / sched.reference
        why = f"s: {MAX_TURNS} turns of the driver"
    else:
        high = MAX_TRAVEL * float(np.max(system.l_ref)) / sched.reference
        why = f"s: a travel of {MAX_TRAVEL} times the largest link"
    if sched.law is not None:
        return real_array(
            "times",
            times,
            low=0.0,
            high=high,
            why=why + "; a motion law's times count from its start, t = 0",
        )
    return real_array(
        "times",
        times,
        low=-high,
        high=high,
        why=why + " either side of the start of the run, t = 0",
    )


NONFINITE_COND = 1e15
"""A row whose group condition number is above this (or infinite) is at a singular
position: non-finite velocities or reactions there are explained, not a defect."""


def _check_finite(
    system: System, motion: Motion, kin: Kinetics | None, cond: dict, singular
) -> None:
    """The last guard of :func:`analyze`: a NaN or infinity that no status explains raises
    :class:`~kinetostatics.errors.NonFiniteResultError` naming the column and the row.

    Explained are the consistent friction solution where it self-locks
    (``friction.status`` 2: its columns are empty there) and every value at a
    singular position (a reported one, or a group condition number above
    :data:`NONFINITE_COND`).  Nothing else may be non-finite: the file's limits
    (``yaml_io.MAGNITUDE``) keep the products of a model far from overflow, so a
    NaN here comes from a model built in Python with values beyond them.
    """
    t, psi = motion.times, motion.psi
    x0, fric, power = (None, None, None) if kin is None else (kin.x0, kin.friction, kin.power)
    values = [motion.q, motion.qd, motion.qdd, x0, *(power or {}).values()]
    if fric is not None:
        values += [fric.solution.x, fric.solution.e, fric.x_approx]
    if math.isfinite(sum(float(np.add.reduce(v, axis=None)) for v in values if v is not None)):
        return  # the common case: nothing to explain (a sum of finite numbers that overflows
        # is looked at below, and passes)
    n = len(t)
    excused = np.zeros(n, dtype=bool)
    for c in cond.values():
        c = np.asarray(c, dtype=float).reshape(-1)
        if c.size == n:
            excused |= ~(c <= NONFINITE_COND)
    for sp in singular:
        excused |= np.isclose(t, sp.t, rtol=0.0, atol=1e-9 * max(1.0, abs(sp.t)))
    locked = excused.copy()
    if fric is not None:
        locked |= np.asarray(fric.solution.status).reshape(-1) == 2
    for arr, labels, ok in _labelled(system, motion, kin, excused, locked):
        arr = np.asarray(arr, dtype=float)
        if arr.ndim != 2 or arr.shape[0] != n:
            continue  # stacked variants: not checked here
        bad = ~np.isfinite(arr) & ~ok[:, None]
        if bad.any():
            row, col = (int(i) for i in np.argwhere(bad)[0])
            label = labels[col] if col < len(labels) else f"column {col}"
            d = system.motion_drivers[0]
            where = (
                f"{d.name} = {np.degrees(psi[row, 0]) % 360:.6g}°"
                if d.joint.angular
                else f"{d.name} = {psi[row, 0] * 1e3:.6g} mm"
            )
            raise NonFiniteResultError(
                label,
                row,
                f"the analysis gave {arr[row, col]} in {label} at row {row} ({where}, t = "
                f"{t[row]:.6g} s), with no self-locking or singular position to explain it: "
                "the model's numbers overflow (masses, "
                "lengths, loads or gravity too large or too small; see the input limits in "
                "docs/errors.md)",
            )


def _labelled(system: System, motion: Motion, kin: Kinetics | None, excused, locked) -> list:
    """The arrays :func:`_check_finite` checks, in order, each with its columns' labels
    and the rows where a non-finite value is explained (``excused``: singular; ``locked``:
    also self-locked, for what the friction solution gives)."""
    names = [f"{name}.{label}" for name in system.links for label in ("x", "y", "theta")]
    rate = {"x": "vx", "y": "vy", "theta": "omega"}
    acc = {"x": "ax", "y": "ay", "theta": "alpha"}
    arrays = [
        (motion.q, names, excused),
        (
            motion.qd,
            [n.rsplit(".", 1)[0] + "." + rate[n.rsplit(".", 1)[1]] for n in names],
            excused,
        ),
        (
            motion.qdd,
            [n.rsplit(".", 1)[0] + "." + acc[n.rsplit(".", 1)[1]] for n in names],
            excused,
        ),
    ]
    if kin is None:
        return arrays
    x0, fric = kin.x0, kin.friction
    n_j = system.n_joint_rows
    labels = [""] * x0.shape[-1]
    for k, j in enumerate(system.model.joints):
        for r in range(x0.shape[-1])[system.rows_of(k)]:
            labels[r] = (
                f"the reaction of joint {j.name} "
                f"({', '.join(f'{j.name}.{x}' for x in j.reaction_labels)})"
            )
    for d_index, d in enumerate(system.motion_drivers):
        effort_joint = system.model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
        labels[n_j + d_index] = f"{d.name}.{'torque' if effort_joint.angular else 'force'}"
    arrays.append((x0, labels, excused))
    if fric is not None:
        sol = fric.solution
        arrays.append((sol.x, [f"{x} (with friction)" for x in labels], locked))
        arrays.append(
            (sol.e, [f"{system.model.joints[k].name}.friction" for k in fric.setup.joints], locked)
        )
        arrays.append((fric.x_approx, [f"{x} (approximate friction)" for x in labels], excused))
    for key, value in kin.power.items():
        late = key in ("friction", "input_friction", "residual_friction")
        arrays.append((np.asarray(value)[..., None], [f"power.{key}"], locked if late else excused))
    return arrays


COND_WARN = 1e8
"""A group condition number above this is warned about: relative errors of
positions there can reach ~1e-16 × condition, and reactions grow like it."""


def _warn_near_singular(system: System, cond: dict, coord: np.ndarray) -> None:
    for group, c in cond.items():
        bad = np.nonzero(c > COND_WARN)[0]
        if bad.size:
            k = bad[np.argmax(c[bad])]
            name = system.motion_drivers[0].name
            where = (
                f"{np.degrees(coord[k]) % 360:.4g}°"
                if system.motion_drivers[0].joint.angular
                else f"{coord[k] * 1e3:.6g} mm"
            )
            warnings.warn(
                f"{group.label} is nearly singular at {bad.size} position(s), worst at "
                f"{name} = {where} (condition {c[k]:.3g} > {COND_WARN:.0e}); "
                "reactions there are unreliable",
                NearSingularWarning,
                stacklevel=4,  # the caller of analyze (through _result)
            )


def _conditions(system: System, q: np.ndarray, lu) -> dict:
    if lu is not None and lu.conditions is not None:  # computed with the factors (fused)
        return {system.plans[g].group: c for g, c in lu.conditions.items()}
    return {
        p.group: (
            condition_number(system, p, lu.diag[g], lu.inv[g])
            if lu is not None
            else group_condition(system, q, p)
        )
        for g, p in enumerate(system.plans)
        if p.group.kind != "driven"
    }


def numerical_mobility(system: System) -> int:
    """n_q − rank Φ_q (joints only) at the first assembled position; warns if it
    differs from Grübler–Kutzbach (an overconstrained or special linkage)."""
    n_j = len(system.model.joints)
    q = initial_guess(system)
    if system.motion_drivers and len(system.motion_drivers) == system.structure.mobility:
        sched = schedule(system)
        q = solve_positions(system, np.array([0.0]), sched).q[0]
    jac = jacobian(system, q, range(n_j))
    s = np.linalg.svd(jac, compute_uv=False)
    rank = int(np.sum(s > 1e-9 * max(s.max(initial=0.0), 1.0)))
    n = system.n_q - rank
    if n != system.structure.mobility:
        warnings.warn(
            f"numerical mobility {n} differs from Grübler–Kutzbach "
            f"{system.structure.mobility}: the linkage is overconstrained or special",
            stacklevel=2,
        )
    return n
