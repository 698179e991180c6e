"""Radial clearance at a revolute pair: the massless-link shorthand and its models.

A revolute [i, j] with radial clearance e (bushing radius − journal radius)
is replaced by a massless *clearance link* ``<joint>_gap`` from the pin on
link i to the pin on link j (docs/clearance.md):

- ``prescribed`` (model a1, the source text's "continuous contact" model):
  the link has the fixed length e, two revolutes (``<joint>`` on i's side,
  ``<joint>_j`` on j's side) and a motion driver ``<joint>_turn`` that
  prescribes its rotation relative to link i (speed and constant
  acceleration).  That driver's effort is the torque the prescription needs;
  its power is reported (it injects energy).
- ``contact`` (model b): the link's length s is free too: a second massless
  link ``<joint>_end`` slides along it (prismatic ``<joint>_slide``) and is
  pinned to j.  Two effort drivers make the relative position of the pins
  free coordinates: ``<joint>_turn`` (the link's angle relative to i, effort 0)
  and ``<joint>_contact`` (s, effort the Lankarani–Nikravesh contact force
  of :mod:`kinetostatics.dynamics.contact` when s > e).

Model (a2), the two-force member for kinetostatics, is :func:`two_force_member`.

At t = 0 the clearance link lies along the ideal joint's force: the journal
bears on the bushing where the force pushes it, so p_j − p_i = −e F̂_ij
(F_ij the force of i on j; the link is in tension).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..analysis import analyze
from ..analysis.pipeline import _require_motion_drivers
from ..base.geometry import rotate
from ..errors import AssemblyError, ModelError
from ..joints.prismatic import Prismatic
from ..joints.revolute import Revolute
from ..kinematics.derivatives import derivatives
from ..kinematics.schedule import schedule
from ..kinematics.start import start_pose
from ..kinetics.inverse import kinetics
from ..model import Clearance, Driver, Link, Model, MotionLaw
from ..structure.system import build_system
from .engine import Dynamics

__all__ = [
    "Clearance",
    "expand",
    "ideal",
    "with_clearance",
    "ideal_force",
    "two_force_member",
    "REFERENCE",
]

REFERENCE = 0.01  # m: the clearance link's reference point for its angle


def _names(joint: str) -> dict[str, str]:
    return {
        "link": f"{joint}_gap",
        "end": f"{joint}_end",
        "joint_j": f"{joint}_j",
        "slide": f"{joint}_slide",
        "driver": f"{joint}_turn",
        "contact": f"{joint}_contact",
    }


def ideal(model: Model) -> Model:
    """The model without its clearances (the ideal joints), or the model itself."""
    return model.ideal if model.ideal is not None else model


def with_clearance(
    model: Model, size: float | None = None, kind: str | None = None, **changes
) -> Model:
    """The ideal model expanded with the file's clearances changed: every ``size``
    (m) and/or ``model`` (``kind``), and any other :class:`Clearance` fields."""
    base = ideal(model)
    specs = []
    for c in model.clearances:
        new = dict(changes)
        if size is not None:
            new["size"] = float(size)
        if kind is not None:
            new["model"] = kind
        specs.append(replace(c, **new))
    return expand(base, specs)


def _start_state(model: Model):
    """(system, q, q̇, q̈, ψ) of the model at t = 0: the first analysis position, or
    at rest under the effort drivers (forward dynamics' first evaluation)."""

    if any(d.motion is None for d in model.drivers):
        dyn = Dynamics(model)
        ev = dyn.state(0.0, np.concatenate((dyn.start(), np.zeros(dyn.n_f), [0.0])))
        return dyn.system, ev.q, ev.qd, ev.qdd0 + ev.accel @ ev.dqdd, ev.psi
    system = build_system(model)
    _require_motion_drivers(system)  # a file without drivers: a located error, not a crash
    drive = schedule(system)
    q, _ = start_pose(system, drive)
    psi, pd, pdd = (x[0] for x in drive(np.array([0.0])))
    qd, qdd, _ = derivatives(system, q[None], pd[None], pdd[None])
    return system, q, qd[0], qdd[0], psi


def ideal_force(model: Model, joints, state=None) -> dict[str, np.ndarray]:
    """Force of i on j (N, global) in each revolute of ``joints`` at t = 0
    (see :func:`_start_state`)."""
    system, q, qd, qdd, psi = state or _start_state(model)
    kin = kinetics(system, q[None], qd[None], qdd[None], psi[None], ref_speed=1.0)
    names = [c.name for c in system.constraints]
    out = {}
    for name in joints:
        k = names.index(name)
        r = system.constraints[k].reaction(kin.x0[0, system.rows_of(k)], None, None)
        out[name] = np.array([float(r["Fx"]), float(r["Fy"])])
    return out


def _global(model, q, index, link: str, p_local) -> tuple[np.ndarray, float]:
    """Global position of a local point and the link's angle."""
    if model.link(link).ground:
        return np.asarray(p_local, dtype=float), 0.0
    k = index[link]
    return q[3 * k : 3 * k + 2] + rotate(q[3 * k + 2], np.asarray(p_local, float)), q[3 * k + 2]


def expand(model: Model, clearances) -> Model:
    """The model with each clearance's revolute replaced by its massless links.

    Raises ModelError (at the clearance's ``where``) for a joint that is not a
    revolute without a driver, an unknown model, a negative size.
    """
    clearances = tuple(clearances)
    if not clearances:
        return model
    problems = []
    for c in clearances:
        j = next((x for x in model.joints if x.name == c.joint), None)
        if not isinstance(j, Revolute):
            problems.append(
                (
                    c.where,
                    f"clearance at '{c.joint}': not a revolute joint of the "
                    "model (clearance applies to revolutes)",
                )
            )
        elif any(d.joint == c.joint for d in model.drivers):
            problems.append(
                (
                    c.where,
                    f"clearance at '{c.joint}': a driver acts on this joint; "
                    "give the clearance to an undriven revolute",
                )
            )
        if c.model not in ("prescribed", "contact"):
            problems.append((c.where, f"clearance model '{c.model}': use prescribed or contact"))
        if not (np.isfinite(c.size) and c.size >= 0):
            problems.append((c.where, f"clearance size {c.size!r}: must be ≥ 0"))
        if c.model == "contact" and c.contact is None:
            problems.append((c.where, "a contact clearance needs its contact law (contact: ...)"))
    if problems:
        raise ModelError(problems)
    state = _start_state(model)
    force = ideal_force(model, [c.joint for c in clearances if c.angle is None], state)
    q, index = state[1], {n: k for k, n in enumerate(state[0].links)}
    links, joints = list(model.links), []
    drivers, sketch = list(model.drivers), dict(model.sketch)
    by_joint = {c.joint: c for c in clearances}
    for j in model.joints:
        c = by_joint.get(j.name)
        if c is None:
            joints.append(j)
            continue
        n = _names(j.name)
        i_link, j_link = j.links
        centre, th_i = _global(model, q, index, i_link, j.p_i)
        beta = c.angle
        if beta is None:
            f = force[j.name]
            beta = float(np.arctan2(-f[1], -f[0])) if np.hypot(*f) > 0 else 0.0
        axis = np.array([np.cos(beta), np.sin(beta)])
        e = c.size
        # link i's reference point for the relative angle: its point farthest from the pin
        pts = model.link(i_link).points
        ref_name = max(pts, key=lambda k: float(np.hypot(*(pts[k] - j.p_i))))
        d_local = pts[ref_name] - j.p_i
        offset = -float(np.arctan2(d_local[1], d_local[0]))
        psi0 = beta - (th_i - offset)
        gap = Link(
            n["link"],
            {"i": np.zeros(2), "ref": np.array([REFERENCE, 0.0]), "j": np.array([e, 0.0])},
            where=c.where,
        )
        links.append(gap)
        joints.append(
            Revolute(
                j.name,
                (i_link, n["link"]),
                j.where,
                j.p_i,
                np.zeros(2),
                (j.point_names[0], "i"),
                j.rho,
            )
        )
        sketch[f"{n['link']}.i"] = centre
        sketch[f"{n['link']}.ref"] = centre + REFERENCE * axis
        sketch[f"{j_link}.{j.point_names[1]}"] = centre + e * axis
        if c.model == "prescribed":
            joints.append(
                Revolute(
                    n["joint_j"],
                    (n["link"], j_link),
                    j.where,
                    np.array([e, 0.0]),
                    j.p_j,
                    ("j", j.point_names[1]),
                )
            )
            law = MotionLaw(c.speed, c.acceleration, start=psi0)
            drivers.append(
                Driver(n["driver"], j.name, law, None, offset, (ref_name, "ref"), where=c.where)
            )
        else:
            end = Link(n["end"], {"j": np.zeros(2)}, where=c.where)
            links.append(end)
            joints.append(
                Prismatic(
                    n["slide"],
                    (n["link"], n["end"]),
                    j.where,
                    np.zeros(2),
                    np.array([1.0, 0.0]),
                    np.zeros(2),
                    0.0,
                    ("i",),
                    "j",
                )
            )
            joints.append(
                Revolute(
                    n["joint_j"],
                    (n["end"], j_link),
                    j.where,
                    np.zeros(2),
                    j.p_j,
                    ("j", j.point_names[1]),
                )
            )
            sketch[f"{n['end']}.j"] = centre + e * axis
            drivers.append(
                Driver(n["driver"], j.name, None, 0.0, offset, (ref_name, "ref"), where=c.where)
            )
            drivers.append(
                Driver(n["contact"], n["slide"], None, c.contact.for_clearance(e), where=c.where)
            )
    return replace(
        model,
        links=tuple(links),
        joints=tuple(joints),
        drivers=tuple(drivers),
        sketch=sketch,
        clearances=clearances,
        ideal=model,
    )


@dataclass
class TwoForceResult:
    """Model (a2) over the positions: ``coordinate`` (n_pos,) driver coordinates,
    ``beta`` (n_pos, n_clearance) global angles of the clearance links (p_i → p_j),
    ``iterations`` (n_pos,), ``results`` the expanded model's analysis per position
    (one row each), ``ideal`` the ideal model's analysis."""

    coordinate: np.ndarray
    beta: np.ndarray
    iterations: np.ndarray
    results: list
    ideal: object

    def column(self, name: str) -> np.ndarray:
        """A result column over the positions (e.g. ``"A.Fx"``, ``"motor.torque"``)."""
        return np.array([r[name][0] for r in self.results])


def _sketch_from(system, q) -> dict[str, np.ndarray]:
    """Global positions of every moving link's points at ``q``: an exact sketch."""
    out = {}
    for k, name in enumerate(system.links):
        for pt, p in system.model.link(name).points.items():
            out[f"{name}.{pt}"] = q[3 * k : 3 * k + 2] + rotate(q[3 * k + 2], p)
    return out


def two_force_member(
    model: Model, sizes, *, positions=None, iterations: int = 30, tol: float = 1e-10
) -> TwoForceResult:
    """Model (a2): kinetostatics with each journal on its bearing circle along the
    joint's reaction, positions and forces iterated to consistency.

    ``model``: an ideal model whose motion drivers equal its mobility; ``sizes``:
    {revolute: e (m)}; ``positions``: driver coordinates (default the analysis).
    At each position the clearance links (length e, frictionless pins: two-force
    members) start along −F_ij of the ideal joint; the expanded linkage is solved
    with each link held at its global angle β (its rotation relative to link i
    frozen over the instant: the quasi-static reading, docs/clearance.md), the
    reactions recomputed and β set along the new −F_ij, until |Δβ| ≤ ``tol`` rad.
    At the fixed point the link carries no couple: the effort of its driver is 0.
    """

    names = list(sizes)
    res0 = analyze(model, friction=False, positions=positions)
    n = res0.q.shape[0]
    beta = np.stack([np.arctan2(-res0[f"{k}.Fy"], -res0[f"{k}.Fx"]) for k in names], axis=-1)
    used = np.zeros(n, dtype=int)
    out = []
    for p in range(n):
        c0 = float(res0.coordinate[p])
        base = replace(
            model,
            sketch=_sketch_from(res0.system, res0.q[p]),
            analysis=replace(model.analysis, start=c0),
        )
        b = beta[p].copy()
        for it in range(iterations):  # noqa: B007 (the count is read after the loop)
            specs = [Clearance(k, float(sizes[k]), angle=float(bk)) for k, bk in zip(names, b)]
            r = analyze(expand(base, specs), friction=False, positions=np.array([c0]))
            nb = np.array([np.arctan2(-r[f"{k}.Fy"][0], -r[f"{k}.Fx"][0]) for k in names])
            # the links' actual angles (a link on a moved link i is turned with it)
            now = np.array([r.q[0, 3 * r.system.link_index(f"{k}_gap") + 2] for k in names])
            step = np.angle(np.exp(1j * (nb - now)))
            b = b + step
            if np.max(np.abs(step)) <= tol:
                break
        else:
            raise AssemblyError(
                "clearance links",
                f"{np.degrees(c0):.6g}°",
                f"the two-force-member iteration did not converge in "
                f"{iterations} steps (last change {np.max(np.abs(step)):.3g} rad)",
            )
        used[p], beta[p] = it + 1, nb
        out.append(r)
    return TwoForceResult(np.asarray(res0.coordinate), beta, used, out, res0)


def motion_over_time(run, link: str, t) -> dict[str, np.ndarray]:
    """θ (rad, unwrapped), ω, α of ``link`` and every motion driver's effort and power
    (``<driver>.effort``, ``<driver>.power``) at times ``t`` of a forward-dynamics run
    (:class:`~kinetostatics.dynamics.Simulation` or a contact run)."""
    dyn = run.dynamics
    t = np.atleast_1d(np.asarray(t, dtype=float))
    y = run.sample(t)
    k = 3 * dyn.system.link_index(link) + 2
    out: dict[str, list] = {"theta": [], "omega": [], "alpha": []}
    prescribed = [n for n in dyn.names if n not in dyn.free_names]
    for tk, yk in zip(t, y):
        ev = dyn.state(float(tk), yk)
        qdd = ev.qdd0 + ev.accel @ ev.dqdd
        out["theta"].append(ev.q[k])
        out["omega"].append(ev.qd[k])
        out["alpha"].append(qdd[k])
        speeds = dyn._speeds(tk, yk)
        for name in prescribed:
            d = dyn.names.index(name)
            out.setdefault(f"{name}.effort", []).append(ev.effort[d])
            out.setdefault(f"{name}.power", []).append(ev.effort[d] * speeds[d])
    res = {key: np.array(v) for key, v in out.items()}
    res["theta"] = np.unwrap(res["theta"])
    return res
