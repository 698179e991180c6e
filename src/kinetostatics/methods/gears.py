r"""The gears' geometry: the gear chapter of a course design (docs/methods.md, "The gears").

For each toothed pair of a file (``type: gear`` or ``type: rack``; the pair tells its teeth,
pitch radii, pressure angle, addendum, clearance and shift coefficients through
``Joint.gear_data()``), the standard involute geometry with its formulas:

    module             m = 2r/z
    pitch radius       r = m z/2
    base radius        r_b = r cos α
    tip radius         r_a = r + (h_a* + x − Δy) m        (annulus: r − (h_a* − x) m)
    root radius        r_f = r − (h_a* + c* − x) m        (annulus: r + (h_a* + c* + x) m)
    pitch              p = π m,   base pitch p_b = p cos α
    tooth thickness    s = π m/2 + 2 x m tan α            (on the pitch circle)
    centre distance    a = m (z_1 ± z_2)/2                (+ external, − internal)
    working angle      inv α' = inv α + 2 tan α (x_1 + x_2)/(z_1 + z_2),   a' = a cos α / cos α'
                       y = (a' − a)/m,   Δy = x_1 + x_2 − y   (the tip reduction)
    contact ratio      ε_α = [z_1 (tan α_a1 − tan α') ± z_2 (tan α_a2 − tan α')]/(2π),
                       α_a = arccos(r_b/r_a); with a rack the second term is 4(h_a* − x_1)/sin 2α
    undercut           z_min = 2 h_a*/sin²α (17 at 20°, rounded as the textbook does),
                       x_min = h_a* (z_min − z)/z_min

The file's pitch circles are the reference circles (its pitch radii are in the ratio of the
teeth, one module).  A profile shift whose sum is not zero makes the pair work at α' and a'
(no backlash); the motion, which depends only on the ratio, is the same, and the joint's line
of action stays at the reference α.  A rack's shift is its pinion's; an internal pair takes
no shift (the reader refuses one).  Lengths in the record are SI (m), angles rad; the
formulas print lengths in the file's length unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..base.units import factor
from ..joints.gearing import GearData
from ..model import Model

__all__ = [
    "GearGeometry",
    "Gears",
    "Wheel",
    "gear_geometry",
    "involute",
    "inverse_involute",
    "pair_geometry",
]


def involute(alpha: float) -> float:
    """inv α = tan α − α."""
    return math.tan(alpha) - alpha


def inverse_involute(value: float) -> float:
    """The angle α in [0, π/2) with inv α = ``value`` ≥ 0 (Newton from a cube-root start)."""
    if value <= 0.0:
        return 0.0
    a = min((3.0 * value) ** (1.0 / 3.0), 1.5)  # inv α ≈ α³/3 for small α
    for _ in range(60):
        step = (involute(a) - value) / math.tan(a) ** 2  # d(inv α)/dα = tan²α
        a = min(max(a - step, 0.5 * a), 0.5 * (a + 0.5 * math.pi))
        if abs(step) <= 1e-15 * a:
            break
    return a


@dataclass(frozen=True)
class Wheel:
    """One gear of a pair (lengths m, angles rad).  ``x_min`` and ``undercut`` are None
    for an annulus (no undercut limit applies to internal teeth)."""

    link: str
    teeth: int
    shift: float
    annulus: bool
    r: float  # pitch (reference) radius
    r_b: float  # base radius
    r_a: float  # tip radius
    r_f: float  # root radius
    s: float  # tooth thickness on the pitch circle
    alpha_a: float  # pressure angle at the tip
    x_min: float | None  # the least shift that avoids undercut
    undercut: bool | None

    def to_dict(self) -> dict:
        return {
            "link": self.link,
            "teeth": self.teeth,
            "shift": self.shift,
            "annulus": self.annulus,
            "pitch_radius": self.r,
            "base_radius": self.r_b,
            "tip_radius": self.r_a,
            "root_radius": self.r_f,
            "tooth_thickness": self.s,
            "tip_pressure_angle": math.degrees(self.alpha_a),
            "x_min": self.x_min,
            "undercut": self.undercut,
        }


@dataclass(frozen=True)
class GearGeometry:
    """The involute geometry of one toothed pair (lengths m, angles rad).

    ``wheels`` are the pair's gears in the joint's link order (a rack pair: its pinion
    only).  ``centre_distance`` is the standard a = m(z_1 ± z_2)/2 (a rack pair: the
    pinion's centre above the rack's reference line, r + x m), ``centre_distance_file``
    the one the file's pitch radii give (r_1 ± r_2; a rack pair: r), ``working_*`` the
    working pressure angle and centre distance (equal to the reference ones without a
    shift sum).  ``formulas`` are ``(key, text)`` pairs, each a formula with its value
    (lengths in ``length_unit``); ``notes`` are sentences for the reader, each an English
    template and its values (``template.format(**values)``), so that a report translates
    the template.
    """

    joint: str
    mesh: str  # external, internal or rack
    module: float
    alpha: float
    addendum: float
    clearance: float
    wheels: tuple[Wheel, ...]
    pitch: float
    base_pitch: float
    centre_distance: float
    centre_distance_file: float
    working_alpha: float
    working_centre_distance: float
    tip_reduction: float  # Δy
    contact_ratio: float
    z_min_exact: float
    z_min: int
    formulas: tuple[tuple[str, str], ...]
    notes: tuple[tuple[str, tuple[tuple[str, str], ...]], ...]
    length_unit: str

    def to_dict(self) -> dict:
        """JSON-safe: lengths in m, angles in degrees (``units``), the formulas as text."""
        return {
            "units": {"length": "m", "angle": "deg"},
            "mesh": self.mesh,
            "module": self.module,
            "pressure_angle": math.degrees(self.alpha),
            "addendum_coefficient": self.addendum,
            "clearance_coefficient": self.clearance,
            "wheels": [w.to_dict() for w in self.wheels],
            "pitch": self.pitch,
            "base_pitch": self.base_pitch,
            "centre_distance": self.centre_distance,
            "centre_distance_file": self.centre_distance_file,
            "working_pressure_angle": math.degrees(self.working_alpha),
            "working_centre_distance": self.working_centre_distance,
            "tip_reduction": self.tip_reduction,
            "contact_ratio": self.contact_ratio,
            "z_min_exact": self.z_min_exact,
            "z_min": self.z_min,
            "formulas": dict(self.formulas),
            "notes": [
                {"text": t.format(**dict(v)), "template": t, "values": dict(v)}
                for t, v in self.notes
            ],
            "formula_length_unit": self.length_unit,
        }


@dataclass(frozen=True)
class Gears:
    """The gear chapter of a file: one :class:`GearGeometry` per toothed pair, and the
    pairs whose geometry is unknown (``incomplete``: (joint, why), a rack's pinion given
    by its radius without its teeth)."""

    pairs: tuple[GearGeometry, ...] = ()
    incomplete: tuple[tuple[str, str], ...] = ()

    def to_dict(self) -> dict:
        """What methods.json holds under ``gears``: each pair's record by its joint's name."""
        return {
            "pairs": {p.joint: p.to_dict() for p in self.pairs},
            "incomplete": dict(self.incomplete),
        }


def gear_geometry(source) -> Gears:
    """The involute geometry of every toothed pair of a model or a result.

    Parameters
    ----------
    source : Model or Result
        The file's model, or a result (its system's model): the geometry reads only the
        pairs' tooth data, none of the rows.

    Returns
    -------
    Gears
        One record per pair with its teeth known (empty for a file without gears).
    """
    model = source if isinstance(source, Model) else source.system.model
    unit = model.units.get("length", "m")
    pairs, incomplete = [], []
    for joint in model.joints:
        data = joint.gear_data()
        if data is None:
            continue
        if None in [z for z, r in zip(data.teeth, data.radii, strict=True) if r is not None]:
            incomplete.append((data.joint, NO_TEETH))
            continue
        pairs.append(pair_geometry(data, unit))
    return Gears(tuple(pairs), tuple(incomplete))


def _z_min(addendum: float, alpha: float) -> tuple[float, int]:
    """(2 h_a*/sin²α, rounded to the nearest whole number as the textbook does)."""
    exact = 2.0 * addendum / math.sin(alpha) ** 2
    return exact, int(math.floor(exact + 0.5))


def _wheel(data: GearData, k: int, m: float, annulus: bool, dy: float) -> Wheel:
    """Gear ``k`` (its link's place in the pair) with the tip reduction Δy."""
    z, x, r = data.teeth[k], data.shift[k], data.radii[k]
    ha, c, alpha = data.addendum, data.clearance, data.alpha
    r_b = r * math.cos(alpha)
    if annulus:
        r_a, r_f = r - (ha - x) * m, r + (ha + c + x) * m
        s = 0.5 * math.pi * m - 2.0 * x * m * math.tan(alpha)
        x_min, undercut = None, None
    else:
        r_a, r_f = r + (ha + x - dy) * m, r - (ha + c - x) * m
        s = 0.5 * math.pi * m + 2.0 * x * m * math.tan(alpha)
        z_min = _z_min(ha, alpha)[1]
        x_min = ha * (z_min - z) / z_min
        undercut = x < x_min - 1e-12
    alpha_a = math.acos(min(r_b / r_a, 1.0))
    return Wheel(data.links[k], z, x, annulus, r, r_b, r_a, r_f, s, alpha_a, x_min, undercut)


def _working(data: GearData, m: float) -> tuple[float, float, float, float]:
    """(a, α', a', Δy): the standard centre distance, the working pressure angle and
    centre distance, the tip reduction (a rack pair: the pinion centre's height)."""
    alpha = data.alpha
    if data.mesh == "rack":
        r, x = data.radii[1], data.shift[1]
        return r + x * m, alpha, r + x * m, 0.0
    z1, z2 = data.teeth
    if data.mesh == "internal":
        return abs(z1 - z2) * m / 2.0, alpha, abs(z1 - z2) * m / 2.0, 0.0
    a = (z1 + z2) * m / 2.0
    x_sum = data.shift[0] + data.shift[1]
    if x_sum == 0.0:
        return a, alpha, a, 0.0
    alpha_w = inverse_involute(involute(alpha) + 2.0 * math.tan(alpha) * x_sum / (z1 + z2))
    a_w = a * math.cos(alpha) / math.cos(alpha_w)
    return a, alpha_w, a_w, x_sum - (a_w - a) / m


def _contact_ratio(data: GearData, wheels: tuple[Wheel, ...], alpha_w: float) -> float:
    """ε_α = Σ ±z (tan α_a − tan α')/(2π), + for external teeth, − for an annulus; a rack's
    term is 4(h_a* − x)/sin 2α."""
    total = sum(
        (-1.0 if w.annulus else 1.0) * w.teeth * (math.tan(w.alpha_a) - math.tan(alpha_w))
        for w in wheels
    )
    if data.mesh == "rack":
        total += 4.0 * (data.addendum - data.shift[1]) / math.sin(2.0 * data.alpha)
    return total / (2.0 * math.pi)


def pair_geometry(data: GearData, unit: str = "mm") -> GearGeometry:
    """The involute geometry of one pair whose teeth are known, its formulas printed with
    lengths in ``unit``."""
    places = [k for k in (0, 1) if data.radii[k] is not None]
    m = 2.0 * data.radii[places[0]] / data.teeth[places[0]]
    a, alpha_w, a_w, dy = _working(data, m)
    annulus = None
    if data.mesh == "internal":
        annulus = 0 if data.radii[0] > data.radii[1] else 1
    wheels = tuple(_wheel(data, k, m, k == annulus, dy) for k in places)
    if data.mesh == "rack":
        a_file = data.radii[1]
    else:
        r1, r2 = data.radii
        a_file = abs(r1 - r2) if data.mesh == "internal" else r1 + r2
    eps = _contact_ratio(data, wheels, alpha_w)
    z_exact, z_min = _z_min(data.addendum, data.alpha)
    record = GearGeometry(
        data.joint, data.mesh, m, data.alpha, data.addendum, data.clearance, wheels,
        math.pi * m, math.pi * m * math.cos(data.alpha), a, a_file, alpha_w, a_w, dy, eps,
        z_exact, z_min, (), (), unit,
    )  # fmt: skip
    return replace(record, formulas=_formulas(record), notes=_notes(record))


# -- the formulas as text --------------------------------------------------------------------
def _printer(unit: str):
    """(length, angle, number): a length in ``unit``, an angle in degrees, a number, as text."""
    scale = factor("length", unit)
    return (
        lambda v: f"{v / scale:.5g} {unit}",
        lambda v: f"{math.degrees(v):.5g}°",
        lambda v: f"{v:.5g}",
    )


def _wheel_formulas(g: GearGeometry, n: int, w: Wheel) -> list[tuple[str, str]]:
    """The formulas of gear ``n`` (1 or 2, in the record's order)."""
    L, A, N = _printer(g.length_unit)
    dy = " − Δy" if g.tip_reduction else ""
    if w.annulus:
        tip, root = f"r_{n} − (h_a* − x_{n})m", f"r_{n} + (h_a* + c* + x_{n})m"
        thickness = f"πm/2 − 2x_{n} m tan α"
    else:
        tip, root = f"r_{n} + (h_a* + x_{n}{dy})m", f"r_{n} − (h_a* + c* − x_{n})m"
        thickness = f"πm/2 + 2x_{n} m tan α"
    out = [
        (f"z_{n}", f"z_{n} = {w.teeth}"),
        (f"x_{n}", f"x_{n} = {N(w.shift)}"),
        (f"r_{n}", f"r_{n} = m z_{n}/2 = {L(w.r)}"),
        (f"r_b{n}", f"r_b{n} = r_{n} cos α = {L(w.r_b)}"),
        (f"r_a{n}", f"r_a{n} = {tip} = {L(w.r_a)}"),
        (f"r_f{n}", f"r_f{n} = {root} = {L(w.r_f)}"),
        (f"s_{n}", f"s_{n} = {thickness} = {L(w.s)}"),
        (f"alpha_a{n}", f"α_a{n} = arccos(r_b{n}/r_a{n}) = {A(w.alpha_a)}"),
    ]
    if w.x_min is not None:
        out.append((f"x_min{n}", f"x_min{n} = h_a*(z_min − z_{n})/z_min = {N(w.x_min)}"))
    return out


def _centre_formulas(g: GearGeometry) -> list[tuple[str, str]]:
    """The centre distances and the working pressure angle."""
    L, A, N = _printer(g.length_unit)
    if g.mesh == "rack":
        return [
            ("a", f"H = r_1 + x_1 m = {L(g.centre_distance)}"),
            ("a_file", f"H_file = r_1 = {L(g.centre_distance_file)}"),
        ]  # fmt: skip
    if g.mesh == "internal":
        i, o = (1, 2) if g.wheels[1].annulus else (2, 1)
        out = [
            ("a", f"a = m(z_{o} − z_{i})/2 = {L(g.centre_distance)}"),
            ("a_file", f"a_file = r_{o} − r_{i} = {L(g.centre_distance_file)}"),
        ]
    else:
        out = [
            ("a", f"a = m(z_1 + z_2)/2 = {L(g.centre_distance)}"),
            ("a_file", f"a_file = r_1 + r_2 = {L(g.centre_distance_file)}"),
        ]
    if g.working_alpha != g.alpha:
        y = (g.working_centre_distance - g.centre_distance) / g.module
        out += [
            ("alpha_w", "inv α' = inv α + 2 tan α (x_1 + x_2)/(z_1 + z_2) → "
                        f"α' = {A(g.working_alpha)}"),
            ("a_w", f"a' = a cos α / cos α' = {L(g.working_centre_distance)}"),
            ("y", f"y = (a' − a)/m = {N(y)}"),
            ("dy", f"Δy = x_1 + x_2 − y = {N(g.tip_reduction)}"),
        ]  # fmt: skip
    return out


def _formulas(g: GearGeometry) -> tuple[tuple[str, str], ...]:
    """Every value of the record with its formula, in the order of the chapter."""
    L, A, N = _printer(g.length_unit)
    out = [
        ("m", f"m = 2r_1/z_1 = {L(g.module)}"),
        ("alpha", f"α = {A(g.alpha)}"),
        ("h_a*", f"h_a* = {N(g.addendum)}"),
        ("c*", f"c* = {N(g.clearance)}"),
    ]
    for n, w in enumerate(g.wheels, start=1):
        out += _wheel_formulas(g, n, w)
    out += [
        ("p", f"p = πm = {L(g.pitch)}"),
        ("p_b", f"p_b = p cos α = {L(g.base_pitch)}"),
    ]
    out += _centre_formulas(g)
    aw = "α'" if g.working_alpha != g.alpha else "α"
    if g.mesh == "rack":
        eps = "[z_1(tan α_a1 − tan α) + 4(h_a* − x_1)/sin 2α]/(2π)"
    else:
        sign = "−" if g.mesh == "internal" else "+"
        terms = [f"z_{n}(tan α_a{n} − tan {aw})" for n in (1, 2)]
        if g.wheels[0].annulus:
            terms.reverse()
        eps = f"[{terms[0]} {sign} {terms[1]}]/(2π)"
    out.append(("epsilon", f"ε_α = {eps} = {N(g.contact_ratio)}"))
    out.append(("z_min", f"z_min = 2h_a*/sin²α = {N(g.z_min_exact)} ≈ {g.z_min}"))
    return tuple(out)


def _notes(g: GearGeometry) -> tuple[tuple[str, tuple[tuple[str, str], ...]], ...]:
    """What the reader should know of the pair, as (template, values): undercut, a contact
    ratio below 1, the working centre distance of a shifted pair, the annulus."""
    L, A, N = _printer(g.length_unit)
    out = []
    for n, w in enumerate(g.wheels, start=1):
        if w.undercut:
            values = {"n": n, "link": w.link, "x": N(w.shift), "x_min": N(w.x_min)}
            values |= {"z": w.teeth, "z_min": g.z_min}
            out.append((UNDERCUT, values))
    if g.contact_ratio < 1.0:
        out.append((DISCONTINUOUS, {"eps": N(g.contact_ratio)}))
    if g.working_alpha != g.alpha:
        out.append((WORKING, {"alpha_w": A(g.working_alpha), "a_w": L(g.working_centre_distance)}))
    if any(w.annulus for w in g.wheels):
        out.append((ANNULUS, {}))
    return tuple((t, tuple((k, str(v)) for k, v in values.items())) for t, values in out)


# the notes' templates (the report translates them; outputs/zh.py)
UNDERCUT = (
    "gear {n} ({link}) is undercut: x_{n} = {x} < x_min{n} = {x_min} (z_{n} = {z}, "
    "z_min = {z_min}); a shift x_{n} ≥ {x_min} avoids it"
)
DISCONTINUOUS = (
    "ε_α = {eps} < 1: one pair of teeth leaves before the next engages (the mesh is not continuous)"
)
WORKING = (
    "the shifted pair works at α' = {alpha_w} and a' = {a_w} without backlash; the file's "
    "pitch circles are the reference circles, and the motion, which reads only the ratio, is "
    "the same"
)
NO_TEETH = (
    "the pinion's number of teeth is not given (key teeth): its module and tooth geometry "
    "are unknown"
)
ANNULUS = "the annulus has no undercut limit; the interference of internal teeth is not checked"
