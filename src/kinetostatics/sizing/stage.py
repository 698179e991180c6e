"""The sizing stage: a Result's reactions turned into the bearings' life, the pins'
stresses and the links' internal forces and fatigue safety factors (docs/sizing.md).

:func:`sizing_stage` reads the result's columns only, at its rows and at the cycle's
quadrature nodes (:func:`~kinetostatics.analysis.cycle.cycle_quadrature`, the frictionless
solution): the arrays of the records are at the rows, the peaks over the rows and the
nodes, the means and the bearing life are integrals over the nodes.  The loads are those
of the frictionless solution (the joints then put no couple on the links: docs/sizing.md
says what friction changes).
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.cycle import Quadrature, cycle_quadrature
from ..analysis.results import Result
from ..model.sizing import SHEAR_PLANES, BearingSpec, PinSpec
from .beams import beam_forces
from .bearings import EXPONENTS, equivalent_load, equivalent_speed, plain_loading, rating_life
from .fatigue import cycle_of, safety_factor
from .loads import beam_loads
from .records import BearingSizing, LinkSizing, PinSizing, Sizing
from .sections import section_properties

__all__ = ["sizing_stage", "STATIONS"]

STATIONS = 41  # stations along a beam (and the places of its point loads)


def sizing_stage(result: Result, nodes: Quadrature | None = None) -> Sizing | None:
    """The sizing records of ``result`` (None when its file has no sizing data).

    Parameters
    ----------
    result : Result
        The analysis.
    nodes : Quadrature, optional
        The cycle's nodes, when the caller has them (frictionless ones serve).

    Returns
    -------
    Sizing or None
        The bearings, pins and links with a section, and the warnings.
    """
    spec = result.system.model.sizing
    if not spec or not len(result):
        return None
    quad = cycle_quadrature(result, friction=False, given=nodes)
    at, w = quad.nodes, quad.weights
    warnings: list[str] = []
    if not result.full_cycle:
        warnings.append(
            "the positions do not span a cycle: the means and the bearing life are those "
            "of the run analysed"
        )
    solved = [j for j in {**spec.bearings, **spec.pins} if f"{j}.Fx" not in result.columns]
    for j in solved:  # a joint the analysis replaced (a clearance's expansion)
        warnings.append(
            f"joint '{j}' has no reaction in the result: its bearing and pin are not checked"
        )
    bearings = tuple(
        _bearing(result, at, w, j, b, warnings) for j, b in spec.bearings.items() if j not in solved
    )
    pins = tuple(_pin(result, at, j, p) for j, p in spec.pins.items() if j not in solved)
    links = []
    for name, section in spec.sections.items():
        record = _link(result, at, name, section, spec.materials.get(name), warnings)
        if record is not None:
            links.append(record)
    return Sizing(_angles(result), bearings, pins, tuple(links), tuple(warnings))


def _angles(result: Result) -> np.ndarray:
    """The rows' crank angles (deg), or the driver coordinate of a prismatic driver."""
    return np.asarray(result.columns.get("angle", result.coordinate), float)


def _force(result: Result, joint: str) -> np.ndarray:
    return np.stack([result[f"{joint}.Fx"], result[f"{joint}.Fy"]], -1)


def _link_angle(result: Result, link: str, what: str) -> np.ndarray:
    col = f"{link}.{what}"
    return (
        np.asarray(result.columns[col], float) if col in result.columns else np.zeros(len(result))
    )


def _relative(result: Result, joint) -> tuple[np.ndarray, np.ndarray]:
    """(relative angle θ_j − θ_i in deg, relative speed ω_j − ω_i in rad/s)."""
    i, j = joint.links
    angle = _link_angle(result, j, "theta") - _link_angle(result, i, "theta")
    return angle, _link_angle(result, j, "omega") - _link_angle(result, i, "omega")


def _bearing(result, at, w, name: str, b: BearingSpec, warnings) -> BearingSizing:
    joint = result.system.model.joint(name)
    i, j = joint.links
    f, fn = _force(result, name), _force(at, name)
    mag, mag_n = np.hypot(*f.T), np.hypot(*fn.T)
    ti, tj = _link_angle(result, i, "theta"), _link_angle(result, j, "theta")
    on_i = np.mod(np.degrees(np.arctan2(-f[:, 1], -f[:, 0])) - ti, 360.0)
    on_j = np.mod(np.degrees(np.arctan2(f[:, 1], f[:, 0])) - tj, 360.0)
    rel, speed = _relative(result, joint)
    rel_n, speed_n = _relative(at, joint)
    turned, travelled = float(np.sum(speed_n * w)), float(np.sum(np.abs(speed_n) * w))
    rotating = travelled > 0 and abs(turned) > 0.5 * travelled
    swing = float(np.ptp(np.concatenate([rel, rel_n]))) if not rotating else float("nan")
    n = equivalent_speed(speed_n, w)
    common = dict(
        joint=name, kind=b.kind, links=(i, j), force=mag, direction=(on_i, on_j),
        relative_angle=rel, relative_speed=speed,
        peak_force=float(max(np.max(mag), np.max(mag_n))),
        motion="rotating" if rotating else "oscillating", swing=swing, speed=n,
    )  # fmt: skip
    if b.kind == "plain":
        plain = _plain(name, b, (mag, speed), (mag_n, speed_n), w, warnings)
        return BearingSizing(**common, plain=plain)
    p = EXPONENTS[b.kind]
    P = equivalent_load(mag_n, speed_n, w, p)
    if not math.isfinite(P):
        warnings.append(
            f"bearing at joint '{name}': its links do not turn relative to each other; "
            "no rating life (check the static rating against the peak load)"
        )
        return BearingSizing(**common, C=b.C, exponent=p)
    life = rating_life(b.C, P, p)
    hours = life / (3600.0 * n) if n > 0 else float("inf")
    return BearingSizing(**common, C=b.C, exponent=p, P=P, life=(life, hours))


def _plain(name: str, b: BearingSpec, rows, nodes, w, warnings) -> dict:
    """{p, v, pv: (rows, peak, mean, limit)} of the plain bearing at joint ``name`` from
    (|F|, ω_rel) at the rows and at the nodes (weights ``w``)."""
    rows = plain_loading(*rows, b.diameter, b.width)
    at_nodes = plain_loading(*nodes, b.diameter, b.width)
    out = {}
    for key, x, xn, limit, unit, scale in zip(
        ("p", "v", "pv"), rows, at_nodes, (b.p_max, b.v_max, b.pv_max),
        ("MPa", "m/s", "MPa·m/s"), (1e-6, 1.0, 1e-6),
    ):  # fmt: skip
        peak = float(max(np.max(x), np.max(xn)))
        out[key] = (x, peak, float(np.sum(xn * w) / np.sum(w)), limit)
        if limit is not None and peak > limit:
            warnings.append(
                f"plain bearing at joint '{name}': peak {key} = {peak * scale:.4g} {unit} "
                f"exceeds its limit {key}_max = {limit * scale:.4g} {unit}"
            )
    return out


def _pin(result, at, name: str, p: PinSpec) -> PinSizing:
    planes = SHEAR_PLANES[p.shear]
    mag, mag_n = np.hypot(*_force(result, name).T), np.hypot(*_force(at, name).T)
    area = math.pi * p.diameter**2 / 4.0
    shear = mag / (planes * area)
    peak = float(max(np.max(mag), np.max(mag_n)))
    eye = peak_eye = None
    if p.eye_width is not None:
        eye = mag / (p.diameter * p.eye_width)
        peak_eye = peak / (p.diameter * p.eye_width)
    return PinSizing(name, p.diameter, planes, shear, peak / (planes * area), eye, peak_eye)


def _link(result, at, name, section, material, warnings) -> LinkSizing | None:
    loads, note = beam_loads(result, name)
    if loads is None:
        warnings.append(f"{note}; its section is not checked")
        return None
    loads_n, _ = beam_loads(at, name)
    if note:
        warnings.append(note)
    L = loads.length
    inner = np.array([x for x, _, _, far in loads.points if 0.0 < x < L and not far])
    # at a point load the values just past it, and a station just before it: both sides
    # of a jump of N or V (and the kink of M) are among the stations
    before = inner - 1e-6 * L
    stations = np.unique(np.concatenate([np.linspace(0.0, L, STATIONS), before, inner]))
    N, V, M = beam_forces(loads, stations)
    Nn, _, Mn = beam_forces(loads_n, stations)
    A, Z = section_properties(section)
    size, size_n = np.abs(N) / A + np.abs(M) / Z, np.abs(Nn) / A + np.abs(Mn) / Z
    worst = np.maximum(size.max(axis=0), size_n.max(axis=0))
    k = int(np.argmax(worst))
    angle = None
    if size[:, k].max() >= size_n[:, k].max():
        angle = float(
            result.columns.get("angle", np.degrees(result.coordinate))[size[:, k].argmax()]
        )
    n_k, m_k = np.concatenate([N[:, k], Nn[:, k]]), np.concatenate([M[:, k], Mn[:, k]])
    fibres = [n_k / A + m_k / Z, n_k / A - m_k / Z]
    cycles = [cycle_of(f) for f in fibres]
    factors: dict = {"goodman": None, "soderberg": None, "yield": None}
    cycle = max(cycles, key=lambda c: abs(c[0]) + c[1])
    if material is not None:
        if material.S_e is not None and material.S_ut is not None:
            gs = [safety_factor(m, a, material.S_e, material.S_ut) for m, a in cycles]
            factors["goodman"] = min(gs)
            cycle = cycles[int(np.argmin(gs))]
        if material.S_e is not None and material.S_y is not None:
            factors["soderberg"] = min(
                safety_factor(m, a, material.S_e, material.S_y) for m, a in cycles
            )
        if material.S_y is not None:
            factors["yield"] = material.S_y / float(worst[k]) if worst[k] > 0 else float("inf")
    for key, v in factors.items():
        if v is not None and v < 1.0:
            warnings.append(f"link '{name}': the {key} safety factor {v:.3g} is below 1")
    pins = tuple(j.name for j in result.system.model.joints if name in j.links)
    return LinkSizing(name, pins, section.shape, A, Z, stations, N, V, M, k, float(worst[k]),
                      angle, cycle, factors, note)  # fmt: skip
