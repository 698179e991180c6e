"""Rows, course positions, the abscissa and position titles of the pictures."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from ...analysis import analyze
from ...structure.system import build_system
from ..labels import link_numbers  # noqa: F401  (the pictures' numbers, from one place)
from ..lang import tr
from .style import PictureError


# -- rows, positions, the abscissa ----------------------------------------------
def _driver(result):
    return result.system.motion_drivers[0]


def _angular(result) -> bool:
    return bool(_driver(result).joint.angular)


def row_at(result, position: float | None = None, *, label: str | None = None) -> int:
    """Row index at a driver coordinate (deg, or mm for a prismatic driver) or at a
    course-position label (``"7"``, ``"8′"``).  Default: the first row.

    Raises :class:`PictureError` if no row is within 1e-6 of the coordinate.
    """
    if label is not None:
        for lab, k in course_positions(result):
            if lab == label.replace("'", "′"):
                return k
        raise PictureError(
            f"no course position '{label}' among the rows "
            f"(have {', '.join(lab for lab, _ in course_positions(result))})"
        )
    if position is None:
        return 0
    if _angular(result):
        d = np.abs((np.degrees(result.coordinate) - position + 180.0) % 360.0 - 180.0)
    else:
        d = np.abs(result.coordinate * 1e3 - position)
    k = int(np.argmin(d))
    if d[k] > 1e-6:
        raise PictureError(
            f"no analysed position at driver coordinate {position:g}"
            f"{'°' if _angular(result) else ' mm'} (nearest "
            f"{d[k]:.3g} away); analyse with analyze_for_pictures(model, "
            f"positions=[{position:g}])"
        )
    return k


def analyze_for_pictures(
    model,
    *,
    positions: Sequence[float] = (),
    frames: int | None = None,
    course: bool = False,
    events: bool = True,
):
    """A full-cycle analysis that also holds rows at chosen driver coordinates.

    ``positions``: driver coordinates in deg (mm for a prismatic driver) added
    to ``analysis.at`` (so loads that depend on the whole cycle, such as a
    cutting band, stay right); ``frames``: replace the grid by that many
    equally spaced positions (animations); ``course``: add the 12 course-design
    positions; ``events``: add rows where loads switch (1′, 8′).
    """
    system = build_system(model)
    a = model.analysis
    angular = system.motion_drivers[0].joint.angular if system.motion_drivers else True
    conv = math.radians if angular else (lambda v: v * 1e-3)
    grid = frames if frames is not None else a.positions
    turns = _sweep_turns(a.sweep) if angular else 0
    if course and turns > 1 and frames is None:  # rows at every 30° of every turn
        grid = -(-grid // (12 * turns)) * 12 * turns
    sign = (
        math.copysign(1.0, system.motion_drivers[0].driver.motion.speed)
        if system.motion_drivers
        else 1.0
    )
    grid_coords = [a.start + sign * k * a.sweep / grid for k in range(grid)]
    extra = [conv(p) for p in positions]
    if course and angular:
        extra += [a.start + sign * k * math.pi / 6 for k in range(12)]
    at = list(a.at)

    def present(c):
        period = 2 * math.pi if angular else math.inf
        for g in grid_coords + at:
            d = abs(c - g)
            if math.isfinite(period):
                d = abs((d + math.pi) % period - math.pi)
            if d < 1e-9:
                return True
        return False

    for c in extra:
        if not present(c):
            at.append(c)
    new = replace(model, analysis=replace(a, positions=grid, at=tuple(at), events=events))
    return analyze(new)


def _sweep_turns(sweep: float) -> int:
    """Whole turns of an angular sweep (rad): 1 for 360°, 2 for 720° …, 0 otherwise."""
    n = round(abs(sweep) / (2 * math.pi))
    return int(n) if n >= 1 and abs(abs(sweep) - 2 * math.pi * n) < 1e-9 else 0


def turns(result) -> int:
    """Whole turns of the first driver that the result covers: 1 for a full cycle, n for
    a sweep of n·360° (two motors of unequal speeds), 0 otherwise (not angular, a motion
    law, a partial sweep)."""
    if not _angular(result) or _driver(result).driver.motion.own_run:
        return 0
    if result.full_cycle:
        return 1
    n = _sweep_turns(result.system.model.analysis.sweep)
    if n > 1 and float(np.max(result["travel"])) >= 360.0 * n - 360.0:
        return n
    return 0


def _abscissa(result, lang: str = "en") -> tuple[np.ndarray, str]:

    d = _driver(result)
    if d.driver.motion.own_run:  # a law of its own run: ψ may reverse
        label = tr(
            "time, s ({name}: {law} law)", lang, name=d.name, law=tr(d.driver.motion.kind, lang)
        )
        return np.asarray(result["time"], dtype=float), label
    if d.joint.angular:
        start = math.degrees(result.system.model.analysis.start) % 360.0
        sense = "clockwise" if d.driver.motion.speed < 0 else "counter-clockwise"
        return (
            np.asarray(result["travel"], dtype=float),
            tr(
                "{name} rotation from {start}° ({sense}), deg",
                lang,
                name=d.name,
                start=f"{start:.4g}",
                sense=tr(sense, lang),
            ),
        )
    return np.asarray(result["travel"], dtype=float) * 1e3, tr(
        "{name} travel, mm", lang, name=d.name
    )


def _event_travel(result, e) -> float:
    """Travel at a load event: in [0, 360) for one turn, along the turns for several."""
    if turns(result) > 1:
        idx = np.nonzero(np.abs(result.t - e.t) < 1e-9 * max(1.0, abs(e.t)))[0]
        if idx.size:
            return float(result["travel"][idx[0]])
    x = abs(e.coordinate - result.coordinate[0])
    return math.degrees(x) % 360.0 if _angular(result) else x * 1e3


def _course_label(k: int, turn: int, n_turns: int, prime: str = "") -> str:
    return f"{k}{prime}" if n_turns <= 1 else f"{k}{prime}/{turn}"


def course_positions(result, n: int = 12) -> list[tuple[str, int]]:
    """Course-design positions among the rows: ``[(label, row), …]`` in order of travel.

    Position k (1…n) is the row at travel (k − 1)·360°/n from the first row, in
    the sense of motion (position 1 = ``analysis.start``); each load event
    (a row added at an exact switching position) is labelled with the number of
    the position before it and a prime (1′, 8′).  Over several turns of the first
    driver (``sweep: 720``: two motors of unequal speeds) the turn follows a slash:
    ``7/2`` is position 7 of the second turn.  Only for whole turns of an angular
    driver; otherwise empty.
    """
    n_turns = turns(result)
    if not n_turns:
        return []
    travel = np.asarray(result["travel"], dtype=float)
    out: list[tuple[float, str, int]] = []
    step = 360.0 / n
    for t in range(n_turns):
        for k in range(n):
            idx = np.nonzero(np.abs(travel - (t * 360.0 + k * step)) < 1e-6)[0]
            if idx.size:
                out.append(
                    (t * 360.0 + k * step, _course_label(k + 1, t + 1, n_turns), int(idx[0]))
                )
    for e in result.events:
        idx = np.nonzero(np.abs(result.t - e.t) < 1e-9 * max(1.0, abs(e.t)))[0]
        if not idx.size:
            continue
        x = _event_travel(result, e)
        turn, within = divmod(x, 360.0)
        before = int(math.floor(within / step + 1e-9)) + 1
        out.append((x, _course_label(before, int(turn) + 1, n_turns, "′"), int(idx[0])))
    out.sort(key=lambda r: r[0])
    return [(lab, k) for _, lab, k in out]


def _course_ticks(result, n: int = 12) -> list[tuple[float, str]]:
    """Travel of the course positions and events (whether or not they are rows)."""
    n_turns = turns(result)
    if not n_turns:
        return []
    step = 360.0 / n
    ticks = [
        (t * 360.0 + k * step, _course_label(k + 1, t + 1, n_turns))
        for t in range(n_turns)
        for k in range(n)
    ]
    for e in result.events:
        x = _event_travel(result, e)
        turn, within = divmod(x, 360.0)
        before = int(math.floor(within / step + 1e-9)) + 1
        ticks.append((x, _course_label(before, int(turn) + 1, n_turns, "′")))
    return sorted(ticks)


def _position_title(result, row: int, lang: str = "en") -> str:

    labels = [lab for lab, k in course_positions(result) if k == row]
    d = _driver(result)
    if d.joint.angular:
        coord = f"φ = {math.degrees(result.coordinate[row]) % 360.0:.2f}°"
    else:
        coord = f"s = {result.coordinate[row] * 1e3:.2f} mm"
    return tr("position {pos} ({coord})", lang, pos=labels[0], coord=coord) if labels else coord


def _sorted(result, lang: str = "en"):
    x, label = _abscissa(result, lang)
    order = np.argsort(x, kind="stable")
    return x[order], order, label
