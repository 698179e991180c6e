"""The ``drivers:`` section: the driven joint, a constant speed or an effort, the
reference points of a revolute driver (motion laws: :mod:`.laws`)."""

from __future__ import annotations

import numpy as np

from ..base import units
from ..base.keys import NAME, NUMBER, Keys, list_of, names, one_of
from ..base.limits import SPEED_RANGE
from ..base.spec import Entry
from ..errors import Location
from ..joints import Joint
from ..model import Driver, EffortLaw, MotionLaw
from .laws import CONSTANT_KEYS, MOTION

# ``effort:`` as a mapping: exactly one of these, each with its own keys
EFFORT_KEYS = Keys(
    {
        "table": Keys({"at": list_of(NUMBER), "value": list_of(NUMBER)}, required=("at", "value")),
        "motor": Keys(
            {"torque": NUMBER, "speed": NUMBER, "slip": NUMBER},
            required=("torque", "speed", "slip"),
        ),
        "curve": Keys(
            {"speed": list_of(NUMBER), "torque": list_of(NUMBER)}, required=("speed", "torque")
        ),
    }
)
DRIVER_KEYS = Keys(
    {
        "joint": NAME,
        "motion": MOTION,
        "effort": one_of(NUMBER, EFFORT_KEYS),
        "points": names(2),
        "balance_at": NAME,
    },
    required=("joint",),
)


class DriverSections:
    """Reads ``drivers:``.

    A mixin of :class:`~kinetostatics.io.builder.Builder`: it uses the builder's ``top``, ``ctx``,
    ``problems`` and name bookkeeping (``_claim``, ``_broken``, ``_not_a``).
    """

    def _drivers(self, links, joints, points) -> list[Driver]:
        section = self.top.get("drivers")
        if section is not None and not section.mapping():
            self.lost.add("driver")
        if section is None or not section.mapping():
            return []
        drivers = []
        for name, e in section.items():
            driver = None
            if self._claim(section, name, "driver") and e.check(DRIVER_KEYS):
                driver = self._driver(name, e, links, joints, points, section.key_where(name))
            if driver is None:
                self.broken["driver"].add(name)
            else:
                drivers.append(driver)
        return drivers

    def _driver(self, name: str, e: Entry, links, joints, points, where: Location) -> Driver | None:
        by_name = {j.name: j for j in joints}
        jname = e["joint"].text()
        joint = by_name.get(jname)
        if joint is None:
            if jname is not None and not self._broken("joint", jname):
                e["joint"].error(self._not_a("joint", jname, by_name))
            return None
        m, f = e.get("motion"), e.get("effort")
        if m is not None and f is not None:
            e.error(
                "give either motion (a prescribed coordinate) or effort (an applied "
                "torque or force), not both"
            )
            return None
        if m is None and f is None:
            e.error("give motion (a prescribed coordinate) or effort (an applied torque or force)")
            return None
        motion = effort = None
        if m is not None and m.is_mapping and m.get("law") is not None:
            motion = self._motion_law(m, joint, links)
            if motion is None:
                return None
        elif m is not None:
            if not m.check(CONSTANT_KEYS):
                return None
            motion = self._constant_speed(m, joint)
            if motion is None:
                return None
        else:
            effort = self._effort(f, joint)
            if effort is None:
                return None
        pts: tuple[str | None, str | None] = (None, None)
        offset = 0.0
        if joint.angular:
            pts, offset = self._driver_offset(e, joint, joints, points)
            if offset is None:
                return None
        elif e.get("points") is not None:
            e["points"].error("points apply to a revolute driver only")
        balance = None
        if (b := e.get("balance_at")) is not None:
            balance = b.text()
            if balance is None:
                return None
            if balance not in by_name:
                if not self._broken("joint", balance):
                    b.error(self._not_a("joint", balance, by_name))
                return None
            if motion is None:
                b.error("balance_at needs a motion driver")
                return None
        return Driver(name, joint.name, motion, effort, offset, pts, balance, where)

    def _constant_speed(self, m: Entry, joint: Joint) -> MotionLaw | None:
        """``motion: {speed: v}``: constant speed, signed (rad/s or m/s)."""
        s = m["speed"]
        unit = self.ctx.unit_names.get("speed")
        if unit and units.is_angular_speed(unit) != joint.angular:
            if joint.angular:
                s.error(
                    f"the speed unit '{unit}' (units.speed) is linear, but joint "
                    f"'{joint.name}' is {joint.kind}: give units.speed as rpm, "
                    "rad/s, deg/s or rev/s"
                )
            else:
                s.error(
                    f"the speed unit '{unit}' (units.speed) is angular, but joint "
                    f"'{joint.name}' is {joint.kind}: give units.speed as m/s, "
                    "mm/s or cm/s"
                )
            return None
        v = s.number("speed", bounded=False)  # SPEED_RANGE below
        if v is not None and v == 0.0:
            s.error("the speed must not be zero (its sign gives the sense of motion)")
            return None
        if v is not None and not SPEED_RANGE[0] <= abs(v) <= SPEED_RANGE[1]:
            si = "rad/s" if joint.angular else "m/s"
            given = self.ctx.unit_names.get("speed", si)
            written = f"{v / self.ctx.units['speed']:g} {given}" + (
                f" ({v:g} {si})" if given != si else ""
            )
            s.error(
                f"the speed is {written}; its magnitude must be from "
                f"{SPEED_RANGE[0]:g} to {SPEED_RANGE[1]:g} {si}"
            )
            return None
        if v is None:
            return None
        return MotionLaw(v)

    def _effort(self, f: Entry, joint: Joint) -> float | EffortLaw | None:
        """``effort:`` a number (constant), or one of ``{table: {at, value}}`` (over the
        driver coordinate), ``{motor: {torque, speed, slip}}`` (the linear motor curve
        τ(ω) = torque·[1 + (speed − ω)/(slip·speed)]) or ``{curve: {speed, torque}}``
        (τ tabulated over the driver speed)."""
        unit = "torque" if joint.angular else "force"
        if not f.is_mapping:
            return f.number(unit)
        kinds = EFFORT_KEYS.names
        if not f.check(EFFORT_KEYS):
            return None
        given = [k for k in kinds if f.get(k) is not None]
        if len(given) != 1:
            f.error(
                "give a number, or exactly one of table (over the driver coordinate), "
                "motor (a linear motor curve) or curve (effort over the driver speed)"
            )
            return None
        e = f[given[0]]
        speed_kind = "speed"
        sunit = self.ctx.unit_names.get("speed")
        if (
            given[0] in ("motor", "curve")
            and sunit
            and units.is_angular_speed(sunit) != joint.angular
        ):
            e.error(
                f"the speed unit '{sunit}' (units.speed) does not suit {joint.kind} joint "
                f"'{joint.name}'"
            )
            return None
        if given[0] == "motor":
            if not e.check(EFFORT_KEYS.shapes["motor"]):
                return None
            torque, speed = e["torque"].number(unit), e["speed"].number(speed_kind)
            slip = e["slip"].number(None, minimum=0.0, strict=True)
            if speed is not None and speed == 0.0:
                e["speed"].error("the rated speed must not be zero (its sign gives the sense)")
                return None
            if None in (torque, speed, slip):
                return None
            return EffortLaw("motor", value=torque, speed=speed, slip=slip)
        keys = EFFORT_KEYS.shapes[given[0]].names  # (x, y): at, value or speed, torque
        if not e.check(EFFORT_KEYS.shapes[given[0]]):
            return None
        xs, ys = e[keys[0]].seq(), e[keys[1]].seq()
        if xs is None or ys is None:
            return None
        if len(xs) != len(ys) or len(xs) < 2:
            e.error(
                f"{keys[0]} and {keys[1]} need the same number of entries, at least 2 "
                f"(got {len(xs)} and {len(ys)})"
            )
            return None
        xkind = ("angle" if joint.angular else "length") if given[0] == "table" else speed_kind
        x = [v.number(xkind) for v in xs]
        y = [v.number(unit) for v in ys]
        if any(v is None for v in x + y):
            return None
        if np.any(np.diff(x) <= 0):
            e[keys[0]].error(f"the {keys[0]} values must increase")
            return None
        return EffortLaw(given[0], at=tuple(x), values=tuple(y))

    def _driver_offset(self, e: Entry, joint: Joint, joints, points):
        """(P_i, P_j) names and the offset α_j − α_i of the driver coordinate."""
        i, j = joint.links
        if self.ground is None:  # reported with the links
            return (None, None), None
        chosen: list[str | None] = [None, None]
        if (pe := e.get("points")) is not None:
            names = pe.names(2)
            if None in names:
                return (None, None), None
            chosen = [None if n in ("", "x", "+x") else n for n in names]
        angles = []
        for k, link in enumerate((i, j)):
            pname = chosen[k]
            if pname is None:
                if link == self.ground and k == 0:
                    angles.append(0.0)  # the global +x axis
                    continue
                others = [o for o in joints if link in o.links and o.name != joint.name]
                if len(others) != 1:
                    if not self.broken["joint"] and "joint" not in self.lost:
                        e.error(
                            f"cannot choose the driver's reference point on link '{link}' "
                            f"(it has {len(others)} other joints): give points: [P_i, P_j]"
                        )
                    return (None, None), None
                other = others[0]
                pname = _joint_point(other, link)
                chosen[k] = pname
            c = _joint_point_vec(joint, link)
            if c is None:
                e.error(
                    f"a {joint.kind} joint has no centre on link '{link}' to measure "
                    "the driver's angle about"
                )
                return (None, None), None
            p = e.point(link, pname, points, key="points", index=k)
            if p is None:
                return (None, None), None
            d = p - c
            if not np.hypot(*d) > 0:
                e.error(
                    f"the driver's reference point '{pname}' on link '{link}' "
                    "coincides with the joint centre"
                )
                return (None, None), None
            angles.append(float(np.arctan2(d[1], d[0])))
        return (chosen[0], chosen[1]), angles[1] - angles[0]


def _joint_point(joint: Joint, link: str) -> str:
    """The name of the point of ``link`` that ``joint`` ties (the joint's name where it
    names none there): the default reference point of a driver's angle."""
    return next((a.point for a in joint.anchors() if a.link == link), joint.name)


def _joint_point_vec(joint: Joint, link: str) -> np.ndarray | None:
    """The driven joint's centre on ``link`` (local, m), or None where it has no point there."""
    return next((a.xy for a in joint.anchors() if a.link == link and a.at_joint), None)
