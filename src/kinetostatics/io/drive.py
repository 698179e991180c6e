"""The ``drive:`` section: the motor of a revolute motion driver and its reduction, read
into ``Model.drive`` (:class:`~kinetostatics.model.DriveSpec`).  Sized and checked against
the cycle by :mod:`kinetostatics.dynamics.drive` (docs/drive.md)."""

from __future__ import annotations

from ..base.keys import BOOLEAN, NAME, NUMBER, Keys
from ..model import DriveSpec

__all__ = ["DRIVE_KEYS", "MOTOR_KEYS", "REDUCTION_KEYS", "DriveSection"]

REDUCTION_KEYS = Keys({"ratio": NUMBER, "efficiency": NUMBER, "inertia": NUMBER})
MOTOR_KEYS = Keys(
    {
        "rated_torque": NUMBER,
        "peak_torque": NUMBER,
        "rated_speed": NUMBER,
        "inertia": NUMBER,
    }
)
DRIVE_KEYS = Keys(
    {"driver": NAME, "friction": BOOLEAN, "reduction": REDUCTION_KEYS, "motor": MOTOR_KEYS}
)


class DriveSection:
    """Reads ``drive:``.

    A mixin of :class:`~kinetostatics.io.builder.Builder`: it uses the builder's ``top``,
    ``ctx``, ``problems`` and name bookkeeping (``_broken``, ``_not_a``).
    """

    def _drive(self, joints, drivers, flywheel) -> DriveSpec | None:
        """``drive: {driver, friction, reduction: {ratio, efficiency, inertia}, motor:
        {rated_torque, peak_torque, rated_speed, inertia}}`` (docs/drive.md)."""
        d = self.top.get("drive")
        if d is None or not d.mapping() or not d.check(DRIVE_KEYS):
            return None
        ok = True
        driver = self._drive_driver(d, joints, drivers)
        ok &= driver is not False
        friction = None
        if d.get("friction") is not None:
            friction = d["friction"].boolean()
            ok &= friction is not None
        red = self._part(d, "reduction", REDUCTION_KEYS)
        mot = self._part(d, "motor", MOTOR_KEYS)
        ok &= red is not None and mot is not None
        red, mot = red or {}, mot or {}
        ratio = efficiency = None
        if "ratio" in red:
            ratio = red["ratio"].number(None, minimum=0.0, strict=True)
            ok &= ratio is not None
            if (
                ratio is not None
                and flywheel is not None
                and flywheel.ratio is not None
                and abs(ratio - flywheel.ratio) > 1e-12 * ratio
            ):
                red["ratio"].error(
                    f"the reduction ratio {ratio:g} differs from flywheel.ratio "
                    f"{flywheel.ratio:g}: both are motor speed / crank speed; give one"
                )
                ok = False
        if "efficiency" in red:
            efficiency = red["efficiency"].number(None, minimum=0.0, strict=True)
            if efficiency is not None and efficiency > 1.0:
                red["efficiency"].error(
                    f"the efficiency of the reduction must be in (0, 1], got {efficiency:g}"
                )
                efficiency = None
            ok &= efficiency is not None
        values = {}
        for key, e, kind in (
            ("gear_inertia", red.get("inertia"), "inertia"),
            ("motor_inertia", mot.get("inertia"), "inertia"),
            ("rated_torque", mot.get("rated_torque"), "torque"),
            ("peak_torque", mot.get("peak_torque"), "torque"),
            ("rated_speed", mot.get("rated_speed"), "speed"),
        ):
            if e is None:
                continue
            strict = kind != "inertia"  # a rating must be positive; an inertia may be 0
            values[key] = e.number(kind, minimum=0.0, strict=strict)
            ok &= values[key] is not None
        rated, peak = values.get("rated_torque"), values.get("peak_torque")
        if rated is not None and peak is not None and peak < rated:
            mot["peak_torque"].error(
                "the peak torque must be at least the rated torque "
                f"({peak / self.ctx.units['torque']:g} < {rated / self.ctx.units['torque']:g})"
            )
            ok = False
        if not ok:
            return None
        return DriveSpec(
            driver=driver,
            friction=friction,
            ratio=ratio,
            efficiency=1.0 if efficiency is None else efficiency,
            gear_inertia=values.get("gear_inertia") or 0.0,
            motor_inertia=values.get("motor_inertia") or 0.0,
            rated_torque=rated,
            peak_torque=peak,
            rated_speed=values.get("rated_speed"),
            where=d.where,
        )

    def _part(self, d, key: str, keys: Keys):
        """The entries of ``drive.<key>`` (``{}`` when absent), None when it is malformed."""
        e = d.get(key)
        if e is None:
            return {}
        if not e.mapping() or not e.check(keys):
            return None
        return dict(e.items())

    def _drive_driver(self, d, joints, drivers):
        """The name of the motion driver the motor turns (None: the first), or False after
        reporting why it cannot be: not a motion driver, not on a revolute, ``balance_at``."""
        motion = [x for x in drivers if x.motion is not None]
        names = [x.name for x in motion]
        e = d.get("driver")
        name = None if e is None else e.text()
        if e is not None and name is None:
            return False
        if name is not None and name not in names:
            if self._broken("driver", name):
                return False
            e.error(self._not_a("motion driver", name, names))
            return False
        where = e if e is not None else d
        if not motion:
            if "driver" not in self.lost and not self.broken["driver"]:
                where.error("a drive needs a motion driver (the motor turns a driven shaft)")
            return False
        chosen = next(x for x in motion if x.name == (name or names[0]))
        joint = next((j for j in joints if j.name == chosen.joint), None)
        if joint is None:
            return False
        if not joint.angular:
            where.error(
                f"driver '{chosen.name}' drives {joint.kind} joint '{joint.name}': a drive "
                "sizes a rotary motor, on a revolute motion driver"
            )
            return False
        if chosen.balance_at:
            where.error(
                f"driver '{chosen.name}' reports its effort at '{chosen.balance_at}' "
                "(balance_at): the drive needs the torque at the driven joint itself"
            )
            return False
        return name
