"""The phase of a ``cam`` pair: whether its follower sits where the law puts it.

``cam.py`` asks these at the start pose (a follower sketched on the mirror side, a
``rise`` of the wrong sense or an ``offset`` that is not the guide's is refused, with the
fix) and over a run (a follower that leaves the phase later, or one the contact force would
pull off the cam, is warned, with the cam angles of those rows as ranges).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..base.arrays import runs
from ..base.geometry import dot, perp, turn, wrap_angle
from ._camprofile import Synthesis

PHASE_TOL = 1e-7  # the follower's misfit at the start, relative to the prime radius


def misfit(cam, syn: Synthesis, qi, qj):
    """How far (relative to the prime radius) the follower lies, at poses ``(..., 3)``
    with the frame at zero, from where ``syn``'s law puts it at the cam's rotation: its
    point (knife, roller) or its face's angle and support value (flat); ``(...)``."""
    Ao, Ap, d, z, phi = cam._pose(qi, qj)
    theta = syn.sigma * qi[..., 2]
    scale = syn.base + syn.radius
    if syn.flat:
        b, _, _, h, _, _ = syn.support(theta)
        n = cam._face_angle(phi) + qi[..., 2]
        N = np.stack((np.cos(n), np.sin(n)), axis=-1)
        beta = b + syn.sigma * theta  # the normal in the frame
        return np.abs(wrap_angle(n - beta)) + np.abs(dot(N, d) - h) / scale
    F = syn.frame_point(theta)[0]
    return np.abs(F - (d[..., 0] + 1j * d[..., 1])) / scale


def phase_fix(cam, qi, qj) -> str:
    """The one change of the cam's keys that fits the assembled pose, or where to
    sketch the follower."""
    s = cam.synthesis
    other = {1: "cw", -1: "ccw"}
    tries = []
    if s.pivot is not None:
        tries.append(
            (
                replace(s, kappa=-s.kappa),
                f"`oscillating.rise: {other[s.kappa]}` fits the "
                "assembly (the arm rising the other way)",
            )  # fmt: skip
        )
    tries.append((replace(s, sigma=-s.sigma), f"`rotation: {other[s.sigma]}` fits the assembly"))
    if s.pivot is None and not s.flat:
        d = cam._pose(qi, qj)[2]
        e = float(dot(d, -s.sigma * perp(np.asarray(s.direction, float))))
        if abs(e - s.offset) > PHASE_TOL * (s.base + s.radius):
            return (
                f"the follower point runs {e * 1e3:.6g} mm from the cam centre across "
                f"its guide, not at `translating.offset: {s.offset * 1e3:.6g}` mm: give "
                "the guide's offset (or move the guide)"
            )
    for syn, text in tries:
        if syn.pivot is not None and isinstance(syn.beta0(), str):
            continue
        if float(misfit(cam, syn, qi, qj)) <= PHASE_TOL:
            return text
    where = ""
    if not s.flat:
        F = complex(s.frame_point(np.array([s.sigma * qi[2]]))[0][0])
        x = qi[:2] + turn(qi, cam.o) + np.array([F.real, F.imag])
        where = f" near [{x[0] * 1e3:.6g}, {x[1] * 1e3:.6g}] mm"
    keys = "`oscillating.rise`" if s.pivot is not None else "`translating.direction`"
    return (
        f"sketch the follower point {cam.links[1]}.{cam.names[1]}{where} (where the law "
        f"puts it at the start), or if it belongs where it is, reverse {keys} or `rotation`"
    )


def start_problem(cam, qi, qj) -> str:
    """The follower must touch the cam where its law puts it: the contact's cam angle
    is the cam's rotation from the frame (the ground) in its sense ``rotation``.  A
    follower sketched on the mirror side, a ``rise`` of the wrong sense or an
    ``offset`` that is not the guide's assemble on the profile at another cam angle:
    the law's phase is lost, silently; the message names both angles and the fix."""
    qi, qj = np.asarray(qi, float), np.asarray(qj, float)
    s = cam.synthesis
    if float(misfit(cam, s, qi, qj)) <= PHASE_TOL:
        return ""
    found = float(np.mod(cam._contact(qi, qj)[0], 2 * math.pi))
    expected = float(np.mod(s.sigma * qi[2], 2 * math.pi))
    lift = s.law.value(np.array([found, expected]))[0]
    unit, k = ("°", 180 / math.pi) if s.pivot is not None else (" mm", 1e3)
    return (
        f"cam joint '{cam.name}': the follower is out of phase with its law: at the "
        f"start it touches the cam at cam angle {math.degrees(found):.4g}° while the cam "
        f"is at {math.degrees(expected):.4g}° (lift {lift[0] * k:.4g}{unit} instead of "
        f"{lift[1] * k:.4g}{unit}); {phase_fix(cam, qi, qj)}"
    )


def warnings(cam, lam, qi, qj) -> tuple[str, ...]:
    """Once per run: the rows where the contact force would pull (the follower leaves
    the cam), and the rows where the follower is not where its law puts it (drift), each
    with its cam angles as the ranges of consecutive rows, each listed once."""
    out = []
    pull = np.asarray(lam[..., 0] < 0)
    if pull.ndim == 1 and pull.any():
        theta = np.degrees(np.mod(cam._contact(qi, qj)[0], 2 * math.pi))
        out.append(
            f"cam joint '{cam.name}': the follower would leave the cam at {int(pull.sum())} "
            f"of {pull.size} positions, cam angles {ranges(pull, theta)}: the contact force "
            f"there would pull ({cam.name}.status = 1); a spring or a larger preload keeps "
            "the follower on the cam"
        )
    drift = drift_warning(cam, qi, qj)
    return (*out, drift) if drift else tuple(out)


def drift_warning(cam, qi, qj) -> str:
    """The rows where the follower is not where its law puts it at the cam's rotation
    (it left the law's phase: the guide or the pivot is not where the joint places it,
    though it was at the start), as one warning; '' where there are none."""
    off = np.asarray(misfit(cam, cam.synthesis, qi, qj) > PHASE_TOL)
    if not (off.ndim == 1 and off.any()):
        return ""
    s = cam.synthesis
    theta = np.degrees(np.mod(s.sigma * qi[..., 2], 2 * math.pi))
    where = "`translating` (its direction)" if s.pivot is None else "`oscillating`"
    return (
        f"cam joint '{cam.name}': the follower leaves its law's phase at "
        f"{int(off.sum())} of {off.size} positions, cam angles {ranges(off, theta)}: "
        f"it does not move as {where} places it (its guide or pivot is elsewhere), "
        f"so {cam.name}.cam_angle is not the cam's and the lift not the law's there"
    )


def ranges(mask: np.ndarray, angle: np.ndarray) -> str:
    """``61°–119°, 181°–239°``: the angles (deg) of the runs of consecutive rows in
    ``mask``, each listed once (six at most)."""
    parts: list[str] = []
    for a, b in runs(mask):
        lo, hi = f"{angle[a]:.4g}°", f"{angle[b]:.4g}°"
        text = lo if lo == hi else f"{lo}–{hi}"
        if text not in parts:
            parts.append(text)
    return ", ".join(parts[:6]) + (", …" if len(parts) > 6 else "")
