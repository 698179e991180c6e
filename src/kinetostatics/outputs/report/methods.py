"""The chapters of the graded methods: the balancing moment three ways, the instant centres
and the cam's design.  Each formats its entry of methods.json (the dict of the methods'
stage, which the report's caller passes: an output does not compute it); the pictures
read the same dict (``plotting/centres.py``, ``plotting/cam.py``)."""

from __future__ import annotations

import math

from ..labels import link_numbers
from ..lang import tr
from ..plotting.cam import cam_diagrams, cam_drawing
from ..plotting.centres import centre_label, centres_figure
from .blocks import _Heading, _Para, _Table

ROUND_OFF = 1e-9  # a centre's coordinate below this (m), a moment below this × the largest: 0


def _g(v, digits: int = 6) -> str:
    """A number to ``digits`` significant digits; "–" for none (null in methods.json)."""
    return "–" if v is None or not math.isfinite(v) else f"{v + 0.0:.{digits}g}"  # no −0


def _xy(v, scale: float = 1.0, digits: int = 4) -> str:
    return "" if v is None else f"{_g(scale * v[0], digits)}, {_g(scale * v[1], digits)}"


def _small(v, scale: float):
    """``v``, or 0 where it is round-off (≤ ROUND_OFF × ``scale``, the chapter's largest)."""
    return 0.0 if v is not None and abs(v) <= ROUND_OFF * scale else v


def _term_row(t: dict, scale: float) -> list[str]:
    """A lever term: load, link, force, point, turned force, image point, moment."""
    if t["kind"] == "force":
        cells = [_xy(t["force"]), _xy(t["point"], 1e3), _xy(t["turned"]), _xy(t["image"])]
    elif t["kind"] == "couple":
        cells = [f"M = {_g(t['couple'], 4)} N·m", "", "", f"ω = {_g(t['omega'], 4)} rad/s"]
    else:  # a spring's, damper's or effort driver's power: its moment only
        cells = ["", "", "", ""]
    return [t["name"], t["link"], *cells, _g(_small(t["moment"], scale))]


def lever_blocks(bm: dict, lang: str = "en", number: int = 9) -> list:
    """Blocks of chapter ``number`` from methods.json's ``balancing_moment`` entry
    (``BalancingMoment.to_dict()``)."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    unit = bm["unit"].replace("*", "·")
    blocks: list = [
        _Heading(2, T("{n}. The balancing moment, three ways", n=number)),
        _Para(
            T(
                "The balancing effort {effort} of the driver {driver} (at its pair {joint}) "
                "checked twice. Joukowski's lever (杠杆法): every load turned by +90° "
                "(counter-clockwise) and applied at the image of its point in the velocity "
                "polygon (image in m/s, pole at the origin); its moment about the pole is "
                "image × turned force = F·v, a couple M on a link turning at ω gives M·ω. The "
                "polygon is in equilibrium with the driver's M_b·ω₁. The power method (功率法): "
                "M_b·ω₁ + Σ(F·v + M·ω) = 0 from the loads' generalized forces. Columns: F the "
                "load (N), P its point (mm), F′ the force turned by +90° (N), p its image "
                "(= v_P, m/s), M_p = p × F′ its moment about the pole (W = N·m/s).",
                effort=bm["effort"],
                driver=bm["driver"],
                joint=bm["joint"],
            )
        ),
    ]
    if bm.get("friction"):
        blocks.append(
            _Para(
                T(
                    "The lever and power methods are frictionless: they are compared with "
                    "the frictionless column {effort}.",
                    effort=bm["effort"],
                )
            )
        )
    header = [T("load"), T("link"), "F, N", "P, mm", "F′, N", "p, m/s", "M_p, W"]
    # the scales of round-off: the largest moment on the lever, the largest M_b
    moments = max((abs(t["moment"] or 0.0) for p in bm["positions"] for t in p["terms"]),
                  default=0.0)  # fmt: skip
    top = max((abs(v or 0.0) for p in bm["positions"] for v in p["M_b"].values()), default=0.0)
    for k, p in enumerate(bm["positions"], start=1):
        mb, rel = p["M_b"], p["relative_difference"]
        rows = [_term_row(t, moments) for t in p["terms"]]
        rows.append([T("sum"), "", "", "", "", "", _g(_small(p["lever_sum"], moments))])
        blocks += [
            _Heading(3, T("{n}.{k} Position {pos} (φ = {phi}°)", n=number, k=k,
                          pos=p["label"], phi=_g(p["coordinate"], 5))),
            _Table(header, rows, T("Position {pos}: the lever's terms", pos=p["label"])),
            _Para(
                T(
                    "M_b by the lever = {lever} {unit}, by the power method = {power} {unit}, "
                    "from the solution = {solution} {unit} (ω₁ = {speed}); relative "
                    "differences: lever–solution {e1}, power–solution {e2}, lever–power {e3}.",
                    lever=_g(_small(mb["lever"], top)), power=_g(_small(mb["power"], top)),
                    solution=_g(_small(mb["solution"], top)), unit=unit,
                    speed=_g(p["speed"], 5),
                    e1=_g(rel["lever_solution"], 2), e2=_g(rel["power_solution"], 2),
                    e3=_g(rel["lever_power"], 2),
                )
            ),
        ]  # fmt: skip
    return blocks


def _direction(c: dict, lang: str) -> str:
    """The direction a centre at infinity lies along (deg from +x, in [0, 180))."""
    if not c["at_infinity"] or c["xy"] is None:
        return ""
    angle = math.degrees(math.atan2(c["xy"][1], c["xy"][0])) % 180.0
    return tr("; at infinity along {angle}°", lang, angle=f"{angle:.1f}")


def _how(c: dict, numbers: dict, lang: str) -> str:
    """How a centre was found, in the reader's words."""
    if c["how"] == "joint":
        text = tr("pair {joint} ({kind})", lang, joint=c["joint"], kind=tr(c["kind"], lang))
        return text + _direction(c, lang)
    if c["how"] == "kennedy":
        lines = [f"{centre_label(a, numbers)}–{centre_label(b, numbers)}" for a, b in c["lines"]]
        if c["joint"]:  # the normal of a higher pair
            lines.append(c["joint"])
        return tr("Kennedy: {lines}", lang, lines=" × ".join(lines)) + _direction(c, lang)
    groups = ", ".join(c["groups"])  # the Assur groups that hide it
    return tr("not found", lang) + (f" ({groups})" if groups else "")


def _where(c: dict) -> tuple[str, str]:
    """x, y in mm (0 below 1e-9 m: round-off); "∞" for a centre at infinity."""
    if c["xy"] is None:
        return "–", "–"
    if c["at_infinity"]:
        return "∞", "∞"
    x, y = (0.0 if abs(v) < ROUND_OFF else 1e3 * v for v in c["xy"])
    return _g(x, 5), _g(y, 5)


def centres_blocks(
    centres: dict,
    result,
    image,
    lang: str = "en",
    number: int = 10,
    dpi: float = 110,
    drawn=None,
) -> list:
    """Blocks of chapter ``number`` from methods.json's ``instant_centres`` entry
    (``{label: InstantCentres.to_dict()}``): at each position the table of the centres,
    and the drawing at the positions ``drawn`` (labels; None: all);
    ``image(fig, name, caption, true_scale)`` saves a figure as a block."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    numbers = link_numbers(result.system)
    blocks: list = [
        _Heading(2, T("{n}. Instant centres", n=number)),
        _Para(
            T(
                "The N(N−1)/2 instant centres (速度瞬心) P_ij: a pair gives its own (a pin's "
                "centre; a slide's lies at infinity normal to it), Kennedy's theorem (三心定理) "
                "the others, each where two lines through known centres (or the normal of a "
                "higher pair) meet. Coordinates in mm in the frame's axes; a centre at "
                "infinity is given by its direction. The velocities the centres give are "
                "checked against the analysis."
            )
        ),
    ]
    header = ["P_ij", T("bodies"), T("found how"), "x, mm", "y, mm"]
    for k, (label, ic) in enumerate(centres.items(), start=1):
        tag = label.replace("′", "p").replace("/", "_t")
        rows = [
            [centre_label(c["bodies"], numbers), " – ".join(c["bodies"]),
             _how(c, numbers, lang), *_where(c)]
            for c in ic["centres"]
        ]  # fmt: skip
        blocks.append(_Heading(3, T("{n}.{k} Position {pos}", n=number, k=k, pos=label)))
        if drawn is None or label in drawn:
            blocks.append(
                image(
                    centres_figure(result, ic, dpi=dpi, lang=lang),
                    f"centres_{tag}",
                    T("Position {pos}: the instant centres with the mechanism.", pos=label),
                    True,
                )
            )
        blocks += [
            _Table(header, rows, T("Position {pos}: instant centres", pos=label)),
            _Para(
                T(
                    "{found} of {total} centres found; from ω of {ref} = {omega} rad/s the "
                    "centres give every body's ω and velocity within {err} (relative) of "
                    "the analysis.",
                    found=ic["found"], total=ic["total"], ref=ic["reference"],
                    omega=_g(ic["omega_reference"], 5), err=_g(ic["max_error"], 2),
                )
            ),
        ]  # fmt: skip
    return blocks


def _method(method: str, lang: str) -> str:
    """How r_b,min was found: the record's words (its reason in English only)."""
    head, _, why = method.partition(": ")
    return tr(head, lang) + (f": {why}" if why and lang == "en" else "")


ALLOWED_FROM = {
    "file": "the file (the cam joint's design: pressure_angle_max)",
    "default": "the default: the textbook's 30° (give the cam joint "
    "design: pressure_angle_max for another)",
    "caller": "the caller",
}


def _cam_rows(d: dict, lang: str) -> list[list[str]]:
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    mm = lambda v: _g(None if v is None else 1e3 * v, 5)  # noqa: E731
    curve = "profile" if d["follower"] == "flat" else "pitch curve"  # a flat face's own
    rows = [
        [T("base radius (file)"), "r_b", mm(d["base_radius"]), "mm"],
        [T("allowable pressure angle"), "[α]", _g(d["allowed"], 4), "°"],
        [T("[α] from"), "", T(ALLOWED_FROM.get(d.get("allowed_from", ""), "")), ""],
        [T("largest pressure angle"), "|α|max", _g(d["peak"], 5), "°"],
        [T("… at the cam angle"), "φ", _g(d["peak_at"], 5), "°"],
        [T(f"least radius of curvature of the {curve}"), "ρ_min", mm(d["curvature_min"]),
         "mm"],
        [T("… at the cam angle"), "φ", _g(d["curvature_at"], 5), "°"],
        [T("least base radius for [α]"), "r_b,min", mm(d["base_radius_min"]), "mm"],
        [T("found by"), "", _method(d["method"], lang), ""],
        [T("the file's base radius keeps |α| ≤ [α]"), "", T("yes" if d["satisfied"] else "no"),
         ""],
    ]  # fmt: skip
    if d["roller_limit"] is not None:
        ok = "yes" if d["roller_radius"] < d["roller_limit"] else "no"
        rows[1:1] = [[T("roller radius (file)"), "r_r", mm(d["roller_radius"]), "mm"]]
        rows[8:8] = [
            [T("roller limit (no undercut: r_r < ρ_min)"), "ρ_min", mm(d["roller_limit"]), "mm"],
            [T("the file's roller is below the limit"), "", T(ok), ""],
        ]
    return rows


def cam_blocks(cams, image, lang: str = "en", number: int = 11, dpi: float = 110) -> list:
    """Blocks of chapter ``number`` from methods.json's ``cam_design`` entry (a list of
    ``CamDesign.to_dict()``, or a dict of them by joint); none without a cam."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    cams = list(cams.values()) if isinstance(cams, dict) else list(cams)
    if not cams:
        return []
    blocks: list = [
        _Heading(2, T("{n}. The cam's design", n=number)),
        _Para(
            T(
                "From the cam's own law and dimensions: the follower's s–φ, v–φ, a–φ diagrams "
                "(per unit cam speed: v = ω·ds/dφ, a = ω²·d²s/dφ²), the pressure angle α(φ) at "
                "the file's base radius, the least radius of curvature of the pitch curve "
                "(the roller must be smaller), the least base radius for the allowable "
                "pressure angle [α], and the cam drawn at a round scale."
            )
        ),
    ]
    header = [T("quantity"), T("symbol"), T("value"), T("unit")]
    for k, d in enumerate(cams, start=1):
        joint = d["joint"]
        what = T("{motion} {follower} follower", motion=T(d["motion"]),
                 follower=T(d["follower"]))  # fmt: skip
        blocks += [
            _Heading(3, T("{n}.{k} Cam {joint} ({what})", n=number, k=k, joint=joint,
                          what=what)),
            _Table(header, _cam_rows(d, lang), T("Cam {joint}", joint=joint)),
            image(
                cam_diagrams(d, dpi=dpi, lang=lang),
                f"cam_{joint}_diagrams",
                T("Cam {joint}: s–φ, v–φ, a–φ diagrams and the pressure angle α–φ.",
                  joint=joint),
            ),
            image(
                cam_drawing(d, dpi=dpi, lang=lang),
                f"cam_{joint}_profile",
                T("Cam {joint}: the working profile and the pitch curve at the scale μ_l.",
                  joint=joint),
                True,
            ),
        ]  # fmt: skip
    return blocks
