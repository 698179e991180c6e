"""Curves over the driver coordinate: output motion, motion diagram, reactions,
driving torque, efficiency, any columns; load zones and events marked."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...errors import did_you_mean
from ...kinetics.forces import activity
from ..labels import column_label, reaction_symbol
from ..lang import tr, tr_unit
from .rows import (
    _course_ticks,
    _driver,
    _event_travel,
    _sorted,
    link_numbers,
    turns,
)
from .style import (
    CURVE_COLORS,
    DPI,
    EVENT_COLOR,
    ROUND_OFF,
    PictureError,
    _course_axis,
    _figure,
    _grow_to_fit,
    _rc,
)


# -- output motion ------------------------------------------------------------------
def _joint_coordinate(result, joint):
    """(c, ċ, c̈) of a joint's relative coordinate over all rows."""
    system = result.system
    k = system.model.joints.index(joint)
    n = len(result)
    ext = lambda a: np.concatenate((a, np.zeros((n, 3))), axis=-1)
    qe, ve, ae = ext(result.q), ext(result.qd), ext(result.qdd)
    i, j = system.ends[k]
    sl = lambda a, m: a[:, 3 * m : 3 * m + 3]
    qi, qj = sl(qe, i), sl(qe, j)
    gi, gj = joint.motion_direction(qi, qj)
    c = joint.coordinate(qi, qj)
    cd = np.sum(gi * sl(ve, i), axis=-1) + np.sum(gj * sl(ve, j), axis=-1)
    cdd = (
        np.sum(gi * sl(ae, i), axis=-1)
        + np.sum(gj * sl(ae, j), axis=-1)
        + joint.coordinate_bias(qi, qj, sl(ve, i), sl(ve, j))
    )
    return c, cd, cdd


def output_motion(result, output: str | None = None, *, lang: str = "en") -> dict:
    """Position, velocity and acceleration of the output, over the rows.

    ``output``: a prismatic joint (its sliding coordinate s = (P_j − A_i)·u_i,
    ṡ, s̈), another joint (its relative coordinate: a revolute's relative angle,
    a gear or rack pair's rolling travel), a link (θ, ω, α), or ``"link.point"``
    (x, y components).  Default: the first undriven pair whose stroke is an
    output (``reports_stroke``: a prismatic pair) on the frame (the output
    slider), else any such pair, else the last link solved.

    Returns ``{"name", "kind" ("slide"|"joint"|"link"|"point"), "series":
    [(label, unit, values (n,) or (n, 2)) × 3], "axes": [short label × 3]}`` in SI; the
    labels in ``lang``.
    """
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    system, model = result.system, result.system.model
    output = _default_output(system) if output is None else output
    joints = {j.name: j for j in model.joints}
    if output in joints:
        return _joint_motion(result, joints[output], T)
    if output in system.links:
        return {
            "name": output,
            "kind": "link",
            "series": [
                (T("θ of {name}", name=output), "deg", result[f"{output}.theta"]),
                (T("ω of {name}", name=output), "rad/s", result[f"{output}.omega"]),
                (T("α of {name}", name=output), "rad/s²", result[f"{output}.alpha"]),
            ],
            "axes": [T("θ"), T("ω"), T("α")],
        }
    if f"{output}.x" in result.columns and output.count(".") == 1:
        return _point_motion(result, output, T)
    names = (
        list(joints)
        + list(system.links)
        + [f"{lk.name}.{p}" for lk in model.moving_links for p in lk.points]
    )
    raise PictureError(
        f"no output '{output}' (a joint, a link or link.point){did_you_mean(output, names)}"
    )


def _default_output(system) -> str:
    """The first undriven pair whose stroke is an output on the frame (the output slider),
    else any such pair, else the last link solved."""
    model = system.model
    driven = {d.joint.name for d in system.motion_drivers}
    slides = [j for j in model.joints if j.reports_stroke and j.name not in driven]
    on_frame = [j for j in slides if model.ground.name in j.links]
    if on_frame or slides:
        return (on_frame or slides)[0].name
    return system.plans[-1].group.links[-1]


def _joint_motion(result, j, T) -> dict:
    """:func:`output_motion` of the joint ``j``: a revolute's relative angle, a gear or
    rack pair's rolling travel, a slide's s of its point along it; labels through ``T``."""
    output = j.name
    c, cd, cdd = _joint_coordinate(result, j)
    if j.angular:
        return {
            "name": output,
            "kind": "joint",
            "series": [
                (T("relative angle of {name}", name=output), "deg", np.degrees(c)),
                (T("relative angular velocity"), "rad/s", cd),
                (T("relative angular acceleration"), "rad/s²", cdd),
            ],
            "axes": [
                T("relative angle"),
                T("relative angular velocity"),
                T("relative angular acceleration"),
            ],
        }
    at = [a for a in j.anchors() if a.at_joint and a.link == j.links[1]]
    if not at:  # no point of link j slides (a gear or rack pair): its rolling travel
        return {
            "name": output,
            "kind": "joint",
            "series": [
                (T("relative travel of {name}", name=output), "mm", c * 1e3),
                (T("relative velocity"), "m/s", cd),
                (T("relative acceleration"), "m/s²", cdd),
            ],
            "axes": [T("relative travel"), T("relative velocity"), T("relative acceleration")],
        }
    pj = T("point {p}", p=at[0].point)  # the point as the reader names it: C点
    return {
        "name": output,
        "kind": "slide",
        "series": [
            (T("s of {point} along {joint}", point=pj, joint=output), "mm", c * 1e3),
            (T("v = ds/dt"), "m/s", cd),
            (T("a = d²s/dt²"), "m/s²", cdd),
        ],
        "axes": [T("s"), T("v = ds/dt"), T("a = d²s/dt²")],
    }


def _point_motion(result, output: str, T) -> dict:
    """:func:`output_motion` of the point ``link.point``: its (x, y) position, velocity
    and acceleration; labels through ``T``."""
    xy = lambda s: np.column_stack(
        (
            result[f"{output}.{s}x" if s else f"{output}.x"],
            result[f"{output}.{s}y" if s else f"{output}.y"],
        )
    )
    return {
        "name": output,
        "kind": "point",
        "series": [
            (T("position of {name}", name=output), "mm", xy("") * 1e3),
            (T("velocity of {name}", name=output), "m/s", xy("v")),
            (T("acceleration of {name}", name=output), "m/s²", xy("a")),
        ],
        "axes": [T("position"), T("velocity"), T("acceleration")],
    }


def _active_spans(result) -> list[tuple[str, float, float]]:
    """Travel intervals where each load with ``active:`` conditions acts."""
    system = result.system
    x, order, _ = _sorted(result)
    ref = abs(_driver(result).driver.motion.speed)
    spans = []
    for load in system.model.loads:
        if not load.active:
            continue
        on = activity(system, load, result.q, result.qd, result.coordinate, result.extremes, ref)[
            order
        ]
        ev = np.array([_is_event_row(result, int(i)) for i in order])
        k = 0
        while k < len(on):
            if not on[k]:
                k += 1
                continue
            m = k
            while m + 1 < len(on) and on[m + 1]:
                m += 1
            x0 = x[k - 1] if k > 0 and ev[k - 1] else x[k]
            x1 = x[m + 1] if m + 1 < len(on) and ev[m + 1] else x[m]
            spans.append((load.name, float(x0), float(x1)))
            k = m + 1
    return spans


def _is_event_row(result, k) -> bool:
    return any(abs(result.t[k] - e.t) < 1e-9 * max(1.0, abs(e.t)) for e in result.events)


def _mark(ax, result, *, top: bool = True, spans=None, lang: str = "en"):
    """Loads' active zones shaded, events as dashed lines (labelled 1′ … in the top
    panel), course positions 1…12 on a top axis."""
    spans = _active_spans(result) if spans is None else spans
    for _name, x0, x1 in spans:
        ax.axvspan(x0, x1, color=EVENT_COLOR, alpha=0.07, lw=0, zorder=0)
    ticks = _course_ticks(result)
    for xe, lab in ticks:
        if "′" in lab:
            ax.axvline(xe, color=EVENT_COLOR, lw=0.8, ls=(0, (4, 2)), zorder=1)
            if top:
                right = xe > 0.9 * 360 * max(1, turns(result))
                ax.text(
                    xe,
                    0.97,
                    f"{lab} " if right else f" {lab}",
                    transform=ax.get_xaxis_transform(),
                    color=EVENT_COLOR,
                    fontsize=7,
                    va="top",
                    ha="right" if right else "left",
                )
    if not ticks:
        for e in result.events:
            ax.axvline(
                _event_travel(result, e), color=EVENT_COLOR, lw=0.8, ls=(0, (4, 2)), zorder=1
            )
    if top and ticks:
        numbered = [(t, lab.split("/")[0]) for t, lab in ticks if "′" not in lab]
        label = (
            tr("course positions (turns 1 to {n})", lang, n=turns(result))
            if turns(result) > 1
            else tr("course positions", lang)
        )
        _course_axis(ax, numbered, label)
    n_turns = turns(result)
    if n_turns:
        ax.set_xlim(0, 360 * n_turns)
        ax.set_xticks(np.arange(0, 360 * n_turns + 1, 30 * n_turns))


def _event_legend(ax, result, lang: str = "en"):
    if result.events:
        loads = ", ".join(sorted({e.load for e in result.events}))
        ax.plot(
            [],
            [],
            color=EVENT_COLOR,
            lw=0.8,
            ls=(0, (4, 2)),
            label=tr("load switches ({loads})", lang, loads=loads),
        )
    names = sorted({name for name, _, _ in _active_spans(result)})
    if names:
        label = tr("{loads} acting", lang, loads=", ".join(names))
        ax.fill_between([], [], color=EVENT_COLOR, alpha=0.1, lw=0, label=label)


def _cycle_mean(cycle, key: str) -> float | None:
    """The cycle mean of a driving effort column from the cycle's record (``cycle.drivers``,
    :func:`~kinetostatics.dynamics.stages.cycle_stage`), as in summary.json; None without
    it (the picture then draws no mean: a picture solves nothing)."""
    drivers = getattr(cycle, "drivers", None)
    if drivers is None or key not in drivers:
        return None
    return float(drivers[key]["mean"])


def motion_diagram(result, output: str | None = None, *, dpi: float = DPI, lang: str = "en"):
    """The motion diagram of the output: position, velocity, acceleration over the
    driver coordinate (three panels), loads' zones and events marked, course
    positions on top.  ``output`` as in :func:`output_motion`."""
    out = output_motion(result, output, lang=lang)
    x, order, xlabel = _sorted(result, lang)
    spans = _active_spans(result)
    with _rc(lang):
        fig = _figure(165, 150, dpi)
        axes = fig.subplots(3, 1, sharex=True)
        for n, (ax, (_, unit, vals)) in enumerate(zip(axes, out["series"])):
            vals = np.asarray(vals)[order]
            if vals.ndim == 2:
                ax.plot(x, vals[:, 0], color=CURVE_COLORS[0], label=tr("x component", lang))
                ax.plot(x, vals[:, 1], color=CURVE_COLORS[1], label=tr("y component", lang))
            else:
                ax.plot(x, vals, color=CURVE_COLORS[n])
            ax.set_ylabel(f"{out['axes'][n]}, {tr_unit(unit, lang)}")
            if n > 0:
                ax.axhline(0, color="black", lw=0.5)
            _mark(ax, result, top=(n == 0), spans=spans, lang=lang)
        _event_legend(axes[0], result, lang)
        if axes[0].get_legend_handles_labels()[0]:
            axes[0].legend(loc="best", fontsize=7)
        axes[-1].set_xlabel(xlabel)
        what = {
            "slide": "output slider",
            "link": "link {name}",
            "point": "point {name}",
            "joint": "joint {name}",
        }[out["kind"]]
        fig.suptitle(
            tr(
                "{model}: motion diagram of the {what}",
                lang,
                model=result.system.model.name,
                what=tr(what, lang, name=out["name"]),
            )
            + (tr(" ({label})", lang, label=out["series"][0][0]) if out["kind"] == "slide" else ""),
            x=0.02,
            ha="left",
            fontsize=9.5,
        )
        fig.align_ylabels(axes)
        fig.subplots_adjust(left=0.12, right=0.97, top=0.875, bottom=0.08, hspace=0.12)
    _grow_to_fit(fig)
    return fig


def reaction_curves(
    result,
    *,
    friction: bool = False,
    joints: Sequence[str] | None = None,
    dpi: float = DPI,
    lang: str = "en",
):
    """Magnitude |F| of every joint's reaction over the driver coordinate (N);
    with ``friction`` the consistent friction solution dashed in the same colour."""
    model = result.system.model
    names = list(joints) if joints else [j.name for j in model.joints]
    x, order, xlabel = _sorted(result, lang)
    nums = link_numbers(result.system)
    with _rc(lang):
        fig = _figure(165, 95, dpi)
        ax = fig.add_subplot()
        for n, name in enumerate(names):
            if f"{name}.Fx" not in result.columns:
                raise PictureError(
                    f"no joint '{name}'{did_you_mean(name, [j.name for j in model.joints])}"
                )
            j = model.joint(name)
            c = CURVE_COLORS[n % len(CURVE_COLORS)]
            mag = np.hypot(result[f"{name}.Fx"], result[f"{name}.Fy"])[order]
            ax.plot(x, mag, color=c, label=f"{name} ({reaction_symbol(j.links, nums)})")
            if friction and f"{name}.Fx_friction" in result.columns:
                magf = np.hypot(result[f"{name}.Fx_friction"], result[f"{name}.Fy_friction"])[order]
                ax.plot(x, magf, color=c, ls="--", lw=1.0)
        if friction:
            label = tr("with friction (consistent)", lang)
            ax.plot([], [], color="black", ls="--", lw=1.0, label=label)
        _mark(ax, result, lang=lang)
        _event_legend(ax, result, lang)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(tr("reaction magnitude |F|, N", lang))
        title = tr("{model}: joint reactions", lang, model=model.name)
        fig.suptitle(title, x=0.02, ha="left", fontsize=9.5)
        ax.set_ylim(bottom=0)
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
        fig.subplots_adjust(left=0.09, right=0.74, top=0.80, bottom=0.14)
    _grow_to_fit(fig)
    return fig


def _driver_effort(result, driver: str | None):
    system = result.system
    ds = {d.name: d for d in system.motion_drivers}
    d = ds.get(driver) if driver else system.motion_drivers[0]
    if d is None:
        raise PictureError(f"no motion driver '{driver}'{did_you_mean(driver, ds)}")
    joint = system.model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
    word, unit = ("torque", "N·m") if joint.angular else ("force", "N")
    return d, word, unit


# the driving effort's curves: (column suffix, legend, colour, line style)
_EFFORT_SERIES = (
    ("", "without friction", CURVE_COLORS[0], "-"),
    (
        "_friction_approx",
        "with friction, approximate (from frictionless reactions)",
        CURVE_COLORS[1],
        "--",
    ),
    ("_friction", "with friction, consistent", CURVE_COLORS[3], "-"),
)


def _with_mean(text: str, y: np.ndarray, mean: float | None, unit: str, lang: str) -> str:
    """A curve's legend ``text`` with its cycle ``mean`` (none: as it is); a mean within
    round-off of the curve's peak is written 0."""
    if mean is None:
        return text
    peak = float(np.nanmax(np.abs(y))) if np.any(np.isfinite(y)) else 0.0
    mean = 0.0 if abs(mean) <= ROUND_OFF * peak else mean  # round-off
    return tr("{label} (cycle mean {mean} {unit})", lang, label=text, mean=f"{mean:.4g}", unit=unit)


def torque_curves(
    result, driver: str | None = None, *, dpi: float = DPI, lang: str = "en", cycle=None
):
    """The driving torque (or force) without friction, with the approximate and
    with the consistent friction, on one plot; events marked; the cycle means in the
    legend when ``cycle`` (the cycle's record,
    :func:`~kinetostatics.dynamics.stages.cycle_stage`) is given."""
    d, word, unit = _driver_effort(result, driver)
    x, order, xlabel = _sorted(result, lang)
    with _rc(lang):
        fig = _figure(165, 95, dpi)
        ax = fig.add_subplot()
        for suffix, label, c, ls in _EFFORT_SERIES:
            key = f"{d.name}.{word}{suffix}"
            if key not in result.columns:
                continue
            y = np.asarray(result[key])[order]
            text = _with_mean(tr(label, lang), y, _cycle_mean(cycle, key), unit, lang)
            ax.plot(
                x,
                y,
                color=c,
                ls=ls,
                lw=1.6 if ls == "-" else 1.3,
                zorder=3 if ls == "-" else 4,
                label=text,
            )
        status = result.columns.get("friction.status")
        if status is not None and np.any(status[order] == 2):
            locked = x[status[order] == 2]
            label = tr("self-locking", lang)
            ax.plot(locked, np.zeros_like(locked), "x", color="black", ms=4, label=label)
        ax.axhline(0, color="black", lw=0.5)
        _mark(ax, result, lang=lang)
        _event_legend(ax, result, lang)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(
            tr("M, {unit} (counter-clockwise +)", lang, unit=unit)
            if word == "torque"
            else f"F, {unit}"
        )
        fig.suptitle(
            tr(
                f"{{model}}: driving {word} of {{driver}}",
                lang,
                model=result.system.model.name,
                driver=d.name,
            ),
            x=0.02,
            ha="left",
            fontsize=9.5,
        )
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1)
        fig.subplots_adjust(left=0.1, right=0.97, top=0.81, bottom=0.36)
    _grow_to_fit(fig)
    return fig


def efficiency_curve(
    result, driver: str | None = None, *, dpi: float = DPI, lang: str = "en", cycle=None
):
    """Instantaneous efficiency η = M / M_friction (frictionless over consistent driving
    torque) where it is one (docs/friction.md: gaps elsewhere) and, when ``cycle`` (the
    cycle's record with its ``efficiency``,
    :func:`~kinetostatics.dynamics.stages.cycle_stage`) is given, the cycle efficiency
    (ratio of the mean input powers)."""
    d, word, _ = _driver_effort(result, driver)
    key = f"{d.name}.efficiency"
    if key not in result.columns:
        raise PictureError(f"no friction in {result.system.model.name}: no efficiency to plot")
    x, order, xlabel = _sorted(result, lang)
    eta = np.asarray(result[key])[order]
    with _rc(lang):
        fig = _figure(165, 85, dpi)
        ax = fig.add_subplot()
        label = tr("η = P / P_friction where the drive delivers power (gaps: undefined)", lang)
        ax.plot(x, eta, color=CURVE_COLORS[2], label=label)
        pin = result.columns.get("power.input")
        pinf = None
        efficiency = getattr(cycle, "efficiency", None) or {}
        if f"{d.name}.{word}_friction" in result.columns and pin is not None:
            pinf = efficiency.get(d.name)
            if pinf is not None:
                ax.axhline(
                    pinf,
                    color="black",
                    ls="--",
                    lw=0.9,
                    label=tr(
                        "cycle efficiency (mean M / mean M_friction) = {eta}",
                        lang,
                        eta=f"{pinf:.4f}",
                    ),
                )
        finite = eta[np.isfinite(eta)]
        lo = max(min(float(np.percentile(finite, 2)) if finite.size else 0.0, 0.0), -1.0)
        ax.set_ylim(lo - 0.05, 1.1)
        _mark(ax, result, lang=lang)
        _event_legend(ax, result, lang)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(tr("efficiency η, 1", lang))
        fig.suptitle(
            tr(
                "{model}: efficiency of the drive {driver}",
                lang,
                model=result.system.model.name,
                driver=d.name,
            ),
            x=0.02,
            ha="left",
            fontsize=9.5,
        )
        ax.legend(loc="lower left")
        fig.subplots_adjust(left=0.1, right=0.97, top=0.79, bottom=0.15)
    _grow_to_fit(fig)
    return fig


def plot_result(result, *names: str, dpi: float = DPI, lang: str = "en"):
    """Any columns over the driver coordinate, one panel per unit (each column named as the
    reader names it, :func:`~kinetostatics.outputs.labels.column_label`: ``构件4 角速度 ω₄``;
    the axes and marks in ``lang``)."""
    if not names:
        raise PictureError("name at least one column to plot")
    for n in names:
        result[n]  # KeyError with a suggestion
    x, order, xlabel = _sorted(result, lang)
    units: dict[str, list[str]] = {}
    for n in names:
        units.setdefault(result.units[n], []).append(n)
    with _rc(lang):
        fig = _figure(165, 45 + 45 * len(units), dpi)
        axes = np.atleast_1d(fig.subplots(len(units), 1, sharex=True))
        for ax, (unit, cols) in zip(axes, units.items()):
            for k, n in enumerate(cols):
                label = column_label(result.system, n, lang)
                ax.plot(x, np.asarray(result[n])[order], color=CURVE_COLORS[k % 10], label=label)
            ax.set_ylabel(tr_unit(unit.replace("*", "·").replace("^2", "²"), lang))
            ax.legend(loc="best")
            _mark(ax, result, top=ax is axes[0], lang=lang)
        axes[-1].set_xlabel(xlabel)
        fig.suptitle(result.system.model.name, x=0.02, ha="left", fontsize=9.5)
        fig.subplots_adjust(
            left=0.11, right=0.97, top=1 - 16 / (45 + 45 * len(units)), bottom=0.1, hspace=0.15
        )
    _grow_to_fit(fig)
    return fig
