"""The units in force and the magnitudes that suggest a forgotten ``units:``.

A file without ``units:`` is read in SI: a crank written ``80`` meaning millimetres is
80 m long, and the analysis runs without complaint to a peak torque of 10⁸ N·m.
``kinetostatics check`` and ``run`` print the units in force (:func:`units_line`), a
one-line note when the file has no ``units:`` (:func:`units_note`), and a warning per
implausible magnitude naming its key (:func:`magnitude_warnings`): a link longer than
:data:`MAX_LINK` m, a driver speed above :data:`MAX_RPM` rpm, a torque above
:data:`MAX_TORQUE` N·m, and what the reading noted (``Model.notes``: a friction
coefficient above 1, its key and line).  Warnings only: a large machine is allowed.
"""

from __future__ import annotations

import numpy as np

from ..model import EffortLaw, Model

__all__ = [
    "MAX_LINK",
    "MAX_RPM",
    "MAX_TORQUE",
    "units_line",
    "units_note",
    "magnitude_warnings",
    "torque_warning",
]

MAX_LINK = 10.0  # m
MAX_RPM = 1e4  # rpm
MAX_TORQUE = 1e6  # N·m

_SI = {
    "length": "m",
    "angle": "rad",
    "speed": "rad/s or m/s",
    "time": "s",
    "mass": "kg",
    "force": "N",
    "torque": "N*m",
    "inertia": "kg*m^2",
}


def units_line(model: Model) -> str:
    """``units: length mm, angle deg, ...`` — every kind, as written or its SI default."""
    written = dict(model.units or {})
    parts = [f"{kind} {written.get(kind, si)}" for kind, si in _SI.items()]
    return "units: " + ", ".join(parts) + ("" if written else " (SI)")


def units_note(model: Model) -> str | None:
    """A one-line note when the file has no ``units:`` key (everything read in SI)."""
    if model.units:
        return None
    return (
        "note: the file has no units: key, so every number is read in SI (lengths in m, "
        "angles in rad, speeds in rad/s); add e.g. units: {length: mm, angle: deg, "
        "speed: rpm} if it is written in mm, degrees and rpm"
    )


def _where(model: Model, where, path: str) -> str:
    text = str(where) if where is not None and getattr(where, "path", "") else ""
    return text or f"{model.source}: {path}"


def magnitude_warnings(model: Model) -> list[str]:
    """One line per implausible magnitude of the file, naming the key: what the reading
    noted (a friction coefficient above 1), then the sizes, speeds and torques."""
    out = list(model.notes)
    hint = " (is units: missing or wrong?)"
    for link in model.links:
        pts = np.array(list(link.points.values()), dtype=float).reshape(-1, 2)
        if len(pts) >= 2:
            size = float(np.max(np.linalg.norm(pts[:, None] - pts[None], axis=-1)))
        elif len(pts) == 1 and link.ground:
            size = float(np.linalg.norm(pts[0]))
        else:
            size = 0.0
        if size > MAX_LINK:
            where = _where(model, link.where, f"links.{link.name}")
            out.append(
                f"{where}: link '{link.name}' is {size:.4g} m long (its points span more than "
                f"{MAX_LINK:g} m){hint}"
            )
    for d in model.drivers:
        where = _where(model, d.where, f"drivers.{d.name}")
        if d.motion is not None and not d.motion.own_run and np.ndim(d.motion.speed) == 0:
            rpm = abs(float(d.motion.speed)) * 30.0 / np.pi
            if rpm > MAX_RPM and _angular(model, d.joint):
                out.append(
                    f"{where}: driver '{d.name}' turns at {rpm:.4g} rpm (more than "
                    f"{MAX_RPM:g} rpm){hint}"
                )
        if d.effort is not None and not isinstance(d.effort, EffortLaw):
            value = float(np.max(np.abs(d.effort)))
            if value > MAX_TORQUE and _angular(model, d.joint):
                out.append(f"{where}: effort of {value:.4g} N*m (more than {MAX_TORQUE:g}){hint}")
    for load in model.loads:
        if "torque" not in load.kind:
            continue
        value = float(np.max(np.abs(load.value))) if load.table is None else 0.0
        if load.table is not None:
            value = float(np.max(np.abs(load.table[1])))
        if value > MAX_TORQUE:
            where = _where(model, load.where, f"loads.{load.name}")
            out.append(
                f"{where}: torque load '{load.name}' of {value:.4g} N*m (more than "
                f"{MAX_TORQUE:g} N*m){hint}"
            )
    return out


def torque_warning(model: Model, driver: str, peak: float, unit: str) -> str | None:
    """A warning when a run's peak driving torque is implausible, naming the driver."""
    if unit != "N*m" or not np.isfinite(peak) or peak <= MAX_TORQUE:
        return None
    d = next((d for d in model.drivers if d.name == driver), None)
    where = _where(model, d.where if d else None, f"drivers.{driver}")
    return (
        f"{where}: the peak driving torque of '{driver}' is {peak:.4g} N*m (more than "
        f"{MAX_TORQUE:g} N*m): check units: (length, mass, force) and the link dimensions"
    )


def _angular(model: Model, joint: str) -> bool:
    return bool(model.joint(joint).angular)
