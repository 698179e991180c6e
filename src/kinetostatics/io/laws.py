"""``drivers.<name>.motion`` given as a law: harmonic, polynomial or table, and the
limits of the path it makes the driver travel."""

from __future__ import annotations

import numpy as np

from ..base import units
from ..base.keys import BOOLEAN, NAME, NUMBER, Keys, enum, list_of
from ..base.limits import MAGNITUDE, MAX_LAW_ACCELERATION, MAX_TURNS, SPEED_RANGE
from ..base.spec import Entry
from ..errors import did_you_mean
from ..joints import Joint

# ``motion:`` with a ``law:``, per law (docs/yaml.md); without one, CONSTANT_KEYS
LAW_KEYS = {
    "constant": Keys({"law": NAME, "speed": NUMBER}, required=("speed",)),
    "harmonic": Keys(
        {"law": NAME, "centre": NUMBER, "amplitude": NUMBER, "period": NUMBER, "phase": NUMBER},
        required=("centre", "amplitude", "period"),
    ),
    "polynomial": Keys(
        {"law": NAME, "coefficients": list_of(NUMBER), "duration": NUMBER},
        required=("coefficients", "duration"),
    ),
    "table": Keys(
        {"law": NAME, "time": list_of(NUMBER), "value": list_of(NUMBER), "periodic": BOOLEAN},
        required=("time", "value"),
    ),
}
CONSTANT_KEYS = Keys({"speed": NUMBER}, required=("speed",))
# the shape of ``motion:``: a law's keys where ``law`` is given, else a constant speed
MOTION = {
    "type": "object",
    "if": {"required": ["law"]},
    "then": {
        "properties": {"law": enum(LAW_KEYS)},
        "allOf": [
            {"if": {"properties": {"law": {"const": law}}}, "then": keys}
            for law, keys in LAW_KEYS.items()
        ],
    },
    "else": CONSTANT_KEYS,
}


class LawSections:
    """Reads the motion law of a driver.

    A mixin of :class:`~kinetostatics.io.builder.Builder`: it uses the builder's ``top``, ``ctx``,
    ``problems`` and name bookkeeping (``_claim``, ``_broken``, ``_not_a``).
    """

    def _motion_law(self, m: Entry, joint: Joint, links=()):
        """``motion: {law: constant | harmonic | polynomial | table, ...}`` (see docs/yaml.md)."""
        law = m["law"].text()
        keys = LAW_KEYS
        if law not in keys:
            if law is not None:
                m["law"].error(
                    f"unknown motion law '{law}'{did_you_mean(law, keys)}; "
                    f"expected one of: {', '.join(keys)}"
                )
            return None
        if not m.check(keys[law]):
            return None
        if law == "constant":
            return self._constant_speed(m, joint)
        made = self._law(m, law, joint)
        return None if made is None or not self._law_in_range(m, made, joint, links) else made

    def _law_in_range(self, m: Entry, law, joint: Joint, links=()) -> bool:
        """A motion law's coordinate within :data:`MAGNITUDE`, its peak speed within
        :data:`SPEED_RANGE` (sampled over its duration), as for a constant speed, and the
        path it makes the driver travel within the sweep limits of a constant-speed driver
        (:data:`MAX_TURNS`, :data:`MAX_TRAVEL`): the positions are followed along it."""
        kind, si = ("angle", "rad/s") if joint.angular else ("length", "m/s")
        t = np.linspace(0.0, law.duration, 4097)
        with np.errstate(all="ignore"):
            psi, psi_d, psi_dd = (np.asarray(a, dtype=float) for a in law.value(0.0, t))
            peak = float(np.max(np.abs(psi_d)))
        if (
            not (
                np.all(np.isfinite(psi))
                and np.all(np.isfinite(psi_d))
                and np.all(np.isfinite(psi_dd))
            )
            or not SPEED_RANGE[0] <= peak <= SPEED_RANGE[1]
        ):
            m.error(
                f"the {law.kind} law reaches a speed of {peak:g} {si}; its peak speed must "
                f"be from {SPEED_RANGE[0]:g} to {SPEED_RANGE[1]:g} {si}"
            )
            return False
        if float(np.max(np.abs(psi_dd))) > MAX_LAW_ACCELERATION:
            m.error(
                f"the {law.kind} law reaches an acceleration of "
                f"{float(np.max(np.abs(psi_dd))):g} {si}^2; its magnitude must be at most "
                f"{MAX_LAW_ACCELERATION:g} {si}^2"
            )
            return False
        worst = float(np.max(np.abs(psi)))
        if joint.angular and worst > MAX_TURNS * 2 * np.pi:
            scale = self.ctx.units["angle"]
            unit = self.ctx.unit_names.get("angle", "rad")
            m.error(
                f"the {law.kind} law reaches {worst / scale:g} {unit}; a revolute driver's "
                f"coordinate must stay within ±{MAX_TURNS} turns "
                f"(±{MAX_TURNS * 2 * np.pi / scale:g} {unit}) of 0 (farther, the positions "
                "lose the precision they are solved to)"
            )
            return False
        if worst > MAGNITUDE[kind][1]:
            m.error(
                f"the {law.kind} law reaches {worst:g} {'rad' if joint.angular else 'm'}; "
                f"the magnitude of a driver coordinate must be at most {MAGNITUDE[kind][1]:g}"
            )
            return False
        path = float(np.sum(np.abs(np.diff(psi))))  # the travel, back and forth
        unit = self.ctx.unit_names.get(kind, units.SI_UNITS[kind])
        if problem := self._too_far(path / self.ctx.units[kind], kind, unit, links):
            m.error(
                f"the {law.kind} law moves the driver {path / self.ctx.units[kind]:g} "
                f"{unit} over its {'period' if law.cyclic else 'duration'}, {problem}"
            )
            return False
        return True

    def _law(self, m: Entry, law: str, joint: Joint):
        """The harmonic, polynomial or table law of ``motion:`` (its keys checked)."""
        from ..model.motion import HarmonicLaw, PolynomialLaw, TableLaw  # when a file has one

        kind = "angle" if joint.angular else "length"
        si = "rad" if joint.angular else "m"
        if law == "harmonic":
            centre, amplitude = m["centre"].number(kind), m["amplitude"].number(kind)
            period = m["period"].number("time", minimum=0.0, strict=True)
            phase = m["phase"].number("angle") if m.get("phase") is not None else 0.0
            if amplitude is not None and amplitude == 0.0:
                m["amplitude"].error("the amplitude must not be zero (the driver would not move)")
                return None
            if None in (centre, amplitude, period, phase):
                return None
            return HarmonicLaw(centre, amplitude, period, phase)
        if law == "polynomial":
            items = m["coefficients"].seq()
            duration = m["duration"].number("time", minimum=0.0, strict=True)
            if items is None or duration is None:
                return None
            if not 2 <= len(items) <= 11:
                m["coefficients"].error(
                    f"give from 2 to 11 coefficients c0, c1, … (ψ = c0 + c1·t + "
                    f"c2·t² + …), got {len(items)}"
                )
                return None
            raw = [x.raw_number() for x in items]
            if any(v is None for v in raw):
                return None
            scale, tscale = self.ctx.units[kind], self.ctx.units["time"]
            with np.errstate(all="ignore"):
                coef = tuple(
                    float(np.float64(v) * scale / np.float64(tscale) ** k)
                    for k, v in enumerate(raw)
                )
            for k, (x, c) in enumerate(zip(items, coef)):
                if not np.isfinite(c):  # the law's limits below bound the rest
                    x.error(
                        f"c{k} = {raw[k]:g} is too large: it overflows once converted "
                        f"to SI ({si}/s^{k})"
                    )
                    return None
            if not any(coef[1:]):
                m["coefficients"].error(
                    "the coefficients c1, c2, … are all zero: the driver would not move"
                )
                return None
            return PolynomialLaw(coef, duration)
        t_items, v_items = m["time"].seq(), m["value"].seq()
        periodic = m["periodic"].boolean() if m.get("periodic") is not None else False
        if t_items is None or v_items is None or periodic is None:
            return None
        if len(t_items) != len(v_items) or len(t_items) < 3:
            m.error(
                f"time and value need the same number of entries, at least 3 "
                f"(got {len(t_items)} and {len(v_items)})"
            )
            return None
        times = [x.number("time") for x in t_items]
        values = [x.number(kind) for x in v_items]
        if any(v is None for v in times + values):
            return None
        if np.any(np.diff(times) <= 0):
            m["time"].error("the times must increase")
            return None
        if periodic and abs(values[-1] - values[0]) > 1e-12 * max(map(abs, values)):
            m["value"].error(
                f"a periodic table must end where it starts: first value "
                f"{values[0]:g} {si}, last {values[-1]:g} {si} (SI)"
            )
            return None
        if periodic:
            values[-1] = values[0]  # equal to round-off (the unit conversion): made exact
        if np.ptp(values) == 0.0:
            m["value"].error("all values are equal: the driver would not move")
            return None
        try:
            return TableLaw(tuple(times), tuple(values), bool(periodic))
        except ValueError as exc:  # the spline refuses the points
            m.error(f"the table cannot be interpolated: {exc}")
            return None
