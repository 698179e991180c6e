"""The loads' switching state on an integration piece and the switching functions.

An integration piece of :func:`~kinetostatics.dynamics.simulate` holds the loads'
switching state it started with (:func:`load_mode`): the system with those loads
held fixed (:func:`frozen_loads`) has a smooth right-hand side that continues smoothly
past the next switch, which is a root of one of the :func:`switching_functions`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from ..kinetics.conditions import activity
from ..kinetics.kinds import CONDITION_KINDS, LOAD_KINDS, ZERO_SPEED
from ..structure.system import System, coordinate_gradient

__all__ = ["load_mode", "frozen_loads", "switching_functions"]


def load_mode(
    system: System,
    loads: Sequence,
    q: np.ndarray,
    qd: np.ndarray,
    psi: np.ndarray,
    extremes: dict,
    ref_speed: float,
) -> tuple:
    """The loads' switching state at a state (q, qd, psi): per load, whether it is
    active and (a load that opposes a rate, :data:`~kinetostatics.kinetics.kinds.LOAD_KINDS`)
    the sign of that rate."""
    out = []
    for load in loads:
        on = bool(activity(system, load, q, qd, psi[0], extremes, ref_speed))
        kind, sign = LOAD_KINDS[load.kind], 0.0
        if kind.opposes:
            v = float(kind.rate(system, load, q, qd)[0])
            sign = float(np.sign(v)) if abs(v) > kind.zero(system, ref_speed) else 0.0
        out.append((on, sign))
    return tuple(out)


def frozen_loads(system: System, loads: Sequence, mode: tuple) -> System:
    """The system whose loads are those of ``mode``, held fixed: an active load
    without its conditions (a resistance as the constant force it is on this
    piece, :meth:`~kinetostatics.kinetics.kinds.LoadKind.held`), an inactive one left
    out; so the right-hand side is smooth on a piece and continues smoothly past its end
    (where the events are located)."""
    out = []
    for load, (on, sign) in zip(loads, mode):
        kind = LOAD_KINDS[load.kind]
        if not on or (kind.opposes and sign == 0.0):
            continue
        out.extend(kind.held(system, load, sign))
    return replace(system, model=replace(system.model, loads=tuple(out)))


def switching_functions(
    system: System, loads: Sequence, extremes: dict, ref_speed: float, friction: bool
) -> list[tuple[str, Callable, float]]:
    """(label, f(q, qd, psi) -> value, zero threshold) of every load switch."""
    out = []
    for load in loads:
        for c in load.active:
            for label, f, thr in CONDITION_KINDS[c.kind].switches(system, c, extremes, ref_speed):
                out.append((f"{load.name}: {label}", f, thr))
        kind = LOAD_KINDS[load.kind]
        if kind.opposes:
            out.append(
                (
                    f"{load.name}: reverses",
                    lambda q, qd, psi, load=load, kind=kind: kind.rate(system, load, q, qd)[0],
                    kind.zero(system, ref_speed),
                )
            )
    if friction:
        for k, j in enumerate(system.model.joints):
            if j.has_friction:
                thr = ZERO_SPEED * ref_speed * (1.0 if j.angular else system.l_ref)
                out.append(
                    (
                        f"{j.name}: friction reverses",
                        lambda q, qd, psi, k=k: coordinate_gradient(system, q, k) @ qd,
                        thr,
                    )
                )
    return out
