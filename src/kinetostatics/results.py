"""The result of an analysis: named arrays over the positions, and their export.

Column names and units are those of ``results.csv`` (SPEC.md).  Angles are
in rad inside the arrays ``q``, ``qd``, ``qdd``; the named columns follow the
CSV (``angle``, ``travel`` and ``<link>.theta`` in degrees).
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ._geometry import rotate
from .errors import did_you_mean
from .forces import point_state
from .system import System

__all__ = ["Result", "build_columns", "group_column"]


def group_column(group) -> str:
    """Column prefix of a group: its links joined by '_'."""
    return "_".join(group.links)


def _joint_position(system: System, q: np.ndarray, name: str) -> np.ndarray:
    j = system.model.joint(name)
    link = j.links[0]
    if link == system.model.ground.name:
        return np.broadcast_to(j.p_i, q.shape[:-1] + (2,))
    k = system.link_index(link)
    return point_state(q, q, None, k, j.p_i)[0]


def _dyad_angles(system: System, q: np.ndarray) -> dict[str, tuple[str, np.ndarray]]:
    """Transmission angle of RRR dyads and pressure angle of RRP dyads, deg."""
    out = {}
    joints = {j.name: j for j in system.model.joints}
    for plan in system.plans:
        g = plan.group
        if g.kind != "dyad" or g.letters not in ("RRR", "RRP"):
            continue
        a, b = g.links
        inner = [n for n in g.joints if set(joints[n].links) == {a, b}][0]
        ext_a = [n for n in g.joints if a in joints[n].links and n != inner][0]
        ext_b = [n for n in g.joints if b in joints[n].links and n != inner][0]
        pa, pm = _joint_position(system, q, ext_a), _joint_position(system, q, inner)
        u = pa - pm
        if g.letters == "RRR":
            v = _joint_position(system, q, ext_b) - pm
            cosang = np.sum(u * v, axis=-1) / (np.linalg.norm(u, axis=-1) * np.linalg.norm(v, axis=-1))
            out[group_column(g)] = ("transmission_angle", np.degrees(np.arccos(np.clip(cosang, -1, 1))))
        else:
            s = joints[ext_b]
            owner = s.links[0]
            th = 0.0 if owner == system.model.ground.name else q[..., 3 * system.link_index(owner) + 2]
            axis = rotate(th, s.u)
            c = np.abs(np.sum(u * axis, axis=-1)) / np.linalg.norm(u, axis=-1)
            out[group_column(g)] = ("pressure_angle", np.degrees(np.arccos(np.clip(c, -1, 1))))
    return out


def build_columns(system: System, t, psi, q, qd, qdd, x0, fric, power, cond, shaking, full):
    """Ordered columns and units (see SPEC.md, Outputs)."""
    model = system.model
    cols: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}

    def put(name, value, unit):
        cols[name] = np.asarray(value, dtype=float)
        units[name] = unit

    first = system.motion_drivers[0]
    angular = first.joint.angular
    coord = psi[..., 0]
    put("time", t - t[0] if len(t) else t, "s")
    if angular:
        put("angle", np.mod(np.degrees(coord), 360.0), "deg")
        put("travel", np.degrees(np.abs(coord - coord[0])), "deg")
    else:
        put("stroke", coord, "m")
        put("travel", np.abs(coord - coord[0]), "m")
    for k, name in enumerate(system.links):
        s = slice(3 * k, 3 * k + 3)
        for label, arr, unit in (("x", q[..., s][..., 0], "m"), ("y", q[..., s][..., 1], "m"),
                                 ("theta", np.degrees(q[..., s][..., 2]), "deg"),
                                 ("vx", qd[..., s][..., 0], "m/s"), ("vy", qd[..., s][..., 1], "m/s"),
                                 ("omega", qd[..., s][..., 2], "rad/s"),
                                 ("ax", qdd[..., s][..., 0], "m/s^2"), ("ay", qdd[..., s][..., 1], "m/s^2"),
                                 ("alpha", qdd[..., s][..., 2], "rad/s^2")):
            put(f"{name}.{label}", arr, unit)
    for k, name in enumerate(system.links):
        for pname, p in model.link(name).points.items():
            pos, vel, acc = point_state(q, qd, qdd, k, p)
            for label, arr, unit in (("x", pos[..., 0], "m"), ("y", pos[..., 1], "m"),
                                     ("vx", vel[..., 0], "m/s"), ("vy", vel[..., 1], "m/s"),
                                     ("ax", acc[..., 0], "m/s^2"), ("ay", acc[..., 1], "m/s^2")):
                put(f"{name}.{pname}.{label}", arr, unit)
    qe = np.concatenate((q, np.zeros(q.shape[:-1] + (3,))), axis=-1)
    sol = fric["solution"] if fric else None
    n_f = {k: n for n, k in enumerate(fric["setup"].joints)} if fric else {}
    for k, j in enumerate(model.joints):
        i_, j_ = system.ends[k]
        qi, qj = qe[..., 3 * i_:3 * i_ + 3], qe[..., 3 * j_:3 * j_ + 3]
        block = system.rows_of(k)
        reac = j.reaction(x0[..., block], qi, qj)
        force_unit = {"M": "N*m"}
        for label in j.reaction_labels:
            put(f"{j.name}.{label}", reac[label], force_unit.get(label, "N"))
        if fric:
            unit = "N*m" if j.angular else "N"
            if k in n_f:
                put(f"{j.name}.friction_approx", fric["e_approx"][..., n_f[k]], unit)
                put(f"{j.name}.friction", sol.e[..., n_f[k]], unit)
            reac_f = j.reaction(sol.x[..., block], qi, qj)
            if k in n_f:                          # a friction force along a slide is a force too
                for label, extra in j.effort_force(sol.e[..., n_f[k]], qi, qj).items():
                    reac_f[label] = reac_f[label] + extra
            for label in j.reaction_labels:
                put(f"{j.name}.{label}_friction", reac_f[label], force_unit.get(label, "N"))
    n_j = system.n_joint_rows
    for d_index, d in enumerate(system.motion_drivers):
        effort_joint = model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
        word, unit = ("torque", "N*m") if effort_joint.angular else ("force", "N")
        put(f"{d.name}.{word}", x0[..., n_j + d_index], unit)
        if fric:
            put(f"{d.name}.{word}_friction_approx", fric["x_approx"][..., n_j + d_index], unit)
            put(f"{d.name}.{word}_friction", sol.x[..., n_j + d_index], unit)
            with np.errstate(divide="ignore", invalid="ignore"):
                put(f"{d.name}.efficiency", x0[..., n_j + d_index] / sol.x[..., n_j + d_index], "1")
    if fric:
        put("friction.status", sol.status, "1")
        put("friction.iterations", sol.iterations, "1")
    for name in ("input", "kinetic", "potential", "external", "friction", "residual",
                 "residual_friction"):
        if name in power:
            put(f"power.{name}", power[name], "W")
    for g, c in cond.items():
        put(f"{group_column(g)}.cond", c, "1")
    for prefix, (label, arr) in _dyad_angles(system, q).items():
        put(f"{prefix}.{label}", arr, "deg")
    put("shaking.Fx", shaking[..., 0], "N")
    put("shaking.Fy", shaking[..., 1], "N")
    put("shaking.M", shaking[..., 2], "N*m")
    return cols, units


@dataclass(frozen=True)
class Result:
    """Named arrays over the positions, with the raw arrays for advanced use.

    ``result["rod.omega"]`` is a ``(n_pos,)`` array; ``result.columns`` the
    names in CSV order; ``result.units[name]`` the unit.  Raw: ``t`` (s),
    ``coordinate`` (rad or m), ``q``, ``qd``, ``qdd`` ``(n_pos, n_q)`` and
    ``lam`` ``(n_pos, n_lam)`` (frictionless multipliers and driver efforts).
    """

    system: System
    t: np.ndarray
    coordinate: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    lam: np.ndarray
    columns: dict[str, np.ndarray]
    units: dict[str, str]
    events: tuple = ()
    singular: tuple = ()
    indeterminate: bool = False
    full_cycle: bool = True
    extremes: dict = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f"no column '{name}'{did_you_mean(name, self.columns)}") from None

    def __len__(self) -> int:
        return len(self.t)

    @property
    def names(self) -> list[str]:
        return list(self.columns)

    def to_csv(self, path: str | Path) -> None:
        """Write ``results.csv``: a ``# units:`` line, the header, one row per position."""
        names = self.names
        with open(path, "w", newline="") as fh:
            fh.write("# units: " + ",".join(self.units[n] for n in names) + "\n")
            w = csv.writer(fh)
            w.writerow(names)
            data = np.column_stack([self.columns[n] for n in names])
            for row in data:
                w.writerow(["" if not np.isfinite(v) else repr(float(v)) for v in row])

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe: ``{"columns": {name: [..]}, "units": {...}}`` (NaN as None)."""
        return {"columns": {n: [None if not np.isfinite(v) else float(v) for v in a]
                            for n, a in self.columns.items()},
                "units": dict(self.units)}

    def summary(self) -> dict[str, Any]:
        """Extremes of every column and where they occur, events, singular positions."""
        from .summary import summarize
        return summarize(self)

    def to_json(self, path: str | Path) -> None:
        Path(path).write_text(json.dumps(self.summary(), indent=2))
