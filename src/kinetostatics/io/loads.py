"""The ``loads:`` section: forces, torques and resistances, their tables over the driver
coordinate and the conditions under which they act."""

from __future__ import annotations

import numpy as np

from ..base.keys import NAME, NUMBER, VECTOR, Keys, enum, list_of, one_of
from ..base.spec import Entry
from ..errors import Location, did_you_mean
from ..model import Condition, Load

LOAD_TYPES = ("force", "torque", "resistance", "resisting_torque")  # each: kinetics.kinds
CONDITION_TYPES = ("moving", "travel", "angle")  # the keys that name a condition's kind
CONDITION_KEYS = Keys(
    {"moving": VECTOR, "travel": VECTOR, "along": VECTOR, "angle": VECTOR, "point": NAME}
)
LOAD_TABLE_KEYS = Keys(
    {"at": list_of(NUMBER), "value": list_of(one_of(NUMBER, VECTOR))}, required=("at", "value")
)
LOAD_KEYS = Keys(
    {
        "type": enum(LOAD_TYPES),
        "link": NAME,
        "value": one_of(NUMBER, VECTOR),
        "table": LOAD_TABLE_KEYS,
        "point": NAME,
        "axis": VECTOR,
        "active": list_of(CONDITION_KEYS),
        "joint": NAME,
    },
    required=("type", "link"),
)


class LoadSections:
    """Reads ``loads:``.

    A mixin of :class:`~kinetostatics.io.builder.Builder`: it uses the builder's ``top``, ``ctx``,
    ``problems`` and name bookkeeping (``_claim``, ``_broken``, ``_not_a``).
    """

    def _loads(self, links, joints, points, drivers) -> list[Load]:
        section = self.top.get("loads")
        if section is None or not section.mapping():
            return []
        out = []
        for name, e in section.items():
            load = None
            if self._claim(section, name, "load") and e.check(LOAD_KEYS):
                load = self._load(name, e, links, joints, points, drivers, section.key_where(name))
            if load is None:
                self.broken["load"].add(name)
            else:
                out.append(load)
        return out

    def _load(
        self, name: str, e: Entry, links, joints, points, drivers, where: Location
    ) -> Load | None:
        link_names = {link.name: link for link in links}
        kinds = LOAD_TYPES
        kind = e["type"].text()
        if kind not in kinds:
            if kind is not None:
                e["type"].error(
                    f"unknown load type '{kind}'{did_you_mean(kind, kinds)}; "
                    "known: force, resistance, resisting_torque, torque"
                )
            return None
        torque_like = kind in ("torque", "resisting_torque")
        link = e["link"].text()
        if link not in link_names:
            if link is not None and not self._broken("link", link):
                e["link"].error(self._not_a("link", link, link_names, links))
            return None
        if link_names[link].ground:
            e["link"].error(
                f"a load on the ground link '{link}' does nothing; put it on a moving link"
            )
            return None
        point = None
        if (pe := e.get("point")) is not None:
            point = pe.text()
            if e.point(link, point, points, key="point") is None:
                return None
        if (e.get("value") is None) == (e.get("table") is None):
            e.error(
                "give exactly one of value (a constant) or table (values over the driver "
                "coordinate)"
            )
            return None
        table = None
        if e.get("value") is not None:
            value = (
                e["value"].vector("force")
                if kind == "force"
                else self._load_number(e["value"], kind)
            )
        else:
            table = self._table(e["table"], kind, joints, drivers)
            value = None if table is None else np.zeros(2 if kind == "force" else ())
        axis = None
        if kind == "resistance":
            if (ae := e.get("axis")) is None:
                e.error(
                    "a resistance needs axis: [x, y], the line along which it opposes "
                    "the point's velocity"
                )
                return None
            axis = ae.vector(None)
            axis = None if axis is None else ae.unit(axis)
            if axis is None:
                return None
        elif e.get("axis") is not None:
            e["axis"].error("axis applies to a resistance only")
        if torque_like and point is not None:
            e["point"].error("a torque acts on the link, not at a point")
        joint = None
        if (je := e.get("joint")) is not None:
            joint = self._relative_joint(je, kind, link, joints)
            if joint is None:
                return None
        conditions = self._conditions(e, link, point, points, drivers)
        if value is None or conditions is None:
            return None
        return Load(
            name,
            kind,
            link,
            np.asarray(value, dtype=float),
            point,
            axis,
            tuple(conditions),
            where,
            table,
            joint,
        )

    def _load_number(self, x: Entry, kind: str) -> float | None:
        """A scalar load value (``value`` or a table entry) in SI; a resisting torque's is
        a magnitude: a negative one would drive the machine, so it is refused."""
        unit = "torque" if kind in ("torque", "resisting_torque") else "force"
        if kind == "resisting_torque":
            raw = x.raw_number()
            if raw is not None and raw < 0:
                x.error(
                    f"a resisting torque is a magnitude that opposes the rotation: it must be "
                    f"zero or positive, got {raw:g} (a torque that drives is type: torque)"
                )
                return None
        return x.number(unit)

    def _relative_joint(self, e: Entry, kind: str, link: str, joints) -> str | None:
        """``joint:`` of a resisting torque: a revolute that holds ``link``."""
        name = e.text()
        if name is None:
            return None
        if kind != "resisting_torque":
            e.error("joint applies to a resisting_torque only")
            return None
        by_name = {j.name: j for j in joints}
        if name not in by_name:
            if not self._broken("joint", name):
                e.error(self._not_a("joint", name, by_name))
            return None
        j = by_name[name]
        if not j.angular or link not in j.links:
            e.error(
                f"joint '{name}' must be a revolute that holds link '{link}' (it joins "
                f"{', '.join(j.links)}): the torque opposes {link}'s rotation relative to "
                "the joint's other link"
            )
            return None
        return name

    def _table(self, e: Entry, kind: str, joints, drivers) -> tuple[np.ndarray, np.ndarray] | None:
        """``table: {at: [driver coordinates], value: [values]}``, sorted by coordinate."""
        if not e.check(LOAD_TABLE_KEYS):
            return None
        motion = [d for d in drivers if d.motion is not None]
        joints = {j.name: j for j in joints}
        angular = not motion or joints[motion[0].joint].angular
        at_items, val_items = e["at"].seq(), e["value"].seq()
        if at_items is None or val_items is None:
            return None
        if len(at_items) != len(val_items) or len(at_items) < 2:
            e.error(
                f"at and value need the same number of entries, at least 2 "
                f"(got {len(at_items)} and {len(val_items)})"
            )
            return None
        at = [x.number("angle" if angular else "length") for x in at_items]
        vals = [
            x.vector("force") if kind == "force" else self._load_number(x, kind) for x in val_items
        ]
        if any(v is None for v in at) or any(v is None for v in vals):
            return None
        at_arr = np.array(at, dtype=float)
        if np.any(np.diff(at_arr) <= 0):
            e["at"].error("the coordinates must increase")
            return None
        return at_arr, np.array(vals, dtype=float)

    def _point_ref(self, e: Entry, ref: str, points, allow_link: bool = False) -> bool:
        """Check ``link.point`` (or ``link`` alone when ``allow_link``); report a bad one."""
        link, dot, pname = ref.partition(".")
        if link not in points:
            if not self._broken("link", link):
                e.error(f"{self._not_a('link', link, points)} (in '{ref}', written link.point)")
            return False
        if not dot and not allow_link:
            e.error(f"'{ref}' is a link; write link.point")
            return False
        if dot and pname not in points[link]:
            e.error(
                f"link '{link}' has no point '{pname}'{did_you_mean(pname, points[link])}; "
                f"it has: {', '.join(points[link]) or 'no points'}"
            )
            return False
        return True

    def _conditions(
        self, e: Entry, link: str, point: str | None, points, drivers
    ) -> list[Condition] | None:
        ae = e.get("active")
        if ae is None:
            return []
        items = ae.seq()
        if items is None:
            return None
        out = []
        for c in items:
            if not c.check(CONDITION_KEYS):
                return None
            kinds = [k for k in CONDITION_TYPES if c.get(k) is not None]
            if not kinds:
                c.error("a condition needs one of: moving, travel, angle")
                return None
            if len(kinds) > 1:
                c.error(
                    f"a condition takes exactly one of moving, travel, angle; this one has "
                    f"{' and '.join(kinds)} (write each condition as its own list item)"
                )
                return None
            kind = kinds[0]
            plink, pname = link, point
            if (pe := c.get("point")) is not None:
                ref = pe.text()
                if ref is None or not self._point_ref(pe, ref, points, allow_link=True):
                    return None
                plink, _, pname = ref.partition(".")
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
                    scale = self.ctx.units["length"]
                    unit = self.ctx.unit_names.get("length", "m")
                    c["travel"].error(
                        f"the travel band [{b[0] / scale:g}, {b[1] / scale:g}] "
                        f"{unit} is empty: give [from, to] with from < to"
                    )
                    return None
                out.append(Condition("travel", plink, pname, axis, (b[0], b[1]), c.where))
            else:
                b = c["angle"].vector("angle")
                if b is None:
                    return None
                if not [d for d in drivers if d.motion is not None]:
                    if not self.broken["driver"] and "driver" not in self.lost:
                        c["angle"].error("an angle condition needs a motion driver")
                    return None
                first = next(d for d in drivers if d.motion is not None)
                if first.motion.own_run:
                    c["angle"].error(
                        f"an angle condition needs a constant-speed driver; "
                        f"'{first.name}' follows a {first.motion.kind} law (use a "
                        "travel or moving condition)"
                    )
                    return None
                out.append(Condition("angle", bounds=(b[0], b[1]), where=c.where))
        return out
