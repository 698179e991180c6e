"""The results sections: the summary over the cycle (section 3), the tables at the
course-design positions (section 5: rows of results.csv to 5 significant digits) and
the peak reactions; every angle of a position is the driver angle φ in [0, 360)°."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...base.units import factor
from ..labels import column_label, link_numbers, member, numbered
from ..lang import tr, tr_unit
from ..summary import ROUND_OFF
from .blocks import _Heading, _List, _Table

# -- numbers -------------------------------------------------------------------------
GROUP = 9  # data columns per printed table: wider tables are split into column groups


def _fmt(v: float, scale: float) -> str:
    """5 significant digits; round-off below 1e-9 of the column's scale prints as 0;
    missing values (self-locking) as an empty cell."""
    if not np.isfinite(v):
        return ""
    if abs(v) <= ROUND_OFF * scale:
        return "0"
    return f"{v:.5g}"


def _unit(u: str) -> str:
    return u.replace("*", "·").replace("^2", "²")


def length_unit(model) -> tuple[str, float]:
    """The file's length unit and its size in m (``("mm", 1e-3)``; SI when none)."""

    u = model.units.get("length", "m") if model.units else "m"
    return u, factor("length", u)


@dataclass
class Column:
    """A printed column: name, unit, values over all rows (already in the printed unit)."""

    name: str
    unit: str
    values: np.ndarray


def _csv_column(result, name: str) -> Column:
    return Column(name, _unit(result.units[name]), np.asarray(result[name], dtype=float))


def _key_column(result) -> Column:
    """The position angle: the first driver's coordinate φ in [0, 360) deg (``angle``),
    or its stroke for a prismatic driver (in the file's length unit)."""
    if "angle" in result.columns:
        return _csv_column(result, "angle")
    u, f = length_unit(result.system.model)
    return Column("stroke", u, np.asarray(result["stroke"], dtype=float) / f)


def _angle(deg) -> np.ndarray:
    """Angles in [0, 360) deg (an unwrapped link angle −390° is 330°)."""
    a = np.mod(np.asarray(deg, dtype=float), 360.0)
    return np.where(a >= 360.0 - 1e-9, 0.0, a)


def _split(header: list[str], body: list[list[str]], keys: int, caption: str) -> list[_Table]:
    """Column groups of at most GROUP data columns, each repeating the ``keys`` first."""
    n = len(header) - keys
    if n <= GROUP:
        return [_Table(header, body, caption)]
    parts = -(-n // GROUP)
    size = -(-n // parts)
    out = []
    for p in range(parts):
        cols = list(range(keys)) + list(
            range(keys + p * size, min(keys + (p + 1) * size, len(header)))
        )
        out.append(
            _Table(
                [header[c] for c in cols],
                [[r[c] for c in cols] for r in body],
                f"{caption} ({p + 1}/{parts})",
            )
        )
    return out


def _header(result, c: Column, lang: str) -> str:
    """A column's head: its CSV name in English (the reader finds it in results.csv); in
    Chinese the quantity, the member and the symbol (``构件4 角速度 ω₄ (rad/s)``)."""
    if lang == "en":
        return f"{c.name} ({c.unit})"
    return f"{column_label(result.system, c.name, lang)} ({tr_unit(c.unit, lang)})"


def _table(
    result, rows: list[tuple[str, int]], columns: list[Column], caption: str, lang: str = "en"
) -> list[_Table]:
    key = _key_column(result)
    columns = [c for c in columns if c.name != key.name]
    header = [tr("pos.", lang), "CSV row"] + [_header(result, c, lang) for c in [key] + columns]

    def size(c):
        v = np.abs(c.values)
        return float(np.max(v[np.isfinite(v)])) if np.any(np.isfinite(v)) else 0.0

    by_unit: dict[str, float] = {}
    for c in [key] + columns:  # round-off is judged per unit, table-wide
        by_unit[c.unit] = max(by_unit.get(c.unit, 0.0), size(c))
    body = [
        [lab, str(k + 1)] + [_fmt(float(c.values[k]), by_unit[c.unit]) for c in [key] + columns]
        for lab, k in rows
    ]
    return _split(header, body, 3, caption)


def _distinct_points(result) -> list[str]:
    """Moving points with distinct paths: one of each pin, none at rest."""
    system = result.system
    kept: list[str] = []
    l_ref = system.l_ref
    for n in system.links:
        for p in system.model.link(n).points:
            ref = f"{n}.{p}"
            xy = np.column_stack((result[f"{ref}.x"], result[f"{ref}.y"]))
            if np.ptp(xy, axis=0).max() <= 1e-9 * l_ref:
                continue
            if any(
                np.allclose(
                    xy,
                    np.column_stack((result[f"{k}.x"], result[f"{k}.y"])),
                    rtol=0,
                    atol=1e-9 * l_ref,
                )
                for k in kept
            ):
                continue
            kept.append(ref)
    return kept


def _rotating_links(result) -> list[str]:
    speed = max(abs(d.driver.motion.speed) for d in result.system.motion_drivers)
    return [
        n
        for n in result.system.links
        if np.max(np.abs(result[f"{n}.omega"])) > 1e-9 * max(1.0, speed)
    ]


def _with_magnitude(result, names: list[str], label: str) -> list[Column]:
    """The CSV columns ``names`` (x, y components) followed by their magnitude."""
    cols = [_csv_column(result, n) for n in names]
    mag = np.hypot(cols[0].values, cols[1].values)
    return cols + [Column(label, cols[0].unit, mag)]


def report_tables(result, rows: Sequence[tuple[str, int]], lang: str = "en") -> list[_Table]:
    """The report's tables at ``rows`` ``[(label, row index)]``: positions,
    velocities, accelerations, reactions, driving effort and friction; wide tables
    split into column groups that repeat the position, its CSV row and its angle.

    Conventions: the position angle φ (``angle``) and the link angles θ in [0, 360)°
    counter-clockwise from +x; point coordinates in the file's length unit; beside the
    components of every point velocity, acceleration and joint force its magnitude
    (``|v|``, ``|a|``, ``|F|``)."""
    rows = list(rows)
    pts = _distinct_points(result)
    rot = _rotating_links(result)
    model = result.system.model
    lu, lf = length_unit(model)
    first = [_csv_column(result, "travel"), _csv_column(result, "time")]
    if "angle" not in result.columns:
        first[0] = Column("travel", lu, np.asarray(result["travel"], dtype=float) / lf)
    thetas = [Column(f"{n}.theta", "deg", _angle(result[f"{n}.theta"])) for n in rot]
    coords = [
        Column(f"{p}.{c}", lu, np.asarray(result[f"{p}.{c}"], dtype=float) / lf)
        for p in pts
        for c in ("x", "y")
    ]
    tables = _table(
        result,
        rows,
        first + thetas + coords,
        tr(
            "Positions: driver angle φ and link angles θ (deg, 0–360, counter-clockwise "
            "from +x), points ({unit})",
            lang,
            unit=lu,
        ),
        lang,
    )
    vel = [_csv_column(result, f"{n}.omega") for n in rot]
    acc = [_csv_column(result, f"{n}.alpha") for n in rot]
    for p in pts:
        vel += _with_magnitude(result, [f"{p}.vx", f"{p}.vy"], f"{p}.|v|")
        acc += _with_magnitude(result, [f"{p}.ax", f"{p}.ay"], f"{p}.|a|")
    tables += _table(
        result,
        rows,
        vel,
        tr(
            "Velocities: angular velocities (rad/s, counter-clockwise +) and point "
            "velocities (m/s), components and magnitude",
            lang,
        ),
        lang,
    )
    tables += _table(
        result,
        rows,
        acc,
        tr(
            "Accelerations: angular accelerations (rad/s², counter-clockwise +) and point "
            "accelerations (m/s²), components and magnitude",
            lang,
        ),
        lang,
    )
    tables += _table(
        result,
        rows,
        _reaction_columns(result, ""),
        tr(
            "Total reactions F_R of the joints without friction: force of link i on link j "
            "(N) and its magnitude; prismatic pairs also N (normal force) and M (couple, N·m)",
            lang,
        ),
        lang,
    )
    drv = []
    for d in result.system.motion_drivers:
        for word in ("torque", "force"):
            for suffix in ("", "_friction_approx", "_friction"):
                drv.append(f"{d.name}.{word}{suffix}")
        drv.append(f"{d.name}.efficiency")
    drv += ["friction.status", "power.input", "power.friction"]
    tables += _table(
        result,
        rows,
        [_csv_column(result, n) for n in drv if n in result.columns],
        tr(
            "Balancing torque M_b of each driver (balancing force F_b of a sliding driver) "
            "without friction, with the approximate and the consistent friction solution, "
            "efficiency, friction status (0 converged, 1 by "
            "homotopy, 2 self-locking, 3 a relative speed is zero), input power and friction "
            "loss (W)",
            lang,
        )
        if "friction.status" in result.columns
        else tr(
            "Balancing torque M_b of each driver (balancing force F_b of a sliding driver) "
            "and the input power (W); no joint has friction",
            lang,
        ),
        lang,
    )
    if model.has_friction:
        tables += _table(
            result,
            rows,
            _reaction_columns(result, "_friction"),
            tr(
                "Total reactions F_R of the joints with friction (consistent solution): force "
                "of link i on link j (N) and its magnitude",
                lang,
            ),
            lang,
        )
    return tables


def _reaction_columns(result, suffix: str) -> list[Column]:
    cols: list[Column] = []
    for j in result.system.model.joints:
        names = [f"{j.name}.{lab}{suffix}" for lab in j.reaction_labels]
        names = [n for n in names if n in result.columns]
        if f"{j.name}.Fx{suffix}" in names and f"{j.name}.Fy{suffix}" in names:
            rest = [n for n in names if n not in (f"{j.name}.Fx{suffix}", f"{j.name}.Fy{suffix}")]
            cols += _with_magnitude(
                result, [f"{j.name}.Fx{suffix}", f"{j.name}.Fy{suffix}"], f"{j.name}.|F|{suffix}"
            )
            cols += [_csv_column(result, n) for n in rest]
        else:
            cols += [_csv_column(result, n) for n in names]
    return cols


def _num(v: float, scale: float, digits: int = 4) -> str:
    """A number to ``digits`` significant digits; round-off of ``scale`` as 0."""
    if not math.isfinite(v):
        return "—"
    return "0" if abs(v) <= ROUND_OFF * scale else f"{v:.{digits}g}"


_ROMAN = ("", "I", "II", "III", "IV", "V", "VI", "VII", "VIII")
_ROMAN_ZH = "\u3000ⅠⅡⅢⅣⅤⅥⅦⅧ"  # the Roman numerals of Chinese text (Ⅱ U+2161 …)


def roman(n: int, lang: str = "en") -> str:
    """The class ``n`` of an Assur group or a mechanism as a Roman numeral (Ⅱ in Chinese)."""
    if not 0 < n < len(_ROMAN):
        return str(n)
    return _ROMAN_ZH[n] if lang == "zh" else _ROMAN[n]


def group_label(group, lang: str = "en") -> str:
    """An Assur group's label with its class (``Group.order``): ``RRR dyad (class II)
    {rod, slider}``, in Chinese ``RRR 型Ⅱ级杆组 {rod, slider}``."""
    links = "{" + ", ".join(group.links) + "}"
    if group.kind == "driven":
        many = len(group.links) > 1
        return tr("driving links {links}" if many else "driving link {links}", lang, links=links)
    if group.order is None:
        return tr("{n}-link group {links}", lang, n=len(group.links), links=links)
    c = roman(group.order, lang)
    if group.kind == "dyad":
        return tr(
            "{letters} dyad (class {c}) {links}", lang, letters=group.letters, c=c, links=links
        )
    return tr("class {c} group of {n} links {links}", lang, c=c, n=len(group.links), links=links)


def crank_angle_between(a: float, b: float) -> float:
    """极位夹角 θ (deg): the acute angle between the crank's positions ``a`` and ``b`` (deg)
    at the output's two limit positions, |180° − the crank's turn from one to the other|;
    at constant crank speed θ = 180°(K − 1)/(K + 1)."""
    return abs(180.0 - (b - a) % 360.0)


def balancing(model, driver: str) -> str:
    """The name of a driver's effort in the kinetostatic analysis: the balancing torque M_b
    on a crank (平衡力矩), the balancing force F_b on a slide (平衡力)."""
    d = next(d for d in model.drivers if d.name == driver)
    return "balancing torque M_b" if model.joint(d.joint).angular else "balancing force F_b"


_END = {(0, 1): "highest", (0, -1): "lowest", (1, 0): "rightmost", (-1, 0): "leftmost"}


def event_position(model, event: dict, lang: str = "en") -> str:
    """Where in its travel the point of a load condition is at a load event: a ``travel``
    band's edge as its distance from the extreme position the travel is measured from (the
    least p·axis over the motion: the highest position for an axis (0, −1)); a ``moving``
    condition switches where the point stops along its axis, at a limit position."""
    load = next((ld for ld in model.loads if ld.name == event["load"]), None)
    kind = {"travel from": "travel", "travel to": "travel"}.get(event["condition"], "moving")
    conds = [c for c in load.active if c.kind == kind] if load is not None else []
    if len(conds) != 1:
        return tr(event["condition"], lang)
    c = conds[0]
    lu, lf = length_unit(model)
    p, (x, y) = f"{c.link}.{c.point or 'CoM'}", (float(v) for v in c.axis)
    if kind == "moving":
        return tr("{p} at a limit position along ({x}, {y})", lang, p=p, x=f"{x:g}", y=f"{y:g}")
    s = c.bounds[0 if event["condition"] == "travel from" else 1] / lf
    end = _END.get((round(-x), round(-y))) if abs(x * y) < 1e-12 else None
    if end is None:
        return tr(
            "{p} {s} {lu} from its extreme position against ({x}, {y})",
            lang,
            p=p,
            s=f"{s:.6g}",
            lu=lu,
            x=f"{x:g}",
            y=f"{y:g}",
        )
    return tr(f"{{p}} {{s}} {{lu}} from its {end} position", lang, p=p, s=f"{s:.6g}", lu=lu)


def _summary_blocks(result, summary, lang: str = "en") -> list:
    model = result.system.model
    lu, lf = length_unit(model)
    labels = {p.group.label: group_label(p.group, lang) for p in result.system.plans}
    blocks: list = [_Heading(2, tr("3. Results over the cycle", lang))]
    items = [
        tr(
            "{n} positions analysed (a full cycle: {full})",
            lang,
            n=len(result),
            full=tr("yes" if result.full_cycle else "no", lang),
        )
    ]
    model, nums = result.system.model, link_numbers(result.system)
    for o in summary.get("outputs", {}).values():  # without the cycle's records: none
        # the member that moves (构件6 ram), not the pair the output is measured at
        name = member(o["link"], nums, model, lang)
        name = f"{name} {o['link']}" if numbered(model) else name
        lo, hi = o["limit_positions"]["min"], o["limit_positions"]["max"]
        k, a, b = f"{o['time_ratio']:.4f}", f"{lo['angle']:.3f}", f"{hi['angle']:.3f}"
        theta = f"{crank_angle_between(lo['angle'], hi['angle']):.3f}"
        if o.get("kind") == "swing":
            text = tr(
                "output {name}: swing {swing}°, time ratio K = {k}, crank angle "
                "between the limit positions θ = {theta}°; limit positions at φ = {a}° "
                "({name} at {ta}°) and {b}° ({name} at {tb}°)",
                lang,
                name=name,
                swing=f"{o['swing']:.4f}",
                k=k,
                theta=theta,
                a=a,
                b=b,
                ta=f"{lo['theta']:.3f}",
                tb=f"{hi['theta']:.3f}",
            )
        else:
            text = tr(
                "output {name}: stroke {stroke} {unit}, time ratio K = {k}, crank angle "
                "between the limit positions θ = {theta}°; limit positions at φ = {a}° and {b}°",
                lang,
                name=name,
                stroke=f"{o['stroke'] / lf:.6g}",
                unit=lu,
                k=k,
                theta=theta,
                a=a,
                b=b,
            )
        items.append(text)
    for e in summary["events"]:
        items.append(
            tr(
                "event: {load} switches {switch} at φ = {angle}° ({where})",
                lang,
                load=e["load"],
                switch=tr(e["switch"], lang),
                angle=f"{e['angle']:.4f}",
                where=event_position(model, e, lang),
            )
        )
    for name, d in summary["drivers"].items():
        if "mean" not in d:  # without the cycle's records: no means
            continue
        peak = max(abs(d["peak"]), abs(d.get("peak_friction", 0.0) or 0.0))
        unit = _unit(d["unit"])
        line = tr(
            "{effort} of {name}: mean {mean} {unit}, largest magnitude {peak} {unit}",
            lang,
            effort=tr(balancing(model, name), lang),
            name=name,
            mean=_num(d["mean"], peak),
            unit=unit,
            peak=_num(d["peak"], peak),
        )
        if "mean_friction" in d and not math.isfinite(d["mean_friction"]):
            line += tr(
                "; with friction: no consistent solution at any position "
                "(self-locking; approximate mean {m})",
                lang,
                m=_num(d["mean_friction_approx"], peak),
            )
        elif "mean_friction" in d:
            line += tr(
                "; with friction mean {m} (approximate {a}), largest magnitude {p}",
                lang,
                m=_num(d["mean_friction"], peak),
                a=_num(d["mean_friction_approx"], peak),
                p=_num(d["peak_friction"], peak),
            )
        items.append(line + tr(" (means over one cycle, integrated between the load events)", lang))
    if "friction.status" in result.columns:
        locked = int(np.sum(result["friction.status"] == 2))
        if locked:
            items.append(
                tr(
                    "self-locking at {k} of {n} positions (friction.status 2): the consistent "
                    "friction columns are empty there and the means and peaks with friction "
                    "are over the other rows",
                    lang,
                    k=locked,
                    n=len(result),
                )
                + (tr(" — here there are none", lang) if locked == len(result) else "")
            )
    for sp in summary["singular_positions"]:
        items.append(
            tr(
                "singular position: {group} at φ = {angle}° (condition {c})",
                lang,
                group=labels.get(sp["group"], sp["group"]),
                angle=f"{sp['angle']:.4f}",
                c=f"{sp['condition']:.3g}",
            )
        )
    if summary["indeterminate_reactions"]:
        items.append(tr("redundant constraints: reactions are the minimum-norm solution", lang))
    blocks.append(_List(items))
    friction = model.has_friction  # else no column with friction (it would be empty)
    rows = [
        [n, f"{p['peak']:.5g}", f"{p['at']:.4g}"]
        + ([_fmt(p.get("peak_friction", math.nan), 0.0)] if friction else [])
        for n, p in summary["reaction_peaks"].items()
    ]
    head = [
        tr("joint", lang),
        tr("largest |F_R| without friction (N)", lang),
        tr("at φ (deg)", lang),
    ] + ([tr("largest |F_R| with friction (N)", lang)] if friction else [])
    blocks.append(_Table(head, rows, tr("Largest total reactions F_R of the joints", lang)))
    return blocks
