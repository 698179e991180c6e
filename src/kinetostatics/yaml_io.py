"""YAML text -> :class:`~kinetostatics.model.Model`.

The file is composed with PyYAML's safe composer (no tags, no object
construction); every node keeps its line and column, so every problem is
reported as ``FILE:LINE:COL: key.path: message``.  Problems are collected and
raised together as one :class:`~kinetostatics.errors.ModelError`.  The schema
is documented in ``docs/yaml.md``.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Iterable

import numpy as np
import yaml

from . import expressions, units
from .errors import Collector, Location, ModelError, did_you_mean
from .joints import JOINT_TYPES, Joint
from .model import Analysis, Condition, Driver, Link, Load, Model, MotionLaw

__all__ = ["load", "loads", "Entry", "MAX_FILE_BYTES", "MAX_NODES", "dump"]

MAX_FILE_BYTES = 1_000_000
MAX_NODES = 100_000
MAX_LINKS = 200
MAX_POSITIONS = 10_000_000
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
RESERVED = frozenset({"time", "angle", "travel", "power", "friction"})
TOP_KEYS = ("name", "units", "parameters", "gravity", "ground", "links", "joints", "loops",
            "drivers", "loads", "sketch", "analysis")


class _Context:
    def __init__(self, file: str):
        self.file = file
        self.problems = Collector()
        self.env: dict[str, float] = {}
        self.units: dict[str, float] = units.unit_table(None)


class Entry:
    """A YAML node with its location; typed readers report problems and return ``None``."""

    def __init__(self, node: yaml.Node, where: Location, ctx: _Context):
        self.node, self.where, self.ctx = node, where, ctx

    # -- structure ----------------------------------------------------------
    def error(self, message: str) -> None:
        self.ctx.problems.add(self.where, message)

    @property
    def is_mapping(self) -> bool:
        return isinstance(self.node, yaml.MappingNode)

    def _pairs(self) -> list[tuple[str, yaml.Node, yaml.Node]]:
        if not self.is_mapping:
            return []
        return [(str(k.value), k, v) for k, v in self.node.value]

    def mapping(self) -> bool:
        if not self.is_mapping:
            self.error(f"expected a mapping of keys, got {_describe(self.node)}")
            return False
        return True

    def items(self) -> list[tuple[str, "Entry"]]:
        return [(key, self._child(key, v)) for key, _, v in self._pairs()]

    def keys(self) -> list[str]:
        return [key for key, _, _ in self._pairs()]

    def _child(self, key: str | int, node: yaml.Node) -> "Entry":
        m = node.start_mark
        return Entry(node, self.where.child(key, m.line + 1, m.column + 1), self.ctx)

    def get(self, key: str) -> "Entry | None":
        for k, _, v in self._pairs():
            if k == key:
                return self._child(k, v)
        return None

    def __getitem__(self, key: str) -> "Entry":
        entry = self.get(key)
        if entry is None:
            raise KeyError(key)
        return entry

    def require(self, key: str) -> "Entry | None":
        entry = self.get(key)
        if entry is None and self.mapping():
            self.error(f"missing required key '{key}'")
        return entry

    def check_keys(self, required: Iterable[str] = (), optional: Iterable[str] = ()) -> bool:
        """Report unknown keys (with a suggestion) and missing required keys."""
        if not self.mapping():
            return False
        required, allowed = tuple(required), tuple(required) + tuple(optional)
        ok = True
        for key, knode, _ in self._pairs():
            if key not in allowed:
                m = knode.start_mark
                self.ctx.problems.add(self.where.child(key, m.line + 1, m.column + 1),
                                      f"unknown key '{key}'{did_you_mean(key, allowed)}; "
                                      f"expected one of: {', '.join(allowed)}")
                ok = False
        present = set(self.keys())
        for key in required:
            if key not in present:
                self.error(f"missing required key '{key}'")
                ok = False
        return ok

    def seq(self) -> list["Entry"] | None:
        if not isinstance(self.node, yaml.SequenceNode):
            self.error(f"expected a list, got {_describe(self.node)}")
            return None
        return [self._child(k, n) for k, n in enumerate(self.node.value)]

    # -- scalars ------------------------------------------------------------
    def text(self) -> str | None:
        if not isinstance(self.node, yaml.ScalarNode) or self.node.value == "":
            self.error(f"expected a name, got {_describe(self.node)}")
            return None
        return str(self.node.value)

    def boolean(self) -> bool | None:
        value = self.node.value if isinstance(self.node, yaml.ScalarNode) else None
        if isinstance(value, str) and value.lower() in ("true", "yes", "on", "false", "no", "off"):
            return value.lower() in ("true", "yes", "on")
        self.error(f"expected true or false, got {_describe(self.node)}")
        return None

    def number(self, kind: str | None, *, minimum: float | None = None,
               strict: bool = False) -> float | None:
        """The scalar's value (a number or a parameter expression) times the
        file's unit factor for ``kind`` (``None``: dimensionless)."""
        if not isinstance(self.node, yaml.ScalarNode) or self.node.value == "":
            self.error(f"expected a number or an expression, got {_describe(self.node)}")
            return None
        try:
            value = expressions.evaluate(self.node.value, self.ctx.env)
        except expressions.ExpressionError as exc:
            self.error(str(exc))
            return None
        if minimum is not None and (value < minimum or (strict and value == minimum)):
            self.error(f"must be {'greater than' if strict else 'at least'} {minimum:g}, got {value:g}")
            return None
        return value * (self.ctx.units[kind] if kind else 1.0)

    def vector(self, kind: str | None, n: int = 2) -> np.ndarray | None:
        items = self.seq()
        if items is None:
            return None
        if len(items) != n:
            self.error(f"expected a list of {n} numbers, got {len(items)}")
            return None
        values = [e.number(kind) for e in items]
        return None if any(v is None for v in values) else np.array(values, dtype=float)

    def unit(self, v: np.ndarray) -> np.ndarray | None:
        norm = float(np.hypot(*v))
        if not norm > 0.0:
            self.error("direction has zero length")
            return None
        return v / norm

    def names(self, n: int) -> list[str] | None:
        """A name (n = 1) or a list of exactly n names."""
        if n == 1 and isinstance(self.node, yaml.ScalarNode):
            t = self.text()
            return None if t is None else [t]
        items = self.seq()
        if items is None:
            return None
        if len(items) != n:
            self.error(f"expected a list of {n} names, got {len(items)}")
            return None
        values = [e.text() for e in items]
        return None if any(v is None for v in values) else values

    def point(self, link: str, name: str | None, points: dict[str, dict[str, np.ndarray]],
              key: str, index: int | None = None) -> np.ndarray | None:
        """Local point ``name`` of ``link``; errors point at ``key[index]`` (or at this entry)."""
        where = self.get(key) or self
        if index is not None and isinstance(where.node, yaml.SequenceNode) and \
                index < len(where.node.value):
            where = where._child(index, where.node.value[index])
        if name is None or link not in points:
            return None
        if name not in points[link]:
            where.error(f"unknown point '{name}' on link '{link}'"
                        f"{did_you_mean(name, points[link])}; "
                        f"it has: {', '.join(points[link]) or 'no points'}")
            return None
        return points[link][name]


def _describe(node: yaml.Node) -> str:
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    return f"'{node.value}'" if node.value != "" else "nothing"


def _count_nodes(node: yaml.Node, limit: int) -> int:
    """Number of nodes reached (aliases counted each time), stopping past ``limit``."""
    count, stack = 0, [node]
    while stack and count <= limit:
        n = stack.pop()
        count += 1
        if isinstance(n, yaml.MappingNode):
            for k, v in n.value:
                stack.extend((k, v))
        elif isinstance(n, yaml.SequenceNode):
            stack.extend(n.value)
    return count


def _duplicate_keys(node: yaml.Node, file: str, problems: Collector, path: str = "") -> None:
    if isinstance(node, yaml.MappingNode):
        seen: set[str] = set()
        for k, v in node.value:
            key = str(k.value)
            sub = f"{path}.{key}" if path else key
            if key in seen:
                problems.add(Location(file, k.start_mark.line + 1, k.start_mark.column + 1, sub),
                             f"duplicate key '{key}'")
            seen.add(key)
            _duplicate_keys(v, file, problems, sub)
    elif isinstance(node, yaml.SequenceNode):
        for k, v in enumerate(node.value):
            _duplicate_keys(v, file, problems, f"{path}[{k}]")


# ---------------------------------------------------------------------------
def load(path: str | Path) -> Model:
    """Read a mechanism from a YAML file.

    Raises :class:`~kinetostatics.errors.ModelError` listing every problem
    as ``FILE:LINE:COL: key.path: message``.
    """
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise ModelError([(Location(str(path)),
                               f"file is {size} bytes; the limit is {MAX_FILE_BYTES}")])
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise ModelError([(Location(str(path)), f"cannot read the file: {reason}")]) from None
    return loads(text, file=str(path))


def loads(text: str, file: str = "<string>") -> Model:
    """Read a mechanism from YAML text (see :func:`load`)."""
    if len(text.encode("utf-8", "replace")) > MAX_FILE_BYTES:
        raise ModelError([(Location(file), f"text is longer than {MAX_FILE_BYTES} bytes")])
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        loc = Location(file, mark.line + 1, mark.column + 1) if mark else Location(file)
        raise ModelError([(loc, f"YAML syntax error: {problem}")]) from None
    if root is None:
        raise ModelError([(Location(file, 1, 1), "the file is empty")])
    if _count_nodes(root, MAX_NODES) > MAX_NODES:
        raise ModelError([(Location(file, 1, 1),
                           f"more than {MAX_NODES} YAML nodes (aliases expanded); refused")])
    ctx = _Context(file)
    _duplicate_keys(root, file, ctx.problems)
    ctx.problems.raise_if_any()
    top = Entry(root, Location(file, 1, 1, ""), ctx)
    if not top.mapping():
        ctx.problems.raise_if_any()
    return _Builder(top, ctx).build()


class _Builder:
    """Reads the top-level sections in dependency order."""

    def __init__(self, top: Entry, ctx: _Context):
        self.top, self.ctx, self.problems = top, ctx, ctx.problems
        self.names: dict[str, str] = {}          # name -> what it names (link, joint, driver)

    def build(self) -> Model:
        top = self.top
        top.check_keys(required=("links", "joints"), optional=TOP_KEYS)
        name = top["name"].text() if top.get("name") else "mechanism"
        unit_names = self._units()
        self._parameters()
        gravity = np.array([0.0, -9.81])
        if (g := top.get("gravity")) is not None:
            gravity = g.vector(None)
            if gravity is None:
                gravity = np.array([0.0, -9.81])
        links = self._links(gravity)
        points = {link.name: dict(link.points) for link in links}
        joints = self._joints(links, points)
        drivers = self._drivers(links, joints, points)
        loads_ = self._loads(links, points, drivers)
        sketch = self._sketch(links, joints)
        analysis = self._analysis(joints, drivers)
        loops = self._loops(joints)
        self.problems.raise_if_any()
        return Model(name=name or "mechanism", links=tuple(links), joints=tuple(joints),
                     drivers=tuple(drivers), loads=tuple(loads_), gravity=gravity,
                     sketch=sketch, analysis=analysis, loops=loops,
                     parameters=dict(self.ctx.env), units=unit_names, source=self.ctx.file)

    # -- names ----------------------------------------------------------------
    def _claim(self, entry: Entry, name: str, what: str) -> bool:
        if not NAME.match(name):
            entry.error(f"{what} name '{name}' is not a valid name "
                        "(letters, digits and _, not starting with a digit)")
            return False
        if name in RESERVED:
            entry.error(f"'{name}' is reserved (reserved names: {', '.join(sorted(RESERVED))})")
            return False
        if name in self.names:
            entry.error(f"duplicate name '{name}': already used by a {self.names[name]}")
            return False
        self.names[name] = what
        return True

    # -- sections ---------------------------------------------------------------
    def _units(self) -> dict[str, str]:
        spec: dict[str, str] = {}
        if (u := self.top.get("units")) is not None and u.mapping():
            for kind, e in u.items():
                unit = e.text()
                if unit is None:
                    continue
                try:
                    self.ctx.units[kind] = units.factor(kind, unit)
                    spec[kind] = unit
                except units.UnitError as exc:
                    e.error(str(exc))
        return spec

    def _parameters(self) -> None:
        p = self.top.get("parameters")
        if p is None or not p.mapping():
            return
        items, where = [], {}
        for key, e in p.items():
            if not isinstance(e.node, yaml.ScalarNode) or e.node.value == "":
                e.error(f"expected a number or an expression, got {_describe(e.node)}")
                continue
            if not NAME.match(key):
                e.error(f"parameter name '{key}' is not a valid name")
                continue
            items.append((key, e.node.value))
            where[key] = e
        try:
            self.ctx.env.update(expressions.evaluate_parameters(items))
        except expressions.ExpressionError as exc:
            (where.get(exc.name) or p).error(str(exc))

    def _links(self, gravity: np.ndarray) -> list[Link]:
        section = self.top.require("links")
        if section is None or not section.mapping():
            return []
        ground_name = "ground"
        if (g := self.top.get("ground")) is not None:
            ground_name = g.text() or "ground"
            if ground_name not in section.keys():
                g.error(f"ground link '{ground_name}' is not among the links"
                        f"{did_you_mean(ground_name, section.keys())}")
        elif "ground" not in section.keys() and section.keys():
            section.error("no ground link: name a link 'ground' or give the top-level key "
                          "'ground: <link>'")
        if len(section.keys()) > MAX_LINKS:
            section.error(f"{len(section.keys())} links; the limit is {MAX_LINKS}")
            return []
        links = []
        for name, e in section.items():
            if not self._claim(e, name, "link") or not e.check_keys(
                    optional=("points", "mass", "weight", "com", "inertia")):
                continue
            is_ground = name == ground_name
            com = e["com"].vector("length") if e.get("com") is not None else np.zeros(2)
            raw: dict[str, np.ndarray] = {}
            if (pts := e.get("points")) is not None and pts.mapping():
                for pname, pe in pts.items():
                    if not NAME.match(pname):
                        pe.error(f"point name '{pname}' is not a valid name")
                        continue
                    v = pe.vector("length")
                    if v is not None:
                        raw[pname] = v
            mass = inertia = 0.0
            if e.get("mass") is not None and e.get("weight") is not None:
                e["weight"].error("give either mass or weight, not both")
            elif e.get("mass") is not None:
                mass = e["mass"].number("mass", minimum=0.0)
            elif e.get("weight") is not None:
                w = e["weight"].number("force", minimum=0.0)
                g = float(np.hypot(*gravity))
                if w is not None and w > 0 and g == 0.0:
                    e["weight"].error("a weight needs a non-zero gravity to give a mass")
                    w = None
                mass = None if w is None else (w / g if w else 0.0)
            if e.get("inertia") is not None:
                inertia = e["inertia"].number("inertia", minimum=0.0)
            if is_ground and (mass or inertia):
                e.error("the ground link takes no mass or inertia")
            if com is None or mass is None or inertia is None:
                continue
            links.append(Link(name, {k: v - com for k, v in raw.items()}, float(mass),
                              float(inertia), com, is_ground, e.where))
        return links

    def _joints(self, links: list[Link], points) -> list[Joint]:
        section = self.top.require("joints")
        if section is None or not section.mapping():
            return []
        link_names = [link.name for link in links]
        joints = []
        for name, e in section.items():
            if not self._claim(e, name, "joint") or not e.mapping():
                continue
            t = e.require("type")
            kind = t.text() if t is not None else None
            if kind is None:
                continue
            if kind not in JOINT_TYPES:
                t.error(f"unknown joint type '{kind}'{did_you_mean(kind, JOINT_TYPES)}; "
                        f"known: {', '.join(sorted(JOINT_TYPES))}")
                continue
            le = e.require("links")
            pair = le.names(2) if le is not None else None
            if pair is None:
                continue
            bad = False
            for k, ln in enumerate(pair):
                if ln not in link_names:
                    where = le._child(k, le.node.value[k])
                    if ln in self.names or ln in points:
                        where.error(f"'{ln}' is not a link")
                    else:
                        where.error(f"unknown link '{ln}'{did_you_mean(ln, link_names)}")
                    bad = True
            if bad:
                continue
            if pair[0] == pair[1]:
                le.error(f"a joint connects two different links; both are '{pair[0]}'")
                continue
            joint = JOINT_TYPES[kind].from_spec(name, e, tuple(pair), points)
            if joint is not None:
                joints.append(joint)
        return joints

    def _drivers(self, links, joints, points) -> list[Driver]:
        section = self.top.get("drivers")
        if section is None or not section.mapping():
            return []
        by_name = {j.name: j for j in joints}
        drivers = []
        for name, e in section.items():
            if not self._claim(e, name, "driver") or not e.check_keys(
                    required=("joint",), optional=("motion", "effort", "points", "balance_at")):
                continue
            jname = e["joint"].text()
            joint = by_name.get(jname)
            if joint is None:
                if jname is not None:
                    e["joint"].error(f"unknown joint '{jname}'{did_you_mean(jname, by_name)}")
                continue
            speed_kind = "speed"
            if (e.get("motion") is None) == (e.get("effort") is None):
                e.error("give exactly one of motion (a prescribed coordinate) or effort "
                        "(an applied torque or force)")
                continue
            motion = effort = None
            if (m := e.get("motion")) is not None and m.check_keys(required=("speed",)):
                s = m["speed"]
                unit = next((u for k, u in self.top["units"].items() if k == "speed"), None) \
                    if self.top.get("units") is not None else None
                unit_text = unit.text() if unit is not None else None
                if unit_text and units.is_angular_speed(unit_text) != joint.angular:
                    s.error(f"speed unit '{unit_text}' does not fit a "
                            f"{joint.kind} joint's coordinate")
                    continue
                v = s.number(speed_kind)
                if v is not None and v == 0.0:
                    s.error("speed must not be zero")
                    v = None
                if v is None:
                    continue
                motion = MotionLaw(v)
            if (f := e.get("effort")) is not None:
                effort = f.number("torque" if joint.angular else "force")
                if effort is None:
                    continue
            pts: tuple[str | None, str | None] = (None, None)
            offset = 0.0
            if joint.angular:
                pts, offset = self._driver_offset(e, joint, joints, points)
                if offset is None:
                    continue
            elif e.get("points") is not None:
                e["points"].error("points apply to a revolute driver only")
            balance = None
            if (b := e.get("balance_at")) is not None:
                balance = b.text()
                if balance not in by_name:
                    b.error(f"unknown joint '{balance}'{did_you_mean(balance or '', by_name)}")
                    continue
                if motion is None:
                    b.error("balance_at needs a motion driver")
                    continue
            drivers.append(Driver(name, joint.name, motion, effort, offset, pts, balance, e.where))
        return drivers

    def _driver_offset(self, e: Entry, joint: Joint, joints, points):
        """(P_i, P_j) names and the offset α_j − α_i of the driver coordinate."""
        i, j = joint.links
        chosen: list[str | None] = [None, None]
        if (pe := e.get("points")) is not None:
            names = pe.names(2)
            if names is None:
                return (None, None), None
            chosen = [None if n in ("", "x", "+x") else n for n in names]
        angles = []
        for k, link in enumerate((i, j)):
            pname = chosen[k]
            if pname is None:
                if link == self._ground_name() and k == 0:
                    angles.append(0.0)          # the global +x axis
                    continue
                others = [o for o in joints if link in o.links and o.name != joint.name]
                if len(others) != 1:
                    e.error(f"cannot choose the driver's reference point on link '{link}' "
                            f"(it has {len(others)} other joints): give points: [P_i, P_j]")
                    return (None, None), None
                other = others[0]
                pname = _joint_point(other, link)
                chosen[k] = pname
            c = _joint_point_vec(joint, link)
            p = e.point(link, pname, points, key="points", index=k)
            if p is None or c is None:
                return (None, None), None
            d = p - c
            if not np.hypot(*d) > 0:
                e.error(f"the driver's reference point '{pname}' on link '{link}' "
                        "coincides with the joint centre")
                return (None, None), None
            angles.append(float(np.arctan2(d[1], d[0])))
        return (chosen[0], chosen[1]), angles[1] - angles[0]

    def _ground_name(self) -> str:
        g = self.top.get("ground")
        return (g.text() if g is not None else None) or "ground"

    def _loads(self, links, points, drivers) -> list[Load]:
        section = self.top.get("loads")
        if section is None or not section.mapping():
            return []
        link_names = {link.name: link for link in links}
        out = []
        for name, e in section.items():
            if not self._claim(e, name, "load") or not e.check_keys(
                    required=("type", "link", "value"), optional=("point", "axis", "active")):
                continue
            kind = e["type"].text()
            if kind not in ("force", "torque", "resistance"):
                if kind is not None:
                    e["type"].error(f"unknown load type '{kind}'"
                                    f"{did_you_mean(kind, ('force', 'torque', 'resistance'))}; "
                                    "known: force, resistance, torque")
                continue
            link = e["link"].text()
            if link not in link_names:
                if link is not None:
                    e["link"].error(f"unknown link '{link}'{did_you_mean(link, link_names)}")
                continue
            if link_names[link].ground:
                e["link"].error("a load on the ground link does nothing")
                continue
            point = None
            if (pe := e.get("point")) is not None:
                point = pe.text()
                if e.point(link, point, points, key="point") is None:
                    continue
            value = (e["value"].vector("force") if kind == "force"
                     else e["value"].number("torque" if kind == "torque" else "force"))
            axis = None
            if kind == "resistance":
                if (ae := e.require("axis")) is None:
                    continue
                axis = ae.vector(None)
                axis = None if axis is None else ae.unit(axis)
                if axis is None:
                    continue
            elif e.get("axis") is not None:
                e["axis"].error("axis applies to a resistance only")
            if kind == "torque" and point is not None:
                e["point"].error("a torque acts on the link, not at a point")
            conditions = self._conditions(e, link, point, points, drivers)
            if value is None or conditions is None:
                continue
            out.append(Load(name, kind, link, np.asarray(value, dtype=float), point, axis,
                            tuple(conditions), e.where))
        return out

    def _conditions(self, e: Entry, link: str, point: str | None, points,
                    drivers) -> list[Condition] | None:
        ae = e.get("active")
        if ae is None:
            return []
        items = ae.seq()
        if items is None:
            return None
        out = []
        for c in items:
            if not c.check_keys(optional=("moving", "travel", "along", "angle", "point")):
                return None
            kinds = [k for k in ("moving", "travel", "angle") if c.get(k) is not None]
            if len(kinds) != 1:
                c.error("each condition takes one of: moving, travel, angle")
                return None
            kind = kinds[0]
            plink, pname = link, point
            if (pe := c.get("point")) is not None:
                ref = pe.text() or ""
                plink, _, pname = ref.partition(".")
                if plink not in points or (pname and pname not in points[plink]):
                    pe.error(f"unknown point '{ref}' (write link.point)")
                    return None
                pname = pname or None
            if kind == "moving":
                axis = c["moving"].vector(None)
                axis = None if axis is None else c["moving"].unit(axis)
                if axis is None:
                    return None
                out.append(Condition("moving", plink, pname, axis, None, c.where))
            elif kind == "travel":
                if c.get("along") is None:
                    c.error("travel needs along: [x, y], the direction of travel")
                    return None
                axis = c["along"].vector(None)
                axis = None if axis is None else c["along"].unit(axis)
                b = c["travel"].vector("length")
                if axis is None or b is None:
                    return None
                if not b[0] < b[1]:
                    c["travel"].error(f"the band [{b[0]:g}, {b[1]:g}] m is empty")
                    return None
                out.append(Condition("travel", plink, pname, axis, (b[0], b[1]), c.where))
            else:
                b = c["angle"].vector("angle")
                if b is None:
                    return None
                if not [d for d in drivers if d.motion is not None]:
                    c["angle"].error("an angle condition needs a motion driver")
                    return None
                out.append(Condition("angle", bounds=(b[0], b[1]), where=c.where))
        return out

    def _sketch(self, links, joints) -> dict[str, np.ndarray]:
        section = self.top.get("sketch")
        if section is None or not section.mapping():
            return {}
        out = {}
        by_joint = {j.name for j in joints}
        pts = {link.name: link.points for link in links}
        for ref, e in section.items():
            link, dot, pname = ref.partition(".")
            if not dot and ref not in by_joint:
                e.error(f"unknown point '{ref}': write a joint name or link.point"
                        f"{did_you_mean(ref, by_joint)}")
                continue
            if dot and (link not in pts or pname not in pts[link]):
                e.error(f"unknown point '{ref}'")
                continue
            v = e.vector("length")
            if v is not None:
                out[ref] = v
        return out

    def _analysis(self, joints, drivers) -> Analysis:
        a = self.top.get("analysis")
        if a is None or not a.check_keys(optional=("start", "sweep", "positions", "at", "events")):
            return Analysis()
        by_name = {j.name: j for j in joints}
        motion = [d for d in drivers if d.motion is not None]
        kind = "angle" if not motion or by_name[motion[0].joint].angular else "length"
        start = a["start"].number(kind) if a.get("start") is not None else 0.0
        sweep = a["sweep"].number(kind) if a.get("sweep") is not None else (
            2 * np.pi if kind == "angle" else None)
        if kind == "length" and a.get("sweep") is None:
            a.error("a prismatic driver needs analysis.sweep (the travel to analyse)")
        if sweep is not None and not sweep > 0:
            a["sweep"].error(f"sweep must be positive, got {sweep:g}")
            sweep = None
        n = 360
        if (pe := a.get("positions")) is not None:
            v = pe.number(None)
            if v is not None and (v != int(v) or not 1 <= v <= MAX_POSITIONS):
                pe.error(f"positions must be a whole number from 1 to {MAX_POSITIONS}, got {v:g}")
            elif v is not None:
                n = int(v)
        at: tuple[float, ...] = ()
        if (ae := a.get("at")) is not None and (items := ae.seq()) is not None:
            vals = [e.number(kind) for e in items]
            at = tuple(v for v in vals if v is not None)
        events = a["events"].boolean() if a.get("events") is not None else False
        return Analysis(start or 0.0, sweep or 2 * np.pi, n, at, bool(events))

    def _loops(self, joints):
        section = self.top.get("loops")
        if section is None or (items := section.seq()) is None:
            return None
        names = {j.name for j in joints}
        loops = []
        for e in items:
            seq = e.seq()
            if seq is None:
                continue
            loop = []
            for x in seq:
                t = x.text()
                if t is not None and t not in names:
                    x.error(f"unknown joint '{t}'{did_you_mean(t, names)}")
                loop.append(t)
            loops.append(tuple(loop))
        return tuple(loops)


def _joint_point(joint: Joint, link: str) -> str:
    names = getattr(joint, "point_names", None)
    if names:
        return names[joint.links.index(link)]
    return getattr(joint, "point_name", joint.name)


def _joint_point_vec(joint: Joint, link: str) -> np.ndarray | None:
    if hasattr(joint, "p_i"):
        return joint.p_i if link == joint.links[0] else joint.p_j
    return None


def dump(model: Model) -> str:
    """The model as YAML text in SI (a round trip through :func:`loads` gives an equal model)."""
    doc: dict[str, Any] = {"name": model.name, "gravity": [float(g) for g in model.gravity],
                           "ground": model.ground.name, "links": {}, "joints": {}}
    for link in model.links:
        spec: dict[str, Any] = {"points": {k: [float(c) for c in v + link.com]
                                           for k, v in link.points.items()}}
        if not link.ground:
            spec.update(mass=link.mass, inertia=link.inertia, com=[float(c) for c in link.com])
        doc["links"][link.name] = spec
    for j in model.joints:
        doc["joints"][j.name] = {"type": j.kind, "links": list(j.links), **j.to_spec()}
    if model.drivers:
        doc["drivers"] = {}
        for d in model.drivers:
            spec = {"joint": d.joint}
            if d.motion is not None:
                spec["motion"] = {"speed": d.motion.speed}
            if d.effort is not None:
                spec["effort"] = d.effort
            if d.points != (None, None):
                spec["points"] = [p or "x" for p in d.points]
            if d.balance_at:
                spec["balance_at"] = d.balance_at
            doc["drivers"][d.name] = spec
    if model.sketch:
        doc["sketch"] = {k: [float(c) for c in v] for k, v in model.sketch.items()}
    a = model.analysis
    doc["analysis"] = {"start": a.start, "sweep": a.sweep, "positions": a.positions,
                       "at": list(a.at), "events": a.events}
    return yaml.safe_dump(doc, sort_keys=False)
