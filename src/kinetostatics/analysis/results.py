"""The result of an analysis: named arrays over the positions, and their export.

Column names and units are those of ``results.csv`` (docs/conventions.md).  Angles are
in rad inside the arrays ``q``, ``qd``, ``qdd``; the named columns follow the
CSV (``angle``, ``travel`` and ``<link>.theta`` in degrees).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from ..base.files import json_text
from ..base.tables import write_columns
from ..errors import did_you_mean
from ..kinematics.state import point_state
from ..kinetics.elements import coordinate as element_coordinate
from ..kinetics.elements import element_states
from ..structure.system import System, coordinate_gradient, link_poses
from .checks import result_checks
from .frames import html_repr, members, select, short_repr, to_pandas, to_xarray

__all__ = ["Result", "build_columns", "joint_warnings", "element_warnings"]


def _joint_position(system: System, q: np.ndarray, name: str) -> np.ndarray:
    """Global position of a pin: its point on link i."""
    j = system.model.joint(name)
    link = j.links[0]
    p = next(a.xy for a in j.anchors() if a.at_joint and a.link == link)
    if link == system.model.ground.name:
        return np.broadcast_to(p, q.shape[:-1] + (2,))
    k = system.link_index(link)
    return point_state(q, q, None, k, p)[0]


def _pose(system: System, q: np.ndarray, link: str) -> np.ndarray:
    """(x, y, θ) of a link, ``(..., 3)``; the frame's are zeros."""
    if link == system.model.ground.name:
        return np.zeros(q.shape[:-1] + (3,))
    k = system.link_index(link)
    return q[..., 3 * k : 3 * k + 3]


def _dyad_angle_names(system: System) -> list[tuple[str, str]]:
    """(column prefix, label) of the dyads that have a transmission or pressure angle."""
    label = {"RRR": "transmission_angle", "RRP": "pressure_angle"}
    return [
        (p.group.column, label[p.group.letters])
        for p in system.plans
        if p.group.kind == "dyad" and p.group.letters in label
    ]


def _angle_between(u: np.ndarray, v: np.ndarray, unsigned: bool = False) -> np.ndarray:
    """Angle between vectors ``u`` and ``v (..., 2)`` in deg, from 0 to 180° (to 90° between
    their lines when ``unsigned``); NaN where either is zero.

    atan2 of cross and dot keeps full relative precision at every angle; the arccos of
    their cosine loses half the digits near 0° and 180° (a pressure angle of 0.0007° came out
    5e-10° apart from two equal positions, 7e-7 of itself: net seed 1005175).
    """
    cross = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    dot = np.sum(u * v, axis=-1)
    ang = np.arctan2(np.abs(cross), np.abs(dot) if unsigned else dot)
    zero = (np.linalg.norm(u, axis=-1) == 0) | (np.linalg.norm(v, axis=-1) == 0)
    return np.degrees(np.where(zero, np.nan, ang))


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
            out[g.column] = ("transmission_angle", _angle_between(u, v))
        else:
            s = joints[ext_b]
            qi, qj = (_pose(system, q, link) for link in s.links)
            axis = s.glyph(qi, qj).guide.direction  # the slide's axis
            out[g.column] = ("pressure_angle", _angle_between(u, axis, unsigned=True))
    return out


class Columns(Mapping):
    """Named result columns in CSV order, each computed on first access.

    Columns computed together (a point's six, a joint's reactions) share one
    computation; asking for one joint's reaction builds only that joint's.
    """

    def __init__(self) -> None:
        self._where: dict[str, tuple[int, int]] = {}
        self._groups: list = []
        self._done: dict[int, tuple] = {}

    def add(self, names: list[str], compute) -> None:
        """Register columns ``names`` whose arrays ``compute()`` returns, in order."""
        g = len(self._groups)
        self._groups.append(compute)
        for k, name in enumerate(names):
            self._where[name] = (g, k)

    def __getitem__(self, name: str) -> np.ndarray:
        g, k = self._where[name]
        if g not in self._done:
            self._done[g] = tuple(np.asarray(a, dtype=float) for a in self._groups[g]())
        return self._done[g][k]

    def __contains__(self, name: object) -> bool:  # without computing it
        return name in self._where

    def __iter__(self):
        return iter(self._where)

    def __len__(self) -> int:
        return len(self._where)

    @property
    def computed(self) -> int:
        """How many columns have been computed so far (for tests and measurements)."""
        return sum(len(v) for v in self._done.values())


def build_columns(system: System, t, psi, q, qd, qdd, x0, fric, power, cond, shaking, full):
    """Ordered lazy columns and units (docs/conventions.md); ``x0`` None: kinematics only."""
    model = system.model
    cols = Columns()
    units: dict[str, str] = {}

    def put(names_units, compute):
        cols.add([n for n, _ in names_units], compute)
        units.update(names_units)

    first = system.motion_drivers[0]
    coord = psi[..., 0]
    put([("time", "s")], lambda: (t - t[0] if len(t) else t,))
    if first.joint.angular:
        put(
            [("angle", "deg"), ("travel", "deg")],
            lambda: (np.mod(np.degrees(coord), 360.0), np.degrees(np.abs(coord - coord[0]))),
        )
    else:
        put([("stroke", "m"), ("travel", "m")], lambda: (coord, np.abs(coord - coord[0])))
    link_units = (
        ("x", "m"),
        ("y", "m"),
        ("theta", "deg"),
        ("vx", "m/s"),
        ("vy", "m/s"),
        ("omega", "rad/s"),
        ("ax", "m/s^2"),
        ("ay", "m/s^2"),
        ("alpha", "rad/s^2"),
    )
    for k, name in enumerate(system.links):
        s = slice(3 * k, 3 * k + 3)
        put(
            [(f"{name}.{label}", unit) for label, unit in link_units],
            lambda s=s: (
                q[..., s][..., 0],
                q[..., s][..., 1],
                np.degrees(q[..., s][..., 2]),
                qd[..., s][..., 0],
                qd[..., s][..., 1],
                qd[..., s][..., 2],
                qdd[..., s][..., 0],
                qdd[..., s][..., 1],
                qdd[..., s][..., 2],
            ),
        )
    point_units = (
        ("x", "m"),
        ("y", "m"),
        ("vx", "m/s"),
        ("vy", "m/s"),
        ("ax", "m/s^2"),
        ("ay", "m/s^2"),
    )

    def point(k, p):
        pos, vel, acc = point_state(q, qd, qdd, k, p, link_poses(system, q)[..., k, :])
        return pos[..., 0], pos[..., 1], vel[..., 0], vel[..., 1], acc[..., 0], acc[..., 1]

    for k, name in enumerate(system.links):
        for pname, p in model.link(name).points.items():
            put(
                [(f"{name}.{pname}.{label}", unit) for label, unit in point_units],
                lambda k=k, p=p: point(k, p),
            )
    if x0 is not None:
        _kinetic_columns(system, put, q, qd, x0, fric, power)
    for g, c in cond.items():
        put([(f"{g.column}.cond", "1")], lambda c=c: (c,))
    angles = {}

    def dyad_angles():
        if not angles:
            angles.update(_dyad_angles(system, q))
        return angles

    for prefix, label in _dyad_angle_names(system):
        put([(f"{prefix}.{label}", "deg")], lambda prefix=prefix: (dyad_angles()[prefix][1],))
    qe = _padded(q)
    seen = None if x0 is None else _seen(x0)
    for k, j in enumerate(model.joints):  # a type's own columns (a cam's pressure angle)
        i_, j_ = system.ends[k]
        qi, qj = qe[..., 3 * i_ : 3 * i_ + 3], qe[..., 3 * j_ : 3 * j_ + 3]
        own = j.columns(qi, qj, None if seen is None else seen[..., system.rows_of(k)])
        if own:
            put(
                [(f"{j.name}.{label}", unit) for label, (unit, _) in own.items()],
                lambda own=own: tuple(v for _, v in own.values()),
            )
    if shaking is not None:
        put(
            [("shaking.Fx", "N"), ("shaking.Fy", "N"), ("shaking.M", "N*m")],
            lambda: (shaking[..., 0], shaking[..., 1], shaking[..., 2]),
        )
    return cols, units


def _padded(q: np.ndarray) -> np.ndarray:
    """q with the frame's zero pose appended (the last link index of ``system.ends``)."""
    return np.concatenate((q, np.zeros(q.shape[:-1] + (3,))), axis=-1)


def _seen(x0: np.ndarray) -> np.ndarray:
    """The frictionless solution ``x0`` as the joints' columns and warnings see it: an
    entry within round-off (1e-12) of the run's largest |value| (of each variant's run,
    for stacked variants) is 0.  (A cam follower at rest in a dwell with nothing pressing
    it has a contact force of 0 in exact arithmetic, ±6e-15 N computed: its status and the
    separation warning followed that sign, and the same row said 0 in one run and 1 in
    another.)"""
    axes = tuple(range(max(x0.ndim - 2, 0), x0.ndim))  # a run's rows; variants apart
    floor = 1e-12 * np.max(np.abs(np.nan_to_num(x0)), axis=axes, keepdims=True, initial=0.0)
    return np.where(np.abs(x0) <= floor, 0.0, x0)


def joint_warnings(system: System, q: np.ndarray, x0: np.ndarray) -> list[str]:
    """What each joint type has to say about the rows (``Joint.warnings``)."""
    qe, out, seen = _padded(q), [], _seen(x0)
    for k, j in enumerate(system.model.joints):
        i_, j_ = system.ends[k]
        lam = seen[..., system.rows_of(k)]
        out += j.warnings(lam, qe[..., 3 * i_ : 3 * i_ + 3], qe[..., 3 * j_ : 3 * j_ + 3])
    return out


def element_warnings(system: System, q: np.ndarray, coord: np.ndarray) -> list[str]:
    """A line per spring or damper whose length reaches zero (≤ 1e-9 L_ref) at some rows
    ``q (N, n_q)``, naming those rows by the first motion driver's coordinate ``coord
    (N,)`` (rad or m): there its direction is undefined and its force acts on nothing."""
    out = []
    driver = system.motion_drivers[0] if system.motion_drivers else None
    for e in system.model.elements:
        if e.rotational:
            continue
        length = element_coordinate(system, e, q)[0]
        rows = np.nonzero(length <= 1e-9 * np.max(system.l_ref))[0]
        if not rows.size:
            continue
        if driver is None:
            where = "rows " + ", ".join(str(int(k)) for k in rows[:8])
        elif driver.joint.angular:
            where = f"{driver.name} = " + ", ".join(
                f"{np.degrees(coord[k]) % 360:.4g}°" for k in rows[:8]
            )
        else:
            where = f"{driver.name} = " + ", ".join(f"{coord[k] * 1e3:.6g} mm" for k in rows[:8])
        more = " …" if rows.size > 8 else ""
        ends = " and ".join(f"{link}.{point}" for link, point in zip(e.links, e.points))
        out.append(
            f"element '{e.name}': {ends} meet (length 0) at {rows.size} position(s), "
            f"{where}{more}: the {e.kind}'s direction is undefined there and its force acts "
            "on nothing"
        )
    return out


def _element_columns(system: System, put, q, qd) -> None:
    """``<element>.length`` (m; ``.angle`` deg for a rotational one), ``.speed`` (its rate,
    m/s or rad/s), ``.F`` (N; ``.M`` N·m: positive reduces the length or angle), ``.energy``
    (J, springs) and ``.power`` (W, f ṡ: stored by a spring, dissipated by a damper)."""
    states: dict = {}

    def of(name: str) -> tuple:
        if not states:
            states["all"] = element_states(system, q, qd)
        st = states["all"]
        cols = [st.s[name], st.rate[name], st.f[name]]
        if next(e for e in system.model.elements if e.name == name).rotational:
            cols[0] = np.degrees(cols[0])
        if st.spring[name]:
            cols.append(st.energy[name])
        return (*cols, st.power[name])

    for e in system.model.elements:
        r = e.rotational
        names = [
            (f"{e.name}.{'angle' if r else 'length'}", "deg" if r else "m"),
            (f"{e.name}.speed", "rad/s" if r else "m/s"),
            (f"{e.name}.{'M' if r else 'F'}", "N*m" if r else "N"),
            *([(f"{e.name}.energy", "J")] if e.spring else []),
            (f"{e.name}.power", "W"),
        ]
        put(names, lambda name=e.name: of(name))


def _in_order(values: Mapping[str, np.ndarray], labels) -> tuple:
    return tuple(values[label] for label in labels)


def _kinetic_columns(system: System, put, q, qd, x0, fric, power) -> None:
    model = system.model
    sol = fric["solution"] if fric else None
    n_f = {k: n for n, k in enumerate(fric["setup"].joints)} if fric else {}
    force_unit = {"M": "N*m"}

    def pair(k: int) -> tuple[np.ndarray, np.ndarray]:
        """Joint k's links' poses with their frames (cos θ, sin θ once per state)."""
        pe = link_poses(system, q)
        return pe[..., system.ends[k][0], :], pe[..., system.ends[k][1], :]

    for k, j in enumerate(model.joints):
        block = system.rows_of(k)
        labels = j.reaction_labels
        put(
            [(f"{j.name}.{label}", force_unit.get(label, "N")) for label in labels],
            lambda j=j, k=k, block=block, labels=labels: _in_order(
                j.reaction(x0[..., block], *pair(k)), labels
            ),
        )
        if not fric:
            continue
        unit = "N*m" if j.angular else "N"
        if k in n_f:
            put(
                [(f"{j.name}.friction_approx", unit), (f"{j.name}.friction", unit)],
                lambda n=n_f[k]: (fric["e_approx"][..., n], sol.e[..., n]),
            )

        def with_friction(j=j, k=k, block=block, labels=labels):
            qi, qj = pair(k)
            reac = j.reaction(sol.x[..., block], qi, qj)
            if k in n_f:  # a friction force along a slide is a force too
                for label, extra in j.effort_force(sol.e[..., n_f[k]], qi, qj).items():
                    reac[label] = reac[label] + extra
            return tuple(reac[label] for label in labels)

        put(
            [(f"{j.name}.{label}_friction", force_unit.get(label, "N")) for label in labels],
            with_friction,
        )
    n_j = system.n_joint_rows
    names = [j.name for j in model.joints]
    for d_index, d in enumerate(system.motion_drivers):
        effort_joint = model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
        word, unit = ("torque", "N*m") if effort_joint.angular else ("force", "N")
        col = n_j + d_index
        put([(f"{d.name}.{word}", unit)], lambda col=col: (x0[..., col],))
        if fric:
            k_effort = names.index(effort_joint.name)

            def efficiency(col=col, k=k_effort):
                # η = P_0/P_f, the driver's input power without over with friction, defined
                # only where the drive delivers power with friction (P_f > 0) and the power
                # it passes on is not negative (P_0 = P_f − friction loss ≥ 0): there
                # 0 ≤ η ≤ 1.  NaN (empty) elsewhere: the machine drives the motor back, the
                # drive idles (0/0), or the friction consumes more than the drive delivers
                # (docs/friction.md)
                rel = np.einsum("...n,...n->...", coordinate_gradient(system, q, k), qd)
                p0, pf = x0[..., col] * rel, sol.x[..., col] * rel
                # a P_0 within round-off of 0 (a limit position of a massless drive) is 0
                ok = (pf > 0.0) & (p0 >= -1e-9 * pf)
                with np.errstate(divide="ignore", invalid="ignore"):
                    return (np.where(ok, np.maximum(p0 / pf, 0.0), np.nan),)

            put(
                [(f"{d.name}.{word}_friction_approx", unit), (f"{d.name}.{word}_friction", unit)],
                lambda col=col: (fric["x_approx"][..., col], sol.x[..., col]),
            )
            put([(f"{d.name}.efficiency", "1")], efficiency)
    if fric:
        put(
            [("friction.status", "1"), ("friction.iterations", "1")],
            lambda: (sol.status, sol.iterations),
        )
    _element_columns(system, put, q, qd)
    names = [
        n
        for n in (
            "input",
            "kinetic",
            "potential",
            "elastic",
            "damping",
            "external",
            "friction",
            "residual",
            "residual_friction",
        )
        if n in power
    ]
    put([(f"power.{n}", "W") for n in names], lambda: tuple(power[n] for n in names))


@dataclass(frozen=True, repr=False)
class Result:
    """Named arrays over the positions, with the raw arrays for advanced use.

    ``result["rod.omega"]`` is a ``(n_pos,)`` array; ``result.columns`` the
    names in CSV order; ``result.units[name]`` the unit.  Raw: ``t`` (s),
    ``coordinate`` (rad or m), ``q``, ``qd``, ``qdd`` ``(n_pos, n_q)`` and
    ``lam`` ``(n_pos, n_lam)`` (frictionless multipliers and driver efforts), and
    ``lam_friction`` the same of the consistent friction solution (None without it).

    Tables (:mod:`.frames`, naming rule ``member.quantity``): :meth:`members`,
    :meth:`select`, :meth:`to_pandas`, :meth:`to_xarray`.
    """

    system: System
    t: np.ndarray
    coordinate: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    lam: np.ndarray
    columns: Mapping[str, np.ndarray]
    units: dict[str, str]
    events: tuple = ()
    singular: tuple = ()
    indeterminate: bool = False
    full_cycle: bool = True
    extremes: dict = field(default_factory=dict)
    lam_friction: np.ndarray | None = None

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f"no column '{name}'{did_you_mean(name, self.columns)}") from None

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:

        return short_repr(self)

    def _repr_html_(self) -> str:

        return html_repr(self)

    def members(self) -> dict[str, list[str]]:
        """``{member: [column names]}``: the columns of each link, joint, driver, load…
        (a name is ``member.quantity``, split at the first dot; :mod:`.frames`)."""

        return members(self)

    def select(self, member: str) -> dict[str, np.ndarray]:
        """``{quantity: array}`` of one member's columns: ``select("rocker")["B.vx"]``
        is ``result["rocker.B.vx"]``."""

        return select(self, member)

    def to_pandas(self, multiindex: bool = False):
        """A pandas DataFrame of the columns, units in ``df.attrs["units"]``;
        ``multiindex=True`` splits ``rocker.y`` into ``("rocker", "y")``.  Needs
        ``pip install 'kinetostatics[pandas]'``."""

        return to_pandas(self, multiindex)

    def to_xarray(self):
        """An xarray Dataset over the dimension ``position`` (``time``, ``angle`` or
        ``stroke``, ``travel`` as coordinates), units as attributes.  Needs
        ``pip install 'kinetostatics[xarray]'``."""

        return to_xarray(self)

    @cached_property
    def checks(self):
        """Self-checks (:class:`~kinetostatics.analysis.checks.Checks`): constraint and
        power-balance residuals, sketch distance, group condition, friction status, each against its
        tolerance; ``checks.ok``, ``checks.failed()``.  Computed on first use."""

        return result_checks(self)

    @property
    def names(self) -> list[str]:
        return list(self.columns)

    def to_csv(self, path: str | Path) -> None:
        """Write ``results.csv``: a ``# units:`` line, the header, one row per position."""
        write_columns(path, self.columns, self.units)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe: ``{"columns": {name: [..]}, "units": {...}}`` (NaN as None)."""
        return {
            "columns": {
                n: [None if not np.isfinite(v) else float(v) for v in a]
                for n, a in self.columns.items()
            },
            "units": dict(self.units),
        }

    def summary(self) -> dict[str, Any]:
        """Extremes of every column and where they occur, events, singular positions."""
        from ..outputs.summary import summarize

        return summarize(self)

    def to_json(self, path: str | Path, summary: dict[str, Any] | None = None) -> None:
        """Write :meth:`summary` (or the one given, already computed) as JSON."""
        data = self.summary() if summary is None else summary
        Path(path).write_text(json_text(data, ensure_ascii=False), encoding="utf-8")
