"""The YAML keys of a ``cam`` pair that place its follower and set its design (``cam.py``
reads the rest): ``translating:``, ``oscillating:``, ``rotation`` and ``rise`` senses, and
``design: {pressure_angle_max}``, the allowable pressure angle of the cam's design."""

from __future__ import annotations

import math

from ..base.keys import NUMBER, VECTOR, Keys, enum

__all__ = ["SENSES", "allowed_angle", "placement"]

SENSES = {"ccw": 1, "cw": -1}
_SENSE = enum(SENSES)
_TRANSLATING = Keys({"direction": VECTOR, "offset": NUMBER}, required=("direction",))
_OSCILLATING = Keys(
    {"pivot": VECTOR, "arm": NUMBER, "offset": NUMBER, "rise": _SENSE}, required=("pivot",)
)
_DESIGN = Keys({"pressure_angle_max": NUMBER}, required=("pressure_angle_max",))


def allowed_angle(design) -> float | None | bool:
    """``design: {pressure_angle_max: [α]}``: the allowable pressure angle (rad, from
    the file's angle unit), strictly between 0° and 90°; None: no ``design:``; False:
    refused (reported at its key)."""
    if design is None:
        return None
    if not design.check(_DESIGN):
        return False
    value = design["pressure_angle_max"].number("angle")
    if value is None:
        return False
    if not 0.0 < value < 0.5 * math.pi:
        design["pressure_angle_max"].error(
            f"the allowable pressure angle must lie strictly between 0° and 90°, got "
            f"{math.degrees(value):g}°"
        )
        return False
    return float(value)


def placement(entry, kind):
    """(u, e or f, A, L, κ) from ``translating:`` or ``oscillating:``."""
    tr, osc = entry.get("translating"), entry.get("oscillating")
    if (tr is None) == (osc is None):
        entry.error("give the follower's placement: translating or oscillating")
        return None
    if tr is not None:
        if not tr.check(_TRANSLATING):
            return None
        d = tr["direction"].vector(None)
        u = None if d is None else tr["direction"].unit(d)
        e = tr["offset"].number("length") if tr.get("offset") is not None else 0.0
        if u is None or e is None or (kind == "flat" and e):
            if kind == "flat" and e:
                tr["offset"].error("a translating flat face has no offset (it changes nothing)")
            return None
        return (float(u[0]), float(u[1])), float(e), None, 0.0, 1
    need = ("pivot",) if kind == "flat" else ("pivot", "arm")
    extra = ("offset", "rise") if kind == "flat" else ("rise",)
    if not osc.check_keys(required=need, optional=extra):
        return None
    a = osc["pivot"].vector("length")
    arm = osc["arm"].number("length", minimum=0.0, strict=True) if kind != "flat" else 0.0
    off = osc["offset"].number("length") if osc.get("offset") is not None else 0.0
    kappa = SENSES.get(osc["rise"].text() or "", 0) if osc.get("rise") is not None else 1
    if not kappa:
        osc["rise"].error("rise must be ccw or cw (the arm's sense as the follower rises)")
    if a is None or arm is None or off is None or not kappa:
        return None
    return None, float(off), (float(a[0]), float(a[1])), float(arm), kappa
