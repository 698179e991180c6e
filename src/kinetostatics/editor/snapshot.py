"""The JSON document of one analysis: what the page draws, over every analysed row.

:func:`snapshot` reads a :class:`~kinetostatics.analysis.results.Result` (the same
``analyze`` as ``run``) and gathers, in the order of the driver's travel: the positions of
every joint and point, the links' outlines, the sliders and guides (the geometry of the
drawings, :mod:`kinetostatics.outputs.plotting.scene`), the loads of the free-body view
(reactions, inertia forces and couples, weights, external loads, the balancing effort;
without and with friction) and their force scale, the friction circles, the sketch's
targets, the paths of the moving pins, the curves (the driving effort, every joint's
reaction, the output's motion) and the self-checks.  Lengths in m, forces in N (the
model's SI units, as the result's columns); a value that is not a finite number is null
and named under ``non_finite`` (:func:`~kinetostatics.base.files.json_text`).
"""

from __future__ import annotations

import numpy as np

from ..base.units import nice_scale
from ..kinematics.start import sketch_distances
from ..outputs.labels import reaction_symbol
from ..outputs.lang import tr
from ..outputs.plotting.curves import _driver_effort, output_motion
from ..outputs.plotting.rows import _sorted, link_numbers
from ..outputs.plotting.scene import (
    _glyph,
    _joint_point,
    _pose,
    _Scene,
    _to_global,
    scene_guides,
)
from ..outputs.plotting.style import FORCE_COLORS, PictureError
from .loads import arrows

__all__ = ["snapshot", "FAR_SKETCH", "FORCE_SHARE"]

FAR_SKETCH = 0.05  # a sketched point this × L_ref from where it assembled is drawn red
FORCE_SHARE = 0.3  # the largest force of the cycle is drawn about this × the drawing's span


def _xy(a) -> np.ndarray:
    """(n, 2) points (m)."""
    return np.asarray(a, float).reshape(-1, 2)


def _rounded(value, decimals: int):
    """Every float array in ``value`` rounded to ``decimals`` (a shorter document; the
    caller picks the decimals far below what is drawn or compared)."""
    if isinstance(value, dict):
        return {k: _rounded(v, decimals) for k, v in value.items()}
    if isinstance(value, list):
        return [_rounded(v, decimals) for v in value]
    if isinstance(value, np.ndarray) and value.dtype.kind == "f":
        return np.round(value, decimals)
    return value


def _joints_points(result, order) -> dict:
    """Each joint's point (where its reaction acts) and each moving link's named points."""
    model = result.system.model
    ground = model.ground.name
    joints = []
    for j in model.joints:
        at = _joint_point(result, j)
        if at is None:
            continue
        joints.append(
            {
                "name": j.name,
                "links": list(j.links),
                "pin": bool(j.pin),
                "ground": ground in j.links,
                "xy": _xy(np.asarray(at)[order]),
            }
        )
    points = [
        {
            "name": f"{lk.name}.{p}",
            "link": lk.name,
            "xy": _xy(_to_global(result, lk.name, xy)[order]),
        }
        for lk in model.links
        for p, xy in lk.points.items()
        if lk.name != ground
    ]
    return {"joints": joints, "points": points}


def _links_blocks(result, scene, order) -> dict:
    """The moving links' outlines (bars, plates) and the sliders."""
    model = result.system.model
    numbers = link_numbers(result.system)
    links = []
    for n, pts in scene.outline_local.items():
        ends = [np.asarray(_to_global(result, n, p))[order] for p in pts]
        links.append(
            {
                "name": n,
                "number": numbers.get(n),
                "color": scene.colors[n],
                "plate": n in scene.plates,
                "outline": np.stack(ends, axis=1),  # (rows, vertices, 2)
            }
        )
    blocks = []
    for j in model.joints:
        g = _glyph(result, j)
        if g.block is None:
            continue
        blocks.append(
            {
                "joint": j.name,
                "link": g.block.link,
                "color": scene.colors.get(g.block.link, "#555555"),
                "length": scene.block_len[j.name],
                "height": scene.block_h[j.name],
                "centre": _xy(np.asarray(g.block.centre)[order]),
                "direction": _xy(np.asarray(g.block.direction)[order]),
            }
        )
    return {"links": links, "blocks": blocks}


def _wheels(result, scene, order) -> list:
    """Pitch circles and lines at each row; a cam's profile in its link's frame with the
    link's pose (x, y, θ in rad) at each row."""
    wheels = []
    for kind, name, link, p, q in scene.wheels_local:
        if kind == "curve":
            pose = np.asarray(_pose(result, link))[order]
            curve = {"kind": kind, "joint": name, "link": link, "a": _xy(p), "b": pose}
            wheels.append({**curve, "closed": bool(q)})
            continue
        a = np.asarray(_to_global(result, link, p))[order]
        b = q if kind == "circle" else _xy(np.asarray(_to_global(result, link, q))[order])
        wheels.append({"kind": kind, "joint": name, "link": link, "a": _xy(a), "b": b})
    return wheels


def _geometry(result, scene, order) -> dict:
    """Joints, points, outlines, sliders, guides, pivots, wheels and centres of mass at
    each row of ``order``."""
    guides = [
        {"joint": g.joint, "start": list(g.start), "end": list(g.end), "half": g.half_width}
        for g in scene_guides(scene)
    ]
    com = {n: _xy(np.asarray(c)[order]) for n, c in _coms(result, result.system.model).items()}
    return {
        **_joints_points(result, order),
        **_links_blocks(result, scene, order),
        "guides": guides,
        "pivots": {k: list(v) for k, v in scene.pivots.items()},
        "wheels": _wheels(result, scene, order),
        "com": com,
    }


def _coms(result, model) -> dict:
    return {
        n: _to_global(result, n, np.zeros(2)) for n in result.system.links if model.link(n).mass > 0
    }


def _loads(result, order, span: float) -> dict:
    """The free-body view's loads (:mod:`.loads`) over the rows, without and with
    friction, and the force scale ``mu`` (N per mm of the drawing) that draws the cycle's
    largest force about FORCE_SHARE of the drawing's span."""
    friction = "friction.status" in result.columns
    out: dict = {"kinds": FORCE_COLORS}
    biggest = 0.0
    for key, on in (("plain", False), ("friction", True)):
        if on and not friction:
            out[key] = None
            continue
        out[key] = []
        for a in arrows(result, friction=on):
            act = a.active[order]
            if a.force is not None and act.any():
                mags = np.hypot(*np.asarray(a.force)[order][act].T)
                biggest = max(biggest, float(np.nanmax(mags, initial=0.0)))
            out[key].append(
                {
                    "kind": a.kind,
                    "label": a.label,
                    "at": np.asarray(a.at, float)[order],
                    "force": None if a.force is None else np.asarray(a.force, float)[order],
                    "moment": None if a.moment is None else np.asarray(a.moment, float)[order],
                    "active": act,
                }
            )
    out["mu"] = nice_scale(biggest / max(FORCE_SHARE * span * 1e3, 1e-12))  # N/mm
    return out


def _friction_circles(result, order) -> list:
    """The friction circle of each pin with friction at each row: radius = the friction
    couple over the reaction with friction (the circle the reaction's line touches)."""
    out = []
    for j in result.system.model.joints:
        m, fx, fy = (f"{j.name}.friction", f"{j.name}.Fx_friction", f"{j.name}.Fy_friction")
        if not j.pin or m not in result.columns or result.units.get(m) != "N*m":
            continue
        big = np.hypot(result[fx], result[fy])
        peak = float(np.max(big, where=np.isfinite(big), initial=0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.where(big > 1e-9 * max(peak, 1e-300), np.abs(result[m]) / big, np.nan)
        at = _joint_point(result, j)
        out.append({"joint": j.name, "xy": _xy(np.asarray(at)[order]), "radius": r[order]})
    return out


def _sketch(result) -> list:
    """The sketch's targets: where each was written, and how far the start pose put it."""
    system = result.system
    starts = np.nonzero(np.abs(result.t) <= 1e-12)[0]
    if not len(starts) or not system.model.sketch:
        return []
    l_ref = float(np.max(system.l_ref))
    far = {
        sp.key: float(np.max(sp.distance)) for sp in sketch_distances(system, result.q[starts[0]])
    }
    return [
        {
            "key": key,
            "xy": list(np.asarray(pos, float)),
            "distance": far.get(key),
            "far": bool(far.get(key, 0.0) > FAR_SKETCH * l_ref),
        }
        for key, pos in system.model.sketch.items()
    ]


def _curves(result, order, lang: str) -> dict:
    """The driving effort (without, with friction), each joint's reaction (magnitude) and
    the output's position, velocity and acceleration, in the order of the travel."""
    d, word, unit = _driver_effort(result, None)
    effort = {"name": d.name, "word": word, "unit": unit, "series": []}
    for suffix, label in (("", "without friction"), ("_friction", "with friction, consistent")):
        key = f"{d.name}.{word}{suffix}"
        if key in result.columns:
            effort["series"].append({"label": tr(label, lang), "y": np.asarray(result[key])[order]})
    nums = link_numbers(result.system)
    reactions = []
    for j in result.system.model.joints:
        if f"{j.name}.Fx" not in result.columns:
            continue
        mag = lambda s, n=j.name: np.hypot(result[f"{n}.Fx{s}"], result[f"{n}.Fy{s}"])[order]
        series = [{"label": tr("without friction", lang), "y": mag("")}]
        if f"{j.name}.Fx_friction" in result.columns:
            series.append({"label": tr("with friction, consistent", lang), "y": mag("_friction")})
        reactions.append(
            {
                "joint": j.name,
                "symbol": reaction_symbol(j.links, nums),
                "unit": "N",
                "series": series,
            }
        )
    try:
        out = output_motion(result, lang=lang)
        motion = {
            "name": out["name"],
            "kind": out.get("kind"),
            "series": [
                {"label": label, "unit": u, "y": np.asarray(y)[order]}
                for label, u, y in out["series"]
                if np.ndim(y) == 1
            ],
        }
    except PictureError:  # no output member (no slide or swing on the frame): no curves
        motion = None
    return {"effort": effort, "reactions": reactions, "output": motion}


def _driver(result, order) -> dict:
    """The first motion driver: its joint, its moving link's angle per row (deg) and, for
    a pivot on the frame, that pivot (the page turns the link by dragging it)."""
    d = result.system.motion_drivers[0]
    ground = result.system.model.ground.name
    j = d.joint
    moving = [n for n in j.links if n != ground]
    pivot = None
    if j.angular and j.pin and ground in j.links and moving:
        pivot = list(np.asarray(_joint_point(result, j))[0])
    theta = result[f"{moving[0]}.theta"][order] if moving else None
    return {
        "name": d.name,
        "joint": j.name,
        "link": moving[0] if moving else None,
        "angular": bool(j.angular),
        "pivot": pivot,
        "theta": theta,
    }


def snapshot(result, *, paths=(), lang: str = "en") -> dict:
    """The page's document of ``result`` (module docstring); ``paths``: the points
    (``link.point``) whose paths are drawn."""
    x, order, xlabel = _sorted(result, lang)
    scene = _Scene(result, paths)
    span = float(np.max(scene.hi - scene.lo))
    model = result.system.model
    angle = result["angle"][order] if "angle" in result.columns else x
    # positions to 1e-13 of the drawing's span, forces to 1e-9 of the largest force
    lengths = int(np.ceil(13 - np.log10(max(span, 1e-300))))
    loads = _loads(result, order, span)
    forces = int(np.ceil(9 - np.log10(max(loads["mu"] * FORCE_SHARE * span * 1e3, 1e-300))))
    loads = {k: _rounded(v, lengths if k == "at" else forces) for k, v in loads.items()}
    loads["plain"], loads["friction"] = (
        None if v is None else [{**a, "at": np.round(a["at"], lengths)} for a in v]
        for v in (loads["plain"], loads["friction"])
    )
    return {
        "name": model.name,
        "rows": len(order),
        "row": np.asarray(order).tolist(),
        "x": x,
        "xlabel": xlabel,
        "angle": angle,
        "time": result["time"][order],
        "bounds": [*scene.lo.tolist(), *scene.hi.tolist()],
        "span": span,
        "l_ref": float(np.max(result.system.l_ref)),
        "ground": model.ground.name,
        **_rounded(_geometry(result, scene, order), lengths),
        "paths": {k: _xy(v[order]) for k, v in scene.paths.items()},
        "loads": loads,
        "friction_circles": _rounded(_friction_circles(result, order), lengths),
        "sketch": _sketch(result),
        "curves": _curves(result, order, lang),
        "driver": _driver(result, order),
        "checks": {"line": result.checks.line(), "ok": bool(result.checks.ok)},
    }
