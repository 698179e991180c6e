"""The cycle as a stage: the quantities of a result that solve again between its rows.

A :class:`~kinetostatics.analysis.results.Result` holds rows.  What summary.json says of
the whole cycle is computed by stages, each solving the mechanism again at times of its
own, and each returning a frozen record:

- the means, RMS and peaks of the driving efforts over the cycle
  (:func:`~kinetostatics.analysis.cycle.cycle_stats`: the pipeline at its quadrature
  nodes, the friction solutions there);
- the output strokes and time ratios (:func:`~kinetostatics.kinematics.events.output_strokes`:
  the limit positions located in time);
- the edges of the self-locked zones (:func:`~kinetostatics.analysis.locking.locking_zones`:
  the consistent friction solution between the rows);
- the flywheel design (:func:`~kinetostatics.dynamics.flywheel.design`) and the drive
  sizing (:func:`~kinetostatics.dynamics.drive.size`), when the file asks for them.

:func:`cycle_stage` runs those asked for and returns them as one :class:`Cycle`; the
caller passes it to :func:`~kinetostatics.analysis.summary.summarize` (or
``result.summary(cycle)``), which only formats.  The module sits in ``dynamics/``, the
lowest layer that sees every stage (the flywheel and the drive are dynamics); the callers
that want the cycle — ``run`` and ``report`` in ``cli/``, a batch row — sit above it.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from ..analysis.cuts import roundoff_floor
from ..analysis.cycle import Quadrature, cycle_quadrature, cycle_stats
from ..analysis.locking import locking_zones
from ..analysis.results import Result
from ..analysis.summary import driver_columns, summarize
from ..errors import NearSingularWarning, SingularEquilibriumWarning
from ..kinematics.continuation import coordinate_text
from ..kinematics.events import output_strokes
from ..kinematics.schedule import schedule
from .drive import DriveSizing, size
from .flywheel import FlywheelDesign, design

__all__ = [
    "Cycle",
    "cycle_efficiency",
    "cycle_stage",
    "driver_stats",
    "full_summary",
    "report_stage",
]


@dataclass(frozen=True)
class Cycle:
    """The cycle's records of one result; a part not asked for is None.

    Attributes
    ----------
    drivers : Mapping or None
        ``{column: {"mean", "rms", "peak", "covered"}}`` of the driving effort columns
        (:func:`driver_stats`).
    outputs : Mapping or None
        The output strokes and time ratios (summary.json ``outputs``).
    self_locking : tuple or None
        The self-locked zones, edges located (summary.json ``self_locking``).
    flywheel : FlywheelDesign or None
        The flywheel design, when the file has ``flywheel:`` (or one was given).
    drive : DriveSizing or None
        The drive sizing, when the file has ``drive:``.
    efficiency : Mapping or None
        ``{driver: cycle efficiency}``, the ratio of the mean input powers without and
        with friction (:func:`cycle_efficiency`; for the efficiency picture).
    """

    drivers: Mapping[str, Mapping[str, float]] | None = None
    outputs: Mapping[str, Any] | None = None
    self_locking: tuple[Mapping[str, Any], ...] | None = None
    flywheel: FlywheelDesign | None = None
    drive: DriveSizing | None = None
    efficiency: Mapping[str, float] | None = None


def _frozen(d: Mapping) -> Mapping:
    """A read-only view of a dict of dicts (a record's part)."""
    return MappingProxyType(
        {k: MappingProxyType(dict(v)) if isinstance(v, Mapping) else v for k, v in d.items()}
    )


def driver_stats(
    result: Result, nodes: Quadrature | None = None
) -> Mapping[str, Mapping[str, float]]:
    """The mean, RMS and peak over the cycle of each driving effort column.

    Parameters
    ----------
    result : Result
        The analysis.
    nodes : Quadrature, optional
        The cycle's quadrature already computed (:func:`cycle_stage` passes its own).

    Returns
    -------
    Mapping
        ``{column: {"mean", "rms", "peak", "covered"}}``
        (:func:`~kinetostatics.analysis.cycle.cycle_stats`); empty without a driving
        effort column or a row.
    """
    wanted = driver_columns(result)
    # over the cycle, integrated exactly between the load events (analysis/cycle.py)
    return _frozen(cycle_stats(result, wanted, given=nodes) if wanted and len(result) else {})


PEAK_BETWEEN = 2.0
"""A driving effort's largest |value| at the cycle's nodes beyond this many times its largest
at the rows: a peak the rows miss (:func:`between_rows`)."""


def between_rows(result: Result, quad: Quadrature) -> set[str]:
    """Warn where the cycle's quadrature nodes see what the analysed rows do not: a driving
    effort with no solution at some nodes while it has one at every row (a dead centre, or
    the friction self-locks, between the rows), or peaking at more than
    :data:`PEAK_BETWEEN` times its largest at the rows (a sharp peak beside a dead point).
    The summary's peaks are the rows' and its self-locked zones the rows' (issue 36, seed
    1007872: 7.1e6 N·m at the nodes, 9,021 at the rows, and a zone between two rows), so
    the warning names where to look: analyse more positions there.  Returns the columns
    warned of."""
    nodes = quad.nodes
    warned = set()
    sched = schedule(result.system)
    floor = 1e3 * roundoff_floor(result)  # an idle drive's round-off is no peak
    for col in driver_columns(result):
        if col not in nodes.columns:
            continue
        rows, v = np.asarray(result[col], dtype=float), np.asarray(nodes[col], dtype=float)
        unit = "N*m" if ".torque" in col else "N"
        where = lambda k: coordinate_text(result.system, sched(nodes.t[k : k + 1])[0][0])  # noqa: E731
        if np.isfinite(rows).all() and not np.isfinite(v).all():
            k = int(np.flatnonzero(~np.isfinite(v))[0])
            warnings.warn(
                f"{col}: no solution between the analysed rows (first at {where(k)}): no "
                "finite effort balances the loads there (a dead centre"
                + (", or the friction self-locks" if "_friction" in col else "")
                + "), which no row shows; its mean and RMS are over the part of the cycle "
                "where it exists; analyse more positions (analysis.positions) to see it",
                SingularEquilibriumWarning,
                stacklevel=2,
            )
            warned.add(col)
        top = np.max(np.abs(rows[np.isfinite(rows)]), initial=0.0)
        finite = np.where(np.isfinite(v), np.abs(v), 0.0)
        k = int(np.argmax(finite))
        if finite[k] > PEAK_BETWEEN * top and finite[k] > floor:
            warnings.warn(
                f"{col} reaches {finite[k]:.4g} {unit} between the analysed rows (at "
                f"{where(k)}), {finite[k] / top:.3g} times its largest at the rows "
                f"({top:.4g} {unit}, the summary's peak): a sharp peak the rows miss, near a "
                "dead point; analyse more positions (analysis.positions) to see it",
                NearSingularWarning,
                stacklevel=2,
            )
            warned.add(col)
    return warned


def cycle_efficiency(result: Result, nodes: Quadrature | None = None) -> Mapping[str, float]:
    """The cycle efficiency of each motion driver with friction: the mean driving effort
    without friction over the mean with the consistent friction solution, both over the
    part of the cycle where the one with friction exists.

    Parameters
    ----------
    result : Result
        The analysis (a full cycle; otherwise there is none).
    nodes : Quadrature, optional
        The cycle's quadrature already computed.

    Returns
    -------
    Mapping
        ``{driver: efficiency}``; a driver without friction columns, or whose mean with
        friction is 0, is absent.
    """
    out = {}
    if not result.full_cycle or "power.input" not in result.columns:
        return MappingProxyType(out)
    for d in result.system.motion_drivers:
        for word in ("torque", "force"):
            key0, key1 = f"{d.name}.{word}", f"{d.name}.{word}_friction"
            if key1 not in result.columns:
                continue
            stats = cycle_stats(
                result,
                {
                    "m0": lambda r, a=key0, b=key1: np.where(np.isfinite(r[b]), r[a], np.nan),
                    "m1": key1,
                },
                given=nodes,
            )
            m0, m1 = stats["m0"]["mean"], stats["m1"]["mean"]
            if m1 != 0:
                out[d.name] = m0 / m1
    return MappingProxyType(out)


def cycle_stage(
    result: Result,
    *,
    drivers: bool = True,
    outputs: bool = True,
    self_locking: bool = True,
    flywheel: bool | FlywheelDesign | None = None,
    drive: bool | None = None,
    efficiency: bool = False,
) -> Cycle:
    """The cycle's records of ``result``, those asked for.

    Parameters
    ----------
    result : Result
        The analysis.
    drivers, outputs, self_locking : bool
        Compute the driving efforts' cycle statistics, the output strokes, the locked
        zones' edges (default all).
    flywheel : bool or FlywheelDesign, optional
        Design the flywheel (default: when the file has ``flywheel:``); a design already
        made is carried as it is.
    drive : bool, optional
        Size the drive (default: when the file has ``drive:``); its flywheel check uses
        the flywheel design of the record.
    efficiency : bool
        Compute the cycle efficiency of the drivers with friction (default not: only the
        efficiency picture shows it).

    Returns
    -------
    Cycle
        The records; a part not asked for is None.
    """
    model = result.system.model
    fw = flywheel if isinstance(flywheel, FlywheelDesign) else None
    want_fw = fw is None and (flywheel or (flywheel is None and model.flywheel is not None))
    want_drive = drive or (drive is None and model.drive is not None)
    # the cycle's nodes once (with friction when the result has it: they serve the
    # frictionless integrals too), for the means, the flywheel, the drive and the efficiency
    nodes = None
    if driver_columns(result) and len(result) and (drivers or want_fw or want_drive or efficiency):
        nodes = cycle_quadrature(result)
    stats = driver_stats(result, nodes) if drivers else None
    if nodes is not None and drivers:
        between_rows(result, nodes)
    strokes = _frozen(output_strokes(result)) if outputs else None
    zones = tuple(_frozen(z) for z in locking_zones(result)) if self_locking else None
    if want_fw:
        fw = design(result, nodes=nodes)
    return Cycle(
        drivers=stats,
        outputs=strokes,
        self_locking=zones,
        flywheel=fw,
        drive=size(result, flywheel=fw, nodes=nodes) if want_drive else None,
        efficiency=cycle_efficiency(result, nodes) if efficiency else None,
    )


def report_stage(result: Result) -> Cycle:
    """The records of the course-design report: :func:`cycle_stage` with the cycle
    efficiency (the report's efficiency picture shows it) and the flywheel's energy curve
    (:meth:`~kinetostatics.dynamics.flywheel.FlywheelDesign.with_curve`: its pictures).

    Parameters
    ----------
    result : Result
        The report's analysis.

    Returns
    -------
    Cycle
        Every record the file asks for, and the efficiency.
    """
    cycle = cycle_stage(result, efficiency=True)
    if cycle.flywheel is None:
        return cycle
    return replace(cycle, flywheel=cycle.flywheel.with_curve())  # the chapter's pictures


def full_summary(result: Result) -> dict[str, Any]:
    """summary.json as ``kinetostatics run`` writes it: every stage the file asks for,
    then :func:`~kinetostatics.analysis.summary.summarize`.

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    dict
        The summary with the cycle's quantities.
    """
    return summarize(result, cycle_stage(result))
