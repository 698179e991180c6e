"""The columns of a result: the named arrays of ``results.csv`` built from the records of
the stages (:class:`~kinetostatics.kinematics.motion.Motion`,
:class:`~kinetostatics.kinetics.inverse.Kinetics`), in CSV order, with their units; and the
warnings a pose or an element's state gives (docs/conventions.md).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..joints import Joint
from ..kinematics.motion import Motion
from ..kinematics.state import point_state
from ..kinetics.elements import coordinate as element_coordinate
from ..kinetics.elements import element_states
from ..kinetics.inverse import Kinetics
from ..structure.system import System, coordinate_rate, link_poses
from .angles import dyad_angle_names as _dyad_angle_names
from .angles import dyad_angles as _dyad_angles

__all__ = ["Columns", "build_columns", "joint_warnings", "element_warnings"]


class Columns(Mapping):
    """Named result columns in CSV order, each computed on first access.

    Columns computed together (a point's six, a joint's reactions) share one
    computation; asking for one joint's reaction builds only that joint's.
    """

    def __init__(self) -> None:
        self._where: dict[str, tuple[int, int]] = {}
        self._groups: list = []
        self._done: dict[int, tuple] = {}
        self._shared = False  # _where is a system's layout (laid_out): copied before a change

    @classmethod
    def laid_out(cls, where: dict[str, tuple[int, int]], groups: list) -> Columns:
        """Columns whose name → (group, index) map is ``where`` (shared, only read) and
        whose groups' computations are ``groups``, in order."""
        cols = cls()
        cols._where, cols._groups, cols._shared = where, groups, True
        return cols

    def add(self, names: list[str], compute) -> None:
        """Register columns ``names`` whose arrays ``compute()`` returns, in order."""
        if self._shared:  # another result reads the same layout
            self._where, self._shared = dict(self._where), False
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


def build_columns(
    system: System, motion: Motion, kin: Kinetics | None, *, cond: dict, shaking=None
) -> tuple[Columns, dict[str, str]]:
    """Ordered lazy columns and units (docs/conventions.md) of the rows of ``motion``;
    ``kin`` None: kinematics only.  ``cond``: each Assur group's condition numbers (a
    ``<group>.cond`` column each); ``shaking``: the frame's reaction, ``(..., 3)``, or a
    function that computes it when a ``shaking.*`` column is first read."""
    groups: list[_Names] = []
    computes: list = []

    def put(names_units, compute):
        groups.append(
            names_units if isinstance(names_units, _Names) else _interned(system, names_units)
        )
        computes.append(compute)

    t, coord = motion.t, motion.psi[..., 0]
    put([("time", "s")], lambda: (t - t[0] if len(t) else t,))
    if system.motion_drivers[0].joint.angular:
        put(
            [("angle", "deg"), ("travel", "deg")],
            lambda: (np.mod(np.degrees(coord), 360.0), np.degrees(np.abs(coord - coord[0]))),
        )
    else:
        put([("stroke", "m"), ("travel", "m")], lambda: (coord, np.abs(coord - coord[0])))
    _link_columns(system, put, motion)
    if kin is not None:
        _kinetic_columns(system, put, motion, kin)
    _group_and_joint_columns(system, put, motion.q, None if kin is None else kin.x0, cond)
    if shaking is not None:
        put(
            [("shaking.Fx", "N"), ("shaking.Fy", "N"), ("shaking.M", "N*m")],
            lambda: _components(shaking() if callable(shaking) else shaking),
        )
    where, units = _layout(system, groups)
    return Columns.laid_out(where, computes), dict(units)


class _Names:
    """Columns' names with their units, made once per system (:func:`_named`)."""

    __slots__ = ("names", "pairs")

    def __init__(self, pairs: list[tuple[str, str]]) -> None:
        self.pairs = pairs
        self.names = [n for n, _ in pairs]


def _named(system: System, key: tuple, make) -> _Names:
    """The names and units ``make()`` gives for ``key``, made on the system's first
    result and kept in its memo: a system's links, points and joints do not change, and
    formatting their ~10² names took a tenth of a short analysis's columns."""
    memo = system.memo.setdefault("column names", {})
    got = memo.get(key)
    if got is None:
        got = memo[key] = _Names(make())
    return got


def _interned(system: System, pairs: list[tuple[str, str]]) -> _Names:
    """The system's one :class:`_Names` of ``pairs`` (names made at each result)."""
    return _named(system, tuple(pairs), lambda: pairs)


def _layout(system: System, groups: list[_Names]) -> tuple[dict, dict[str, str]]:
    """Where each column is (name → (group, index)) and the units, for the groups in
    this order: made once per system and order of groups (a result with friction and one
    without have two), then shared — the map is only read."""
    layouts = system.memo.setdefault("column layouts", {})
    key = tuple(map(id, groups))  # each _Names is kept alive by the entry's own list
    hit = layouts.get(key)
    if hit is None:
        if len(layouts) >= 64:  # a few orders at most (with or without friction, events)
            layouts.clear()
        where: dict[str, tuple[int, int]] = {}
        units: dict[str, str] = {}
        for g, names in enumerate(groups):
            for k, name in enumerate(names.names):
                where[name] = (g, k)
            units.update(names.pairs)
        hit = layouts[key] = (where, units, list(groups))
    return hit[0], hit[1]


def _components(v: np.ndarray) -> tuple[np.ndarray, ...]:
    return v[..., 0], v[..., 1], v[..., 2]


_LINK_UNITS = (
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
_POINT_UNITS = (
    ("x", "m"),
    ("y", "m"),
    ("vx", "m/s"),
    ("vy", "m/s"),
    ("ax", "m/s^2"),
    ("ay", "m/s^2"),
)


def _link_columns(system: System, put, motion: Motion) -> None:
    """Each link's pose, velocity and acceleration, then each named point's."""
    q, qd, qdd = motion.q, motion.qd, motion.qdd
    for k, name in enumerate(system.links):
        s = slice(3 * k, 3 * k + 3)
        put(
            _named(
                system,
                ("link", name),
                lambda name=name: [(f"{name}.{label}", unit) for label, unit in _LINK_UNITS],
            ),
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

    def point(k, p):
        pos, vel, acc = point_state(q, qd, qdd, k, p, link_poses(system, q)[..., k, :])
        return pos[..., 0], pos[..., 1], vel[..., 0], vel[..., 1], acc[..., 0], acc[..., 1]

    for k, name, pname, p in _link_points(system):
        put(
            _named(
                system,
                ("point", name, pname),
                lambda name=name, pname=pname: [
                    (f"{name}.{pname}.{label}", unit) for label, unit in _POINT_UNITS
                ],
            ),
            lambda k=k, p=p: point(k, p),
        )


def _link_points(system: System) -> list[tuple[int, str, str, np.ndarray]]:
    """(link index, link, point, its local coordinates) of every moving link's named
    point, in the columns' order; once per system."""
    key = "link points"
    if key not in system.memo:
        links = {link.name: link for link in system.model.links}
        system.memo[key] = [
            (k, name, pname, p)
            for k, name in enumerate(system.links)
            for pname, p in links[name].points.items()
        ]
    return system.memo[key]


def _group_and_joint_columns(system: System, put, q, x0, cond: dict) -> None:
    """Each group's condition number, the dyads' transmission and pressure angles, and
    each joint type's own columns (a cam's pressure angle; ``x0`` None: kinematics only)."""
    for g, c in cond.items():
        put([(f"{g.column}.cond", "1")], lambda c=c: (c,))
    angles: dict[str, tuple[str, np.ndarray]] = {}

    def dyad_angles():
        if not angles:
            angles.update(_dyad_angles(system, q))
        return angles

    for prefix, label in _dyad_angle_names(system):
        put([(f"{prefix}.{label}", "deg")], lambda prefix=prefix: (dyad_angles()[prefix][1],))
    own_columns = _overriding(system, "columns")
    if not own_columns:
        return
    qe = _padded(q)
    seen = None if x0 is None else _seen(x0)
    for k in own_columns:
        j = system.model.joints[k]
        i_, j_ = system.ends[k]
        qi, qj = qe[..., 3 * i_ : 3 * i_ + 3], qe[..., 3 * j_ : 3 * j_ + 3]
        own = j.columns(qi, qj, None if seen is None else seen[..., system.rows_of(k)])
        if own:
            put(
                [(f"{j.name}.{label}", unit) for label, (unit, _) in own.items()],
                lambda own=own: tuple(v for _, v in own.values()),
            )


def _overriding(system: System, hook: str) -> tuple[int, ...]:
    """The joints whose type has its own ``hook`` (``columns``, ``warnings``): the others
    have nothing to give (the contract's default), so the arrays they would be handed are
    not made.  Decided once per system (kept in its memo)."""
    key = ("joints with their own", hook)
    if key not in system.memo:
        default = getattr(Joint, hook)
        system.memo[key] = tuple(
            k for k, j in enumerate(system.model.joints) if getattr(type(j), hook) is not default
        )
    return system.memo[key]


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
    speaking = _overriding(system, "warnings")
    if not speaking:
        return []
    qe, seen = _padded(q), _seen(x0)
    out: list[str] = []
    for k in speaking:
        j = system.model.joints[k]
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
            texts = [str(int(k)) for k in rows]
        elif driver.joint.angular:
            texts = [f"{np.degrees(coord[k]) % 360:.6g}°" for k in rows]
        else:
            texts = [f"{coord[k] * 1e3:.6g} mm" for k in rows]
        texts = list(dict.fromkeys(texts))  # each once: close rows may print alike
        where = ("rows " if driver is None else f"{driver.name} = ") + ", ".join(texts[:8])
        more = " …" if len(texts) > 8 else ""
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


_POWER_COLUMNS = (
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


def _kinetic_columns(system: System, put, motion: Motion, kin: Kinetics) -> None:
    """The columns of the loads: reactions, friction, efforts, elements and power."""
    _reaction_columns(system, put, motion.q, kin)
    _effort_columns(system, put, motion, kin)
    sol = kin.friction.solution if kin.friction else None
    if sol is not None:
        put(
            [("friction.status", "1"), ("friction.iterations", "1")],
            lambda: (sol.status, sol.iterations),
        )
    _element_columns(system, put, motion.q, motion.qd)
    power = kin.power
    names = [n for n in _POWER_COLUMNS if n in power]
    put([(f"power.{n}", "W") for n in names], lambda: tuple(power[n] for n in names))


def _reaction_columns(system: System, put, q: np.ndarray, kin: Kinetics) -> None:
    """Each joint's reactions in its own labels; with friction, its friction effort
    (approximate and consistent) and its reactions with friction."""
    x0, fric = kin.x0, kin.friction
    sol = fric.solution if fric else None
    n_f = {k: n for n, k in enumerate(fric.setup.joints)} if fric else {}
    force_unit = {"M": "N*m"}

    def pair(k: int) -> tuple[np.ndarray, np.ndarray]:
        """Joint k's links' poses with their frames (cos θ, sin θ once per state)."""
        pe = link_poses(system, q)
        return pe[..., system.ends[k][0], :], pe[..., system.ends[k][1], :]

    for k, j in enumerate(system.model.joints):
        block = system.rows_of(k)
        labels = j.reaction_labels
        put(
            _named(
                system,
                ("reaction", j.name),
                lambda j=j, labels=labels: [
                    (f"{j.name}.{label}", force_unit.get(label, "N")) for label in labels
                ],
            ),
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
                lambda n=n_f[k]: (fric.e_approx[..., n], sol.e[..., n]),
            )

        def with_friction(j=j, k=k, block=block, labels=labels):
            qi, qj = pair(k)
            reac = j.reaction(sol.x[..., block], qi, qj)
            if k in n_f:  # a friction force along a slide is a force too
                for label, extra in j.effort_force(sol.e[..., n_f[k]], qi, qj).items():
                    reac[label] = reac[label] + extra
            return tuple(reac[label] for label in labels)

        put(
            _named(
                system,
                ("reaction with friction", j.name),
                lambda j=j, labels=labels: [
                    (f"{j.name}.{label}_friction", force_unit.get(label, "N")) for label in labels
                ],
            ),
            with_friction,
        )


def _idle_effort(system: System, x0: np.ndarray, x: np.ndarray, n_j: int, angular: bool):
    """Per row, the size below which a driving effort is a round-off zero: 1e-12 of the
    row's largest joint reaction (without or with friction), times the mechanism's size
    (the largest distance of a link's point from its centre of mass) for a torque."""
    reaction = np.maximum(
        np.max(np.abs(x0[..., :n_j]), axis=-1, initial=0.0),
        np.max(np.abs(x[..., :n_j]), axis=-1, initial=0.0),
    )
    size = max(
        (float(np.linalg.norm(p)) for link in system.model.links for p in link.points.values()),
        default=1.0,
    )
    return 1e-12 * reaction * (size if angular else 1.0)


def _effort_columns(system: System, put, motion: Motion, kin: Kinetics) -> None:
    """Each motion driver's torque or force; with friction, the same with friction
    (approximate and consistent) and the drive's efficiency."""
    model, q, qd = system.model, motion.q, motion.qd
    x0, fric = kin.x0, kin.friction
    sol = fric.solution if fric else None
    n_j = system.n_joint_rows
    names = [j.name for j in model.joints]
    for d_index, d in enumerate(system.motion_drivers):
        effort_joint = model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
        word, unit = ("torque", "N*m") if effort_joint.angular else ("force", "N")
        col = n_j + d_index
        put([(f"{d.name}.{word}", unit)], lambda col=col: (x0[..., col],))
        if not fric:
            continue
        k_effort = names.index(effort_joint.name)

        def efficiency(col=col, k=k_effort, angular=effort_joint.angular):
            # η = P_0/P_f, the driver's input power without over with friction, defined
            # only where the drive delivers power with friction (P_f > 0) and the power
            # it passes on is not negative (P_0 = P_f − friction loss ≥ 0): there
            # 0 ≤ η ≤ 1.  NaN (empty) elsewhere: the machine drives the motor back, the
            # drive idles (0/0), or the friction consumes more than the drive delivers
            # (docs/friction.md)
            rel = coordinate_rate(system, q, qd, k)
            p0, pf = x0[..., col] * rel, sol.x[..., col] * rel
            # a P_0 within round-off of 0 (a limit position of a massless drive) is 0; a
            # driving effort within round-off of 0 (the drive idles) leaves η undefined:
            # |effort| ≤ 1e-12 of the row's largest reaction (times the mechanism's size
            # for a torque), a scale no subset, frame or unit of the run changes
            ok = (
                (pf > 0.0)
                & (p0 >= -1e-9 * pf)
                & (np.abs(sol.x[..., col]) > _idle_effort(system, x0, sol.x, n_j, angular))
            )
            with np.errstate(divide="ignore", invalid="ignore"):
                return (np.where(ok, np.maximum(p0 / pf, 0.0), np.nan),)

        put(
            [(f"{d.name}.{word}_friction_approx", unit), (f"{d.name}.{word}_friction", unit)],
            lambda col=col: (fric.x_approx[..., col], sol.x[..., col]),
        )
        put([(f"{d.name}.efficiency", "1")], efficiency)
