"""methods.json: every graded method that applies to a result, at the positions asked for.

:func:`methods_stage` is what ``kinetostatics report`` passes to the report (as it passes
the cycle's stage): the report calls it on its own analysis with the course positions of
its detailed chapters, writes the dict to ``methods.json`` and formats the parts it has
chapters for.  A part is present only where its method applies: the balancing moment
(Joukowski's lever and the power method beside the solution's) and the free body and
force polygon of each Assur group for a result with efforts (and with friction, those of
the consistent solution with friction);
the instant centres and the vector equations at each position; the gears' geometry for a
file with toothed pairs;
the cam's design for a file with a cam (at the allowable pressure angle of the cam joint's
``design: {pressure_angle_max}``, else the textbook's 30°, unless the caller gives one).
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from typing import Any

from ..analysis.results import Result
from .cam_design import cam_design
from .centres import centres_at
from .gears import gear_geometry
from .lever import lever_stage
from .polygons import force_polygons
from .vectors import vector_equations

__all__ = ["methods_stage", "METHODS_VERSION", "PARTS"]

METHODS_VERSION = 1
"""The layout of methods.json (docs/methods.md); raised when a key changes meaning."""

PARTS = (
    "balancing_moment",
    "force_polygons",
    "instant_centres",
    "vector_equations",
    "gears",
    "cam_design",
)
"""The methods a caller may ask for (``force_polygons`` brings its friction twin)."""


def methods_stage(
    result: Result,
    rows: Sequence[tuple[str, int]],
    *,
    pressure_angle_max: float | None = None,
    parts: Collection[str] | None = None,
) -> dict[str, Any]:
    """The JSON-safe contents of methods.json.

    Parameters
    ----------
    result : Result
        The analysis (the report's: course positions and events included).
    rows : sequence of (str, int)
        The positions of the detailed chapters: ``(label, row)`` pairs, as
        ``outputs.plotting.course_positions(result)`` gives them.
    pressure_angle_max : float, optional
        The allowable pressure angle of the cam's design, in degrees, for every cam;
        default: each cam's ``design: {pressure_angle_max}`` in the file, else 30°.
    parts : collection of str, optional
        The methods to compute, of :data:`PARTS` (``plot`` asks for those it draws);
        default: all that apply.

    Returns
    -------
    dict
        ``{"version", "positions", "balancing_moment"?, "force_polygons"?,
        "force_polygons_friction"?, "instant_centres", "vector_equations",
        "gears"?, "cam_design"?}`` (docs/methods.md).
    """
    wanted = set(PARTS if parts is None else parts)
    if unknown := wanted - set(PARTS):
        raise ValueError(f"methods_stage: unknown parts {sorted(unknown)} (have {PARTS})")
    rows = [(str(label), int(k)) for label, k in rows]
    out: dict[str, Any] = {
        "version": METHODS_VERSION,
        "positions": [label for label, _ in rows],
    }
    system = result.system
    efforts = bool(system.motion_drivers) and result.lam.shape[-1] > system.n_joint_rows
    if efforts and "balancing_moment" in wanted:
        out["balancing_moment"] = lever_stage(result, rows).to_dict()
    if efforts and "force_polygons" in wanted:
        out["force_polygons"] = force_polygons(result, rows).to_dict()
        if result.lam_friction is not None:
            out["force_polygons_friction"] = force_polygons(result, rows, friction=True).to_dict()
    if "instant_centres" in wanted:
        out["instant_centres"] = {
            label: record.to_dict()
            for (label, _), record in zip(rows, centres_at(result, [k for _, k in rows]))
        }
    if "vector_equations" in wanted:
        out["vector_equations"] = {p.label: p.to_dict() for p in vector_equations(result, rows)}
    gears = gear_geometry(result) if "gears" in wanted else None
    if gears is not None and (gears.pairs or gears.incomplete):
        out["gears"] = gears.to_dict()
    cams = ()
    if "cam_design" in wanted:
        cams = cam_design(result, pressure_angle_max=pressure_angle_max)
    if cams:
        out["cam_design"] = {c.joint: c.to_dict() for c in cams}
    return out
