"""The ``elements:`` section: springs and dampers between two links (docs/yaml.md, "Elements").

A translational element (``spring``, ``damper``) joins two points, ``between: [link.point,
link.point]``; a rotational one (``torsion_spring``, ``rotary_damper``) acts at a revolute,
``joint: NAME``, on the rotation of its link j relative to its link i.  A spring gives
``stiffness`` and ``free_length`` (``free_angle``), optionally ``preload`` (its force there),
or a ``table`` of force over length (torque over angle); a damper gives ``damping``.
"""

from __future__ import annotations

import numpy as np

from ..base.keys import NAME, NUMBER, Keys, enum, list_of, names
from ..base.spec import Entry
from ..errors import Location, did_you_mean
from ..model import ELEMENT_KINDS, Element


def _table(s_kind: str, force_kind: str) -> Keys:
    return Keys({s_kind: list_of(NUMBER), force_kind: list_of(NUMBER)}, (s_kind, force_kind))


def _keys(place: str, shapes: dict) -> Keys:
    return Keys({"type": enum(ELEMENT_KINDS), place: PLACES[place], **shapes}, ("type", place))


PLACES = {"between": names(2), "joint": NAME}
ELEMENT_KEYS = {  # each type's keys, for the loader and the JSON Schema
    "spring": _keys(
        "between",
        {
            "stiffness": NUMBER,
            "free_length": NUMBER,
            "preload": NUMBER,
            "table": _table("length", "force"),
        },
    ),
    "damper": _keys("between", {"damping": NUMBER}),
    "torsion_spring": _keys(
        "joint",
        {
            "stiffness": NUMBER,
            "free_angle": NUMBER,
            "preload": NUMBER,
            "table": _table("angle", "torque"),
        },
    ),
    "rotary_damper": _keys("joint", {"damping": NUMBER}),
}


def _held_together(ends, points, joints) -> list | None:
    """The joints that hold the two points ``ends`` ((link, point), (link, point)) at the
    same place at every position, or None if nothing does: a path from one to the other
    through the pairs of points that a joint keeps together (``Joint.coincident``, a
    revolute's pins) and the points of one link at the same local coordinates."""
    scale = max(
        (float(np.max(np.abs(p))) for pts in points.values() for p in pts.values()), default=0.0
    )
    tol = 1e-12 * scale

    def at(link: str, xy) -> list[tuple[str, str]]:
        """The named points of ``link`` at ``xy`` (its frame)."""
        return [(link, n) for n, p in points.get(link, {}).items() if np.max(np.abs(p - xy)) <= tol]

    edges: dict[tuple[str, str], list] = {}
    for j in joints:
        for a, b in j.coincident():
            for u in at(a.link, a.xy):
                for v in at(b.link, b.xy):
                    edges.setdefault(u, []).append((v, j))
                    edges.setdefault(v, []).append((u, j))
    start, goal = ends
    targets = set(at(goal[0], points[goal[0]][goal[1]]))
    seen = {u: [] for u in at(start[0], points[start[0]][start[1]])}
    todo = list(seen)
    while todo:
        node = todo.pop(0)
        if node in targets:
            return seen[node]
        for v, j in edges.get(node, ()):
            for w in at(v[0], points[v[0]][v[1]]):
                if w not in seen:
                    seen[w] = [*seen[node], j]
                    todo.append(w)
    return None


class ElementSections:
    """Reads ``elements:`` (a mixin of :class:`~kinetostatics.io.builder.Builder`)."""

    def _elements(self, links, joints, points) -> list[Element]:
        section = self.top.get("elements")
        if section is None or not section.mapping():
            return []
        out = []
        for name, e in section.items():
            element = None
            if self._claim(section, name, "element"):
                element = self._element(name, e, links, joints, points, section.key_where(name))
            if element is None:
                self.broken["element"].add(name)
            else:
                out.append(element)
        return out

    def _element(self, name: str, e: Entry, links, joints, points, where: Location):
        if not e.mapping():
            return None
        kind = e["type"].text() if e.get("type") is not None else None
        if kind not in ELEMENT_KINDS:
            if e.get("type") is None:
                e.error("missing required key 'type' (" + ", ".join(ELEMENT_KINDS) + ")")
            elif kind is not None:
                e["type"].error(
                    f"unknown element type '{kind}'{did_you_mean(kind, ELEMENT_KINDS)}; "
                    f"known: {', '.join(ELEMENT_KINDS)}"
                )
            return None
        rotational = kind in ("torsion_spring", "rotary_damper")
        if not e.check(ELEMENT_KEYS[kind]):
            return None
        u = self.ctx.units
        if rotational:
            where_at = self._element_joint(e, joints)
            if where_at is None:
                return None
            ends, pts, joint = where_at, (None, None), e["joint"].text()
            per = u["torque"] / u["angle"]  # N·m per rad
            free_kind, force_kind, s_kind = "angle", "torque", "angle"
        else:
            ends_pts = self._element_points(e, points, joints, kind)
            if ends_pts is None:
                return None
            ends, pts, joint = ends_pts[0], ends_pts[1], None
            per = u["force"] / u["length"]  # N per m
            free_kind, force_kind, s_kind = "length", "force", "length"
        if kind in ("damper", "rotary_damper"):
            c = e["damping"].number(None, minimum=0.0) if e.get("damping") else None
            if e.get("damping") is None:
                e.error("a damper needs damping: its coefficient (force per speed)")
            if c is None:
                return None
            return Element(name, kind, ends, pts, joint, damping=c * per * u["time"], where=where)
        return self._spring(name, kind, e, ends, pts, joint, per, free_kind, force_kind, s_kind)

    def _spring(self, name, kind, e, ends, pts, joint, per, free_kind, force_kind, s_kind):  # noqa: PLR0913  an element's keys read by _element
        free_key = "free_angle" if kind == "torsion_spring" else "free_length"
        linear = [k for k in ("stiffness", free_key, "preload") if e.get(k) is not None]
        if e.get("table") is not None:
            if linear:
                e.error(f"give a table or {', '.join(linear)}, not both")
                return None
            table = self._element_table(e["table"], s_kind, force_kind)
            if table is None:
                return None
            return Element(name, kind, ends, pts, joint, table=table, where=e.where)
        missing = [k for k in ("stiffness", free_key) if e.get(k) is None]
        if missing:
            e.error(
                f"a {kind.replace('_', ' ')} needs stiffness and {free_key} (and optionally "
                f"preload), or a table; missing: {', '.join(missing)}"
            )
            return None
        k = e["stiffness"].number(None, minimum=0.0)
        free = e[free_key].number(free_kind)
        preload = e["preload"].number(force_kind) if e.get("preload") is not None else 0.0
        if k is None or free is None or preload is None:
            return None
        if kind == "spring" and free < 0:
            e[free_key].error(f"a free length must be zero or positive, got {free:g} m")
            return None
        return Element(
            name,
            kind,
            ends,
            pts,
            joint,
            stiffness=k * per,
            free=free,
            preload=preload,
            where=e.where,
        )

    def _element_joint(self, e: Entry, joints) -> tuple[str, str] | None:
        name = e["joint"].text()
        known = {j.name: j for j in joints}
        if name not in known:
            if name is not None and not self._broken("joint", name):
                e["joint"].error(self._not_a("joint", name, known))
            return None
        if not known[name].pin:
            e["joint"].error(
                f"'{name}' is a {known[name].kind} joint: a torsion spring or rotary damper "
                "acts at a revolute (on the relative rotation of its two links)"
            )
            return None
        return tuple(known[name].links)

    def _element_points(self, e: Entry, points, joints, kind: str):
        refs = e["between"].names(2)
        if any(r is None for r in refs):
            return None
        for r in refs:
            if not self._point_ref(e["between"], r, points):
                return None
        ends = tuple(r.partition(".")[0] for r in refs)
        if ends[0] == ends[1]:
            e["between"].error(
                f"both ends are on link '{ends[0]}': an element between two points of one "
                "rigid link does nothing"
            )
            return None
        names = tuple(r.partition(".")[2] for r in refs)
        held = _held_together(tuple(zip(ends, names)), points, joints)
        if held is not None:
            by = ", ".join(f"{j.kind} '{j.name}'" for j in held)
            e["between"].error(
                f"{refs[0]} and {refs[1]} are at the same place at every position (held "
                f"together by {by}): the {kind}'s direction is undefined and it would act on "
                "nothing; join two points that move apart"
            )
            return None
        return ends, names

    def _element_table(self, e: Entry, s_kind: str, force_kind: str):
        """``table: {length|angle: [...], force|torque: [...]}``, increasing in s."""
        if not e.check(_table(s_kind, force_kind)):
            return None
        s_items, f_items = e[s_kind].seq(), e[force_kind].seq()
        if s_items is None or f_items is None:
            return None
        if len(s_items) != len(f_items) or len(s_items) < 2:
            e.error(
                f"{s_kind} and {force_kind} need the same number of entries, at least 2 "
                f"(got {len(s_items)} and {len(f_items)})"
            )
            return None
        s = [x.number(s_kind) for x in s_items]
        f = [x.number(force_kind) for x in f_items]
        if any(v is None for v in s + f):
            return None
        at = np.array(s, dtype=float)
        if np.any(np.diff(at) <= 0):
            e[s_kind].error(f"the {s_kind}s must increase")
            return None
        return at, np.array(f, dtype=float)
