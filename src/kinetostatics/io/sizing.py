"""The sizing keys of ``links:`` and ``joints:`` (docs/sizing.md): a pin joint's
``bearing:`` and ``pin:``, a link's ``section:`` and ``material:``, read into
``Model.sizing`` (:class:`~kinetostatics.model.sizing.SizingSpec`).

Lengths are in the file's length unit, forces in its force unit, strengths and pressures
in force/length² (N and mm: MPa), speeds in length/s.  Impossible data (a zero width, a
negative rating, a tube thicker than its radius) is one line naming the key.
"""

from __future__ import annotations

from ..base.keys import NUMBER, TEXT, Keys
from ..base.spec import Entry
from ..joints.revolute import BEARING_KEYS, PIN_KEYS
from ..model.sizing import (
    BEARING_TYPES,
    SECTION_SHAPES,
    SHEAR_PLANES,
    BearingSpec,
    MaterialSpec,
    PinSpec,
    SectionSpec,
    SizingSpec,
)

__all__ = ["SECTION_KEYS", "MATERIAL_KEYS", "SizingSections"]

SECTION_KEYS = Keys(
    {
        "shape": TEXT,
        **{k: NUMBER for dims in SECTION_SHAPES.values() for k in dims},
    },
    required=("shape",),
)
MATERIAL_KEYS = Keys({"S_ut": NUMBER, "S_y": NUMBER, "S_e": NUMBER})


def _stress_scale(e: Entry) -> float:
    """SI factor of a stress written in the file's force/length² (N/mm²: 1e6)."""
    return e.ctx.units["force"] / e.ctx.units["length"] ** 2


def _positive(e: Entry, kind: str | None, scale: float = 1.0) -> float | None:
    """A strictly positive number of ``kind`` (times ``scale``), None after a problem."""
    v = e.number(kind, minimum=0.0, strict=True)
    return None if v is None else v * scale


class SizingSections:
    """Reads the sizing keys of the links and joints into ``self.sizing`` (a dict of four
    dicts).  A mixin of :class:`~kinetostatics.io.builder.Builder`."""

    def _sizing_start(self) -> None:
        self.sizing = {"bearings": {}, "pins": {}, "sections": {}, "materials": {}}

    def _sizing_spec(self) -> SizingSpec | None:
        s = self.sizing
        if not any(s.values()):
            return None
        return SizingSpec(**{k: dict(v) for k, v in s.items()})

    # -- joints --------------------------------------------------------------
    def _joint_sizing(self, names: list[str], e: Entry) -> bool:
        """``bearing:`` and ``pin:`` of the joint entry ``e`` for each revolute of
        ``names`` (a pin shared by three links: each of its revolutes); False after a
        problem (reported)."""
        ok = True
        if (b := e.get("bearing")) is not None:
            spec = self._bearing(b)
            ok &= spec is not None
            for n in names:
                self.sizing["bearings"][n] = spec
        if (p := e.get("pin")) is not None:
            spec = self._pin_spec(p)
            ok &= spec is not None
            for n in names:
                self.sizing["pins"][n] = spec
        return ok

    def _bearing(self, b: Entry) -> BearingSpec | None:
        if not b.check(BEARING_KEYS):
            return None
        kind = b["type"].text()
        if kind is None:
            return None
        if kind not in BEARING_TYPES:
            b["type"].error(f"unknown bearing type '{kind}'; expected one of: ball, roller, plain")
            return None
        stress = _stress_scale(b)
        kinds = {
            "C": ("force", 1.0),
            "width": ("length", 1.0),
            "diameter": ("length", 1.0),
            "p_max": (None, stress),
            "v_max": (None, b.ctx.units["length"]),
            "pv_max": (None, stress * b.ctx.units["length"]),
        }
        values, ok = {}, True
        for key, (unit, scale) in kinds.items():
            if (k := b.get(key)) is not None:
                values[key] = _positive(k, unit, scale)
                ok &= values[key] is not None
        need = ("C",) if kind != "plain" else ("width", "diameter")
        for key in need:
            if key not in values:
                b.error(
                    f"a {kind} bearing needs {' and '.join(need)} "
                    f"({'its dynamic load rating' if kind != 'plain' else 'its length and bore'})"
                )
                return None
        return BearingSpec(kind, where=b.where, **values) if ok else None

    def _pin_spec(self, p: Entry) -> PinSpec | None:
        if not p.check(PIN_KEYS):
            return None
        d = _positive(p["diameter"], "length")
        shear = "single"
        if (s := p.get("shear")) is not None:
            shear = s.text()
            if shear is not None and shear not in SHEAR_PLANES:
                s.error(f"unknown shear '{shear}'; expected single or double")
                shear = None
        width = None
        if (w := p.get("eye_width")) is not None:
            width = _positive(w, "length")
            if width is None:
                return None
        if d is None or shear is None:
            return None
        return PinSpec(d, shear, width, p.where)

    # -- links ---------------------------------------------------------------
    def _link_sizing(self, name: str, e: Entry) -> bool:
        """``section:`` and ``material:`` of link ``name``; False after a problem."""
        ok = True
        if (s := e.get("section")) is not None:
            spec = self._section(s)
            ok &= spec is not None
            if spec is not None:
                self.sizing["sections"][name] = spec
        if (m := e.get("material")) is not None:
            spec = self._material(m)
            ok &= spec is not None
            if spec is not None:
                self.sizing["materials"][name] = spec
        return ok

    def _section(self, s: Entry) -> SectionSpec | None:
        if not s.check(SECTION_KEYS):
            return None
        shape = s["shape"].text()
        if shape is None:
            return None
        if shape not in SECTION_SHAPES:
            s["shape"].error(
                f"unknown section shape '{shape}'; expected one of: {', '.join(SECTION_SHAPES)}"
            )
            return None
        dims, ok = {}, True
        for key in s.keys():
            if key != "shape" and key not in SECTION_SHAPES[shape]:
                s.error(f"a {shape} section takes {', '.join(SECTION_SHAPES[shape])}, not {key}")
                ok = False
        for key in SECTION_SHAPES[shape]:
            dims[key] = _positive(s.require(key), "length")
            ok &= dims[key] is not None
        if not ok:
            return None
        unit = (s.ctx.unit_names.get("length", "m"), s.ctx.units["length"])
        if problem := _section_problem(shape, dims, unit):
            key, message = problem
            s[key].error(message)
            return None
        return SectionSpec(shape, dims, s.where)

    def _material(self, m: Entry) -> MaterialSpec | None:
        if not m.check(MATERIAL_KEYS):
            return None
        scale, values, ok = _stress_scale(m), {}, True
        for key in MATERIAL_KEYS.names:
            if (k := m.get(key)) is not None:
                values[key] = _positive(k, None, scale)
                ok &= values[key] is not None
        if not ok:
            return None
        su, sy = values.get("S_ut"), values.get("S_y")
        if su is not None and sy is not None and sy > su:
            m["S_y"].error(
                f"the yield strength S_y exceeds the ultimate strength S_ut "
                f"({sy / scale:g} > {su / scale:g})"
            )
            return None
        return MaterialSpec(where=m.where, **values)


def _section_problem(shape: str, d: dict[str, float], unit) -> tuple[str, str] | None:
    """(key, message) of a section that cannot be made, or None; ``unit``: the file's
    length unit (name, SI factor) for the message."""
    name, scale = unit
    if shape == "tube" and d["thickness"] > d["diameter"] / 2:
        return "thickness", (
            f"a tube's wall ({d['thickness'] / scale:g} {name}) is thicker than its radius "
            f"({d['diameter'] / 2 / scale:g} {name})"
        )
    if shape == "I" and 2 * d["flange"] >= d["height"]:
        return "flange", "an I section's two flanges are as deep as its height, or deeper"
    if shape == "I" and d["web"] > d["width"]:
        return "web", "an I section's web is wider than its flanges"
    return None
