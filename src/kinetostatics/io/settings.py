"""The sections that set up a run: ``sketch:``, ``analysis:``, ``loops:`` and
``flywheel:``."""

from __future__ import annotations

import numpy as np

from ..base import units
from ..base.keys import BOOLEAN, NUMBER, Keys, list_of, whole
from ..base.limits import MAX_POSITIONS, MAX_TRAVEL, MAX_TURNS
from ..base.spec import Entry
from ..errors import did_you_mean
from ..model import Analysis, Driver, FlywheelSpec

FLYWHEEL_KEYS = Keys({"delta": NUMBER, "ratio": NUMBER, "friction": BOOLEAN}, required=("delta",))
ANALYSIS_KEYS = Keys(
    {
        "start": NUMBER,
        "sweep": NUMBER,
        "positions": whole(1, MAX_POSITIONS),
        "at": list_of(NUMBER),
        "events": BOOLEAN,
    }
)


class SettingSections:
    """Reads ``sketch:``, ``analysis:``, ``loops:`` and ``flywheel:``.

    A mixin of :class:`~kinetostatics.io.builder.Builder`: it uses the builder's ``top``, ``ctx``,
    ``problems`` and name bookkeeping (``_claim``, ``_broken``, ``_not_a``).
    """

    def _flywheel(self) -> FlywheelSpec | None:
        """``flywheel: {delta, ratio, friction}``: size a flywheel for δ (see docs/dynamics.md)."""
        f = self.top.get("flywheel")
        if f is None or not f.check(FLYWHEEL_KEYS):
            return None
        delta = f["delta"].number(None, minimum=0.0, strict=True)
        if delta is not None and not delta < 1.0:
            f["delta"].error(f"the coefficient of speed fluctuation must be below 1, got {delta:g}")
            delta = None
        ratio = None
        if f.get("ratio") is not None:
            ratio = f["ratio"].number(None, minimum=0.0, strict=True)
            if ratio is None:
                return None
        friction = f["friction"].boolean() if f.get("friction") is not None else False
        if delta is None or friction is None:
            return None
        return FlywheelSpec(delta, ratio, bool(friction), f.where)

    def _sketch(self, links, joints) -> dict[str, np.ndarray]:
        section = self.top.get("sketch")
        if section is None or not section.mapping():
            return {}
        out = {}
        by_joint = [j.name for j in joints]
        pts = {link.name: link.points for link in links}
        for ref, e in section.items():
            where = section.key_where(ref)
            if "." in ref:
                if not self._point_ref(Entry(e.node, where, self.ctx), ref, pts):
                    continue
            elif ref in self.pins:  # a pin places all its revolutes
                v = e.vector("length")
                for gen in self.pins[ref] if v is not None else ():
                    out[gen] = v
                    self.sketch_where[gen] = where
                continue
            elif ref not in by_joint:
                if self._broken("joint", ref):
                    continue
                what = self._what(ref)
                head = (
                    f"'{ref}' is a {what}, not a joint"
                    if what and what != "joint"
                    else f"unknown joint '{ref}'{did_you_mean(ref, by_joint)}"
                )
                self.problems.add(
                    where,
                    f"{head}: a sketch key is a joint name ({', '.join(by_joint)}) or link.point",
                )
                continue
            v = e.vector("length")
            if v is not None:
                out[ref] = v
                self.sketch_where[ref] = where
        return out

    def _analysis(self, joints, drivers, links=()) -> Analysis:
        a = self.top.get("analysis")
        motion = [d for d in drivers if d.motion is not None]
        if motion and motion[0].motion.own_run:
            return self._law_analysis(a, motion[0])
        if a is None or not a.check(ANALYSIS_KEYS):
            return Analysis()
        by_name = {j.name: j for j in joints}
        kind = "angle" if not motion or by_name[motion[0].joint].angular else "length"
        unit = self.ctx.unit_names.get(kind, units.SI_UNITS[kind])
        start = a["start"].number(kind) if a.get("start") is not None else 0.0
        sweep = None if kind == "length" else 2 * np.pi
        if (se := a.get("sweep")) is not None:
            raw = se.raw_number()
            sweep = None if raw is None else raw * self.ctx.units[kind]
            if raw is not None and not raw > 0:
                se.error(
                    f"the sweep must be positive, got {raw:g} {unit} (it is measured in "
                    "the sense of motion, which the sign of the driver's speed gives)"
                )
                sweep = None
            elif raw is not None and (problem := self._too_far(raw, kind, unit, links)):
                se.error(f"the sweep is {raw:g} {unit}, {problem}")
                sweep = None
        elif kind == "length":
            a.error("a prismatic driver needs analysis.sweep (the travel to analyse)")
        if kind == "angle" and start is not None:
            start = self._within_turns(
                a["start"] if a.get("start") is not None else a, start, "the start", unit
            )
            sense = np.sign(motion[0].motion.speed) if motion else 1.0
            if (
                start is not None
                and sweep is not None
                and (se := a.get("sweep")) is not None
                and self._within_turns(
                    se, start + sense * sweep, "the end of the sweep (start + sweep)", unit
                )
                is None
            ):
                sweep = None
        n = self._positions(a)
        at: tuple[float, ...] = ()
        if (ae := a.get("at")) is not None and (items := ae.seq()) is not None:
            vals = [e.number(kind, bounded=kind == "angle") for e in items]  # lengths: below
            if kind == "angle":
                vals = [
                    None if v is None else self._within_turns(e, v, "the position", unit)
                    for e, v in zip(items, vals)
                ]
            if kind == "length" and start is not None:
                for e, v in zip(items, vals):
                    scale = self.ctx.units[kind]
                    if v is not None and (
                        problem := self._too_far((v - start) / scale, kind, unit, links)
                    ):
                        e.error(
                            f"{v / scale:g} {unit} is {abs(v - start) / scale:g} {unit} "
                            f"from analysis.start ({start / scale:g} {unit}), {problem}"
                        )
            at = tuple(v for v in vals if v is not None)
        events = a["events"].boolean() if a.get("events") is not None else False
        return Analysis(start or 0.0, sweep or 2 * np.pi, n, at, bool(events))

    def _within_turns(self, e: Entry, value: float, what: str, unit: str) -> float | None:
        """``value`` (rad), a revolute driver's coordinate in a run, if within ±MAX_TURNS
        turns of 0: farther, its rounding (|value| × 2.2e-16) approaches the tolerance of the
        position solver (1e-12) and the positions no longer converge."""
        limit = MAX_TURNS * 2 * np.pi
        if abs(value) <= limit * (1 + 1e-12):
            return value
        scale = self.ctx.units["angle"]
        e.error(
            f"{what} is {value / scale:g} {unit}; a revolute driver's coordinate must stay "
            f"within ±{MAX_TURNS} turns (±{limit / scale:g} {unit}) of 0 over the run "
            "(farther, the positions lose the precision they are solved to)"
        )
        return None

    def _positions(self, a: Entry) -> int:
        """``analysis.positions`` (default 360)."""
        if (pe := a.get("positions")) is not None:
            v = pe.number(None)
            if v is not None and (v != int(v) or not 1 <= v <= MAX_POSITIONS):
                pe.error(f"positions must be a whole number from 1 to {MAX_POSITIONS}, got {v:g}")
            elif v is not None:
                return int(v)
        return 360

    def _law_analysis(self, a: Entry | None, driver: Driver) -> Analysis:
        """``analysis`` when the first driver follows a motion law: the law fixes where the run
        starts and what it covers, so only ``positions`` and ``events`` apply."""
        if a is None or not a.check(ANALYSIS_KEYS):
            return Analysis(driver.motion.start)
        for key in ("start", "sweep", "at"):
            if a.get(key) is not None:
                self.ctx.problems.add(
                    a.key_where(key),
                    f"{key} does not apply: driver '{driver.name}' follows a "
                    f"{driver.motion.kind} motion law, which gives the coordinate at every time "
                    f"(the run covers {'one period' if driver.motion.cyclic else 'its duration'}; "
                    "set analysis.positions, or analyze(..., times=...))",
                )
        n = self._positions(a)
        events = a["events"].boolean() if a.get("events") is not None else False
        return Analysis(driver.motion.start, 2 * np.pi, n, (), bool(events))

    def _too_far(self, raw: float, kind: str, unit: str, links) -> str | None:
        """Why a driver-coordinate range ``raw`` (file units) is too long to analyse, if it is:
        the path is followed in steps of 30 degrees, or of 30 degrees x the largest link."""
        span = abs(raw) * self.ctx.units[kind]
        if kind == "angle":
            if span > MAX_TURNS * 2 * np.pi:
                return (
                    f"more than the limit of {MAX_TURNS} turns "
                    f"({MAX_TURNS * 2 * np.pi / self.ctx.units[kind]:g} {unit})"
                )
            return None
        spans = [
            float(np.hypot(*np.ptp(np.array(list(link.points.values())), axis=0)))
            for link in links
            if len(link.points) > 1
        ]
        size = max(spans, default=0.0)
        if size == 0.0:
            return (
                "but no link has two points: the mechanism has no size to measure the "
                "travel of a prismatic driver by"
            )
        if span > MAX_TRAVEL * size:
            scale = self.ctx.units[kind]
            return (
                f"more than the limit of {MAX_TRAVEL} times the largest link "
                f"({size / scale:g} {unit})"
            )
        return None

    def _loops(self, joints):
        section = self.top.get("loops")
        if section is None or (items := section.seq()) is None:
            return None
        names = [j.name for j in joints]
        loops = []
        for e in items:
            seq = e.seq()
            if seq is None:
                continue
            loop = []
            for x in seq:
                t = x.text()
                if t is not None and t not in names and not self._broken("joint", t):
                    x.error(self._not_a("joint", t, names))
                loop.append(t)
            loops.append(tuple(loop))
        return tuple(loops)
