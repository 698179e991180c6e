"""Self-checks of a result: does it satisfy what it claims to?

Each :class:`~kinetostatics.analysis.results.Result` carries ``result.checks`` (a
:class:`Checks`, computed on first use from the result's own arrays):

- ``constraints``: the largest |Φ(q, t)| over the rows and constraint
  equations (joints and motion drivers), divided by L_ref — Newton's stopping
  measure; tolerance :data:`CONSTRAINT_TOL`;
- ``power`` and ``power_friction``: the largest |power.residual| (frictionless)
  and |power.residual_friction| (consistent friction solution, rows where it
  exists) over the rows, divided by the largest |power.input| (or, where no
  power is put in, by the largest |power| term); rows at a reported singular
  position (no finite effort there) are left out; tolerance :data:`POWER_TOL`;
- ``sketch``: the largest distance between a sketched point and where the start
  pose put it, and which point; tolerance ``SKETCH_TOL``·L_ref (the start
  refuses a larger one, see docs/yaml.md);
- ``cond``: the largest condition number of an Assur group over the rows, which
  group and where; tolerance :data:`COND_TOL` (the near-singular warning's);
- ``closure``: a full cycle of one constant-speed revolute driver must end where it
  began: its last row carried on (by the same continuation as the rows) to one period
  after its first, compared with its first pose (lengths over L_ref, angles modulo a
  turn, in rad); tolerance :data:`CLOSURE_TOL`.  A linkage whose branch, followed once
  round, does not come back (it changed branch, or its motion takes more than one turn)
  has no one-turn cycle: its cycle means, strokes and flywheel would be wrong;
- ``friction``: the rows per ``friction.status`` (0 converged, 1 by homotopy,
  2 self-locking, 3 a relative speed is zero); fails where a row self-locks
  (its friction values are empty).  It also counts the other rows whose
  ``<driver>.efficiency`` is undefined (empty: the drive delivers no power there, or
  passes none on; docs/friction.md), ``efficiency_undefined`` in summary.json; they do
  not fail it.

A check that does not apply (no power columns in a kinematics-only result, no
friction, no sketch) is ``None`` and passes.  Documented in docs/theory.md
("Self-checks").
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from ..base.units import factor
from ..errors import KinetostaticsError
from ..kinematics.continuation import COARSE_STEP, continue_path
from ..kinematics.newton import group_condition, group_signature
from ..kinematics.schedule import schedule
from ..kinematics.start import SKETCH_TOL, sketch_distances, start_pose
from ..structure.system import phi

__all__ = [
    "Check",
    "Checks",
    "result_checks",
    "start_checks",
    "CONSTRAINT_TOL",
    "POWER_TOL",
    "COND_TOL",
    "CLOSURE_TOL",
]

CONSTRAINT_TOL = 1e-9  # max|Φ| / L_ref (Newton stops at 1e-12)
POWER_TOL = 1e-8  # max|power residual| / max|power.input|
COND_TOL = 1e8  # group condition number (analysis.COND_WARN)
CLOSURE_TOL = 1e-7  # the pose one period on from the first row against it (L_ref, rad)
STATUS_WORDS = ("ok", "homotopy", "self-locking", "zero-speed")


@dataclass(frozen=True)
class Check:
    """One self-check: the measured ``value`` against ``tolerance``; ``where`` says
    where the worst value is; ``text`` is its part of the one-line rendering."""

    name: str
    value: float
    tolerance: float
    where: str = ""
    text: str = ""
    detail: tuple = ()  # further (key, value) pairs for summary.json

    @property
    def ok(self) -> bool:
        return bool(self.value <= self.tolerance)  # NaN fails

    def to_dict(self) -> dict[str, Any]:
        value = float(self.value)
        return {
            "value": value if np.isfinite(value) else None,
            "tolerance": self.tolerance,
            "ok": self.ok,
            "where": self.where,
            **dict(self.detail),
        }


@dataclass(frozen=True)
class Checks:
    """The self-checks of a result (``None``: does not apply)."""

    constraints: Check | None = None
    power: Check | None = None
    power_friction: Check | None = None
    sketch: Check | None = None
    cond: Check | None = None
    closure: Check | None = None
    friction: Check | None = None
    friction_status: tuple[int, int, int, int] | None = None  # rows with status 0, 1, 2, 3

    def __iter__(self):
        for f in fields(self):
            c = getattr(self, f.name)
            if isinstance(c, Check):
                yield c

    @property
    def ok(self) -> bool:
        return all(c.ok for c in self)

    def failed(self) -> list[Check]:
        """The checks that fail."""
        return [c for c in self if not c.ok]

    def line(self) -> str:
        """``checks: constraints 3e-16 · power 2e-14 · ... `` (one line)."""
        return "checks: " + " · ".join(c.text for c in self)

    def warning(self) -> str:
        """One line naming the failed checks, or ``""``."""
        bad = self.failed()
        if not bad:
            return ""
        return "self-check failed: " + "; ".join(
            f"{c.name} {c.value:.3g} > {c.tolerance:.3g}" + (f" ({c.where})" if c.where else "")
            for c in bad
        )

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"ok": self.ok, "failed": [c.name for c in self.failed()]}
        for c in self:
            out[c.name] = c.to_dict()
        if self.friction_status is not None:
            out["friction"]["status"] = dict(zip(("0", "1", "2", "3"), self.friction_status))
        return out


def _row_text(result, k: int) -> str:
    if "angle" in result.columns:
        return f"angle {float(result['angle'][k]):.4g}°"
    if "stroke" in result.columns:
        return f"stroke {float(result['stroke'][k]) * 1e3:.6g} mm"
    return f"row {k}"


def _length(system, metres: float) -> str:

    unit = system.model.units.get("length", "m")
    return f"{metres / factor('length', unit):.3g} {unit}"


def _constraints(system, q, psi) -> tuple[float, int]:

    n_j = len(system.model.joints)
    which = range(len(system.constraints)) if psi is not None else range(n_j)
    if psi is None:
        psi = np.zeros(q.shape[:-1] + (0,))
    r = np.max(np.abs(phi(system, q, psi, which)), axis=-1, initial=0.0) / np.max(system.l_ref)
    r = np.where(np.isfinite(r), r, np.inf).reshape(-1)
    k = int(np.argmax(r)) if r.size else 0
    return (float(r[k]) if r.size else 0.0), k


def _constraint_check(value: float, where: str) -> Check:
    return Check("constraints", value, CONSTRAINT_TOL, where, f"constraints {value:.0e}")


def _sketch_check(system, q0) -> Check | None:

    points = sketch_distances(system, q0)
    if not points:
        return None
    worst = max(points, key=lambda sp: float(np.max(sp.distance)))
    d = float(np.max(worst.distance))
    l_ref = float(np.max(system.l_ref))
    where = system.model.sketch_where.get(worst.key)
    key = where.path.removeprefix("sketch.") if where is not None else worst.key
    return Check(
        "sketch",
        d / l_ref,
        SKETCH_TOL,
        f"{key}, placed by {worst.group}",
        f"sketch {_length(system, d)} ({key})",
        (("distance", d), ("point", key), ("group", worst.group)),
    )


def _cond_check(value: float, where: str, group: str) -> Check:
    return Check("cond", value, COND_TOL, where, f"cond ≤ {value:.2g}", (("group", group),))


def _start(system):

    sched = schedule(system)
    return sched, start_pose(system, sched)[0]


def result_checks(result) -> Checks:
    """The self-checks of ``result`` (see the module's docstring)."""

    system = result.system
    sched, q0 = _start(system)
    q = np.asarray(result.q)
    try:
        psi = sched(result.t)[0] if system.motion_drivers else None
    except (ValueError, IndexError):  # times not of this schedule: joints only
        psi = None
    value, k = _constraints(system, q, psi)
    checks: dict[str, Any] = {
        "constraints": _constraint_check(value, _row_text(result, k)),
        "sketch": _sketch_check(system, q0),
        **_power_checks(result),
    }
    cond = _worst_group_check(result)
    if cond is not None:
        checks["cond"] = cond
    checks["closure"] = _closure_check(result, sched, q)
    status = None
    if "friction.status" in result.columns:
        st = np.asarray(result.columns["friction.status"])
        status = tuple(int(np.sum(st == s)) for s in range(4))
        checks["friction"] = _friction_check(result, status)
    return Checks(**checks, friction_status=status)


def _power_reference(cols) -> float:
    """The scale of the power residuals: the largest input power, or with nothing put in
    the largest power term (1 W where every term is zero)."""
    ref = np.nanmax(np.abs(cols["power.input"]), initial=0.0)
    if ref == 0.0:  # nothing put in: the largest power term instead
        ref = max(
            (
                np.nanmax(np.abs(cols[f"power.{n}"]), initial=0.0)
                for n in ("kinetic", "potential", "elastic", "damping", "external", "friction")
                if f"power.{n}" in cols
            ),
            default=0.0,
        )
    return ref if ref > 0.0 else 1.0


def _power_checks(result) -> dict[str, Check]:
    """The power-balance checks (``power``, ``power_friction``) of the columns that exist,
    the reported singular rows (and the self-locked rows, for friction) left out."""
    cols = result.columns
    if "power.residual" not in cols:
        return {}
    ref = _power_reference(cols)
    t = np.asarray(result.t)
    singular = np.zeros(t.shape, dtype=bool)  # reported singular rows: no effort there
    for sp in result.singular:
        singular |= np.isclose(t, sp.t, rtol=0.0, atol=1e-9 * max(1.0, abs(sp.t)))
    out = {}
    for name, col in (("power", "power.residual"), ("power_friction", "power.residual_friction")):
        if col not in cols:
            continue
        r = np.where(singular, 0.0, np.abs(np.asarray(cols[col])))
        if name == "power_friction" and "friction.status" in cols:
            r = np.where(cols["friction.status"] == 2, 0.0, r)  # no solution there
        r = np.where(np.isnan(r), np.inf, r) / ref
        k = int(np.argmax(r)) if r.size else 0
        v = float(r[k]) if r.size else 0.0
        label = "power" if name == "power" else "power (friction)"
        out[name] = Check(name, v, POWER_TOL, _row_text(result, k), f"{label} {v:.0e}")
    return out


def _worst_group_check(result) -> Check | None:
    """The condition check of the worst-conditioned undriven group (None without one)."""
    cols = result.columns
    worst, where, group = 0.0, "", ""
    for p in result.system.plans:
        col = f"{p.group.column}.cond"
        if p.group.kind == "driven" or col not in cols:
            continue
        c = np.where(np.isnan(cols[col]), np.inf, cols[col])
        k = int(np.argmax(c))
        if c[k] >= worst:
            worst, where, group = (
                float(c[k]),
                f"{p.group.label}, {_row_text(result, k)}",
                p.group.label,
            )
    return _cond_check(worst, where, group) if where else None


def _friction_check(result, status: tuple[int, ...]) -> Check:
    """The friction check from the rows' solution ``status`` counts: the self-locked rows
    fail it; the rows whose efficiency is undefined are counted."""
    cols = result.columns
    st = np.asarray(cols["friction.status"])
    parts = [f"{n} {w}" for n, w in zip(status, STATUS_WORDS) if n]
    # rows whose <driver>.efficiency is undefined although the friction solution exists:
    # the drive delivers no power there or passes none on (docs/friction.md)
    undefined = np.zeros(st.shape, dtype=bool)
    for d in result.system.motion_drivers:
        if f"{d.name}.efficiency" in cols:
            undefined |= np.isnan(np.asarray(cols[f"{d.name}.efficiency"]))
    undefined &= st != 2
    n_undef = int(np.sum(undefined))
    if n_undef:
        parts.append(f"efficiency undefined at {n_undef}")
    return Check(
        "friction",
        float(status[2]),
        0.0,
        f"{status[2]} row(s) self-locking" if status[2] else "",
        "friction " + (", ".join(parts) or "no rows"),
        (("efficiency_undefined", n_undef),),
    )


def _closure_check(result, sched, q) -> Check | None:
    """The last row of a full cycle continued to one period after the first, against it."""
    system = result.system
    drivers = system.motion_drivers
    t = np.asarray(result.t)
    if (
        not result.full_cycle
        or len(drivers) != 1
        or not drivers[0].joint.angular
        or sched.law is not None
        or sched.acceleration is not None
        or t.size < 2
    ):
        return None
    first, last = int(np.argmin(t)), int(np.argmax(t))
    t_end = float(t[first]) + float(sched.period)
    sig = np.array([float(group_signature(system, q[last], p)) for p in system.plans])
    max_dt = COARSE_STEP / abs(float(sched.speed[0]))
    try:
        _, qs, _, _ = continue_path(system, q[last], sig, float(t[last]), t_end, sched, max_dt, [])
        gap = np.asarray(qs[-1]) - q[first]
    except KinetostaticsError:
        gap = np.full(q.shape[-1], np.inf)
    ang = np.arange(gap.size) % 3 == 2
    with np.errstate(invalid="ignore"):
        gap = np.where(ang, gap - 2 * np.pi * np.round(gap / (2 * np.pi)), gap)
        gap = np.abs(np.where(ang, gap, gap / np.max(system.l_ref)))
    k = int(np.argmax(np.where(np.isnan(gap), np.inf, gap)))
    value = float(gap[k]) if np.isfinite(gap[k]) else np.inf
    link = system.links[k // 3]
    where = f"link {link} one turn after {_row_text(result, first)}"
    return Check("closure", value, CLOSURE_TOL, where, f"closure {value:.0e}")


def start_checks(system) -> Checks:
    """The checks that apply at the start pose alone (``kinetostatics check``):
    constraints, sketch and the groups' condition numbers there."""
    sched, q0 = _start(system)
    value, _ = _constraints(system, q0, sched(np.zeros(1))[0][0])
    worst, where = 0.0, ""
    for p in system.plans:
        if p.group.kind == "driven":
            continue
        c = float(group_condition(system, q0, p))
        if not c < worst:
            worst, where = c, p.group.label
    return Checks(
        constraints=_constraint_check(value, "start pose"),
        sketch=_sketch_check(system, q0),
        cond=_cond_check(worst, where, where) if where else None,
    )
