"""Positions along the whole path by closed-form dyads (:mod:`.dyads`), where every
group has one: the branch is decided by the dyads' discriminants along the path,
independently of the rows (:func:`_change_points`), and the angles are unwrapped
along auxiliary times (:func:`path_times`).  :func:`closed_form_near` solves near a
guess (stepping methods, events).
"""

from __future__ import annotations

import math

import numpy as np

from ..base.arrays import entries_last, sorted_distinct
from ..base.geometry import framed_poses
from ..structure.system import System, phi
from .continuation import COARSE_STEP, Drive, Singularity, time_step
from .dyads import MARGIN, ClosedForms
from .newton import DISC_TOL, MAX_ITER, TOL, group_condition
from .plan import planned_phi
from .schedule import Schedule

__all__ = ["DISC_SCAN", "DISC_NEAR", "path_times", "closed_form_path", "closed_form_near"]

DISC_SCAN = np.radians(5.0)  # sample spacing of the discriminants along a closed-form path
DISC_NEAR = 1e-3  # a local minimum of D is refined if a sample beside it is this low


def path_times(system: System, t: np.ndarray, drive: Drive) -> tuple[np.ndarray, np.ndarray]:
    """``t``, then t = 0 (the start pose), then auxiliary times every ≤ 30° of the
    driver over the range, and the order that sorts them: the closed-form angles
    are unwrapped along it."""
    coarse = time_step(system, 0.0, drive, COARSE_STEP)
    lo, hi = min(0.0, float(t.min())), max(0.0, float(t.max()))
    aux = _evenly(lo, hi, math.ceil((hi - lo) / coarse) + 2)
    if getattr(drive, "laws", ()):  # where a law turns back, a group may touch a toggle
        aux = np.concatenate((aux, drive.turning_times(lo, hi)))
    tt = np.concatenate((t, [0.0], aux))
    return tt, np.argsort(tt, kind="stable")


def _evenly(lo: float, hi: float, num: int) -> np.ndarray:
    """``np.linspace(lo, hi, num)`` for ``num ≥ 2`` floats, by its operations (the same
    numbers) without its ~15 µs of checks and conversions: it is called once per analysis."""
    y = np.arange(num, dtype=float)
    step = (hi - lo) / (num - 1)
    if step == 0:  # linspace's way with a step that underflows
        y /= num - 1
        y *= hi - lo
    else:
        y *= step
    y += lo
    y[-1] = hi
    return y


def closed_form_path(
    system: System,
    forms: ClosedForms,
    q0: np.ndarray,
    t: np.ndarray,
    drive: Drive,
    singular: list | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
    """Closed-form positions at times ``t (N,)`` from start poses ``q0 (V, 1, n_q)``
    (V variants, stacked or not): ``(q (V, N, n_q), ok (V,), signs (V, N, n_groups),
    poses)``, ``poses`` one model's rows as :func:`~.system.link_poses` lays them out,
    their frames those the pass placed the links with (no cosine evaluated again; None
    for stacked variants).

    Each group is solved with the closed-form sign of its start pose times
    ``signs``: the sign changes at every *change point* of the group, where its
    discriminant D touches zero (:func:`_change_points`, located between the rows
    and independently of them), so that the path is C¹.  With ``singular`` a list
    (one model, V = 1) the change points are appended to it as singular
    positions; without, a variant that passes one is not ok (its own analysis
    reports it).  ``ok`` also needs D ≥ −``DISC_TOL`` along the path (the links
    reach; else the Newton path reports where they do not) and a sample of the
    positions to satisfy Φ = 0.  Auxiliary points every ≤ 30° of the driver
    (:func:`path_times`) let the angles be unwrapped continuously from the start pose.
    """
    n_v = len(q0)
    lo, hi = min(0.0, float(t.min())), max(0.0, float(t.max()))
    flips, ok = _memo_change_points(system, forms, q0, lo, hi, drive, singular is not None)
    tt, order = path_times(system, t, drive)
    psi = drive(tt)[0]
    signs = _branch_signs(flips, np.broadcast_to(tt, (n_v, len(tt))))
    frames = np.empty((len(system.links), 2, n_v, len(tt))) if singular is not None else None
    q, disc = _closed_forms(forms, (n_v, len(tt), q0.shape[-1]), psi, signs, frames)
    ok &= np.all(disc >= -DISC_TOL, axis=(-2, -1))
    start, ang = len(t), slice(2, None, 3)
    columns = np.moveaxis(q, -1, 0)  # (n_q, V, points): each coordinate one run (a view)
    for h in (3 * k + 2 for k in forms.wrapping):  # the angles that may jump by 2π: nearest
        angle = columns[h]  # the start pose, as the guess; then unwrapped along the path
        angle += 2 * np.pi * np.round((q0[:, :, h] - angle) / (2 * np.pi))
        path = angle[:, order]
        turned = _unwrapped(path)
        if turned is not path:  # it crossed the branch cut somewhere
            angle[:, order] = turned
    q[..., ang] += (2 * np.pi * np.round((q0[:, 0, ang] - q[:, start, ang]) / (2 * np.pi)))[:, None]
    pe = None
    if frames is not None:  # one model: the rows' poses, their frames the pass's
        pe = framed_poses(np.moveaxis(q[0, :start], -1, 0), frames[:, :, 0, :start])
        pe.flags.writeable = False
    q = np.ascontiguousarray(q[:, :start])
    probe = slice(None, None, max(1, start // 32))
    if n_v == 1:  # one model: Φ by its plan (the pairs' residuals written out)
        at = planned_phi(system, q[0, probe], psi[:start][probe])[None]
    else:
        at = phi(system, q[:, probe], psi[:start][probe])
    res = np.max(np.abs(at), axis=(-2, -1))
    ok &= res <= 1e3 * TOL * np.ravel(np.broadcast_to(system.l_ref, (n_v, 1)))
    if singular is None:
        for f in flips:
            ok &= np.all(np.isnan(f), axis=-1)
    else:
        found = [(ts, g) for g, f in enumerate(flips) for ts in f[0] if not np.isnan(ts)]
        for ts, g in sorted(found):
            at = np.array([[ts]])
            qs, _ = _closed_forms(forms, q0.shape, drive(at)[0], _branch_signs(flips, at))
            coord = float(drive(at)[0][0, 0, 0]) if system.motion_drivers else ts
            singular.append(
                Singularity(
                    system.plans[g].group.label,
                    float(ts),
                    coord,
                    float(group_condition(system, qs[0, 0], system.plans[g])),
                )
            )
    return q, ok, signs[:, :start], pe


def _unwrapped(path: np.ndarray) -> np.ndarray:
    """``np.unwrap(path, axis=1)``: each step between neighbours along axis 1 taken to the
    nearest multiple of 2π away (the whole turns counted as integers, summed exactly);
    half the passes of NumPy's, whose ~12 cost 1.5 ms over a 36,000-position path; the
    path itself where no step turns (most paths: the angles were taken nearest the start
    pose's)."""
    turns = np.round(np.diff(path, axis=1) / (2 * np.pi))
    if not turns.any():
        return path
    out = path.copy()
    out[:, 1:] -= 2 * np.pi * np.cumsum(turns, axis=1)
    return out


def _memo_change_points(system: System, forms, q0, lo: float, hi: float, drive, one: bool):
    """:func:`_change_points`, kept in ``system.memo`` for one model's path over the same
    span from the same start and schedule (a property of the mechanism, like its start
    pose): a repeated analysis does not search the span again, and gets the same numbers
    as the first (the key is exact, so the result never depends on earlier calls)."""
    if not (one and isinstance(drive, Schedule)):
        return _change_points(system, forms, q0, lo, hi, drive)
    acc = drive.acceleration
    key = (
        lo,
        hi,
        q0.tobytes(),
        drive.start.tobytes(),
        drive.speed.tobytes(),
        None if acc is None else np.asarray(acc).tobytes(),
    )
    memo = system.memo.setdefault("change_points", {})
    hit = memo.get(key)
    laws = tuple(drive.laws)
    if hit is None or len(hit[0]) != len(laws) or any(a is not b for a, b in zip(hit[0], laws)):
        if len(memo) >= 8:  # a few spans at most (the run, the cycle nodes, the flywheel)
            memo.clear()
        hit = (laws, _change_points(system, forms, q0, lo, hi, drive))
        memo[key] = hit
    flips, ok = hit[1]
    return [f.copy() for f in flips], ok.copy()


def _closed_forms(
    forms: ClosedForms, shape: tuple, psi: np.ndarray, signs: np.ndarray, frames=None
) -> tuple[np.ndarray, np.ndarray]:
    """The closed forms' pass into new coordinates ``q (shape)``, stored coordinate-major
    (the pass writes every column), group g on its start sign × ``signs[..., g]``:
    (q, the groups' discriminants D ``(..., n_groups)``); the links' frames into
    ``frames`` (``(n_links, 2) + shape[:-1]``) where given."""
    q = entries_last(np.empty(shape[-1:] + tuple(shape[:-1])), 1)
    return forms.run(q, psi, signs, frames)


def _branch_signs(flips: list, t: np.ndarray) -> np.ndarray:
    """±1 per group at times ``t (V, M)``: −1 where an odd number of the group's
    change points ``flips[g] (V, K)`` (NaN: none) lie between t = 0 and t."""
    if not any(f.shape[-1] for f in flips):  # no change point at all (most paths)
        return np.ones(t.shape + (len(flips),))
    out = []
    for f in flips:
        if not f.shape[-1]:  # no change point: +1 everywhere (most paths)
            out.append(np.ones(t.shape))
            continue
        f, tt = f[:, None, :], t[..., None]
        with np.errstate(invalid="ignore"):
            n = np.sum(((f > 0) & (f <= tt)) | ((f < 0) & (f >= tt)), axis=-1)
        out.append(np.where(n % 2, -1.0, 1.0))
    return np.stack(out, axis=-1) if out else np.ones(t.shape + (0,))


def _change_points(
    system: System, forms, q0: np.ndarray, lo: float, hi: float, drive: Drive
) -> tuple[list, np.ndarray]:
    """The change points of every group over ``[lo, hi]``: ``(flips, ok)``, flips[g]
    ``(V, K)`` their times (NaN padding), ``ok (V,)`` where no local minimum of a
    discriminant lies below −``DISC_TOL`` (the links reach everywhere).

    A group's discriminant D(t) is smooth along the path.  It is sampled every
    ≤ ``DISC_SCAN`` of the driver (plus t = 0 and the times a motion law turns
    back), never at the output rows, with slopes by central differences; the
    interior minima of the cubic Hermite interpolant between samples are added
    as samples where they are low (so a sample lies next to every low minimum,
    to the interpolant's O(h⁴) error), and every sign change − to + of the slope with a sample
    beside it at D ≤ ``DISC_NEAR`` brackets a local minimum of D, refined by a
    safeguarded Newton iteration on D' = 0.  A
    minimum with |D| ≤ ``DISC_TOL`` is a change point: D touches zero there
    (D ≈ c (t − t*)²), the two assemblies meet, and the C¹ continuation is the
    other closed-form sign (√D ∝ |t − t*| changes its signed form).  A minimum
    above ``DISC_TOL``, however small (a near-toggle), keeps the sign.
    Groups are taken in solve order: a group's change points enter the
    closed forms of the later groups.
    """
    n_v = len(q0)
    fine = time_step(system, 0.0, drive, DISC_SCAN)
    eta = 1e-4 * fine
    ts = np.linspace(lo, hi, int(np.ceil((hi - lo) / fine)) + 1)
    if getattr(drive, "laws", ()):
        ts = np.concatenate((ts, drive.turning_times(lo, hi)))
    ts = sorted_distinct(np.append(ts, 0.0))
    ts = np.broadcast_to(ts, (n_v, len(ts)))
    flips = [np.full((n_v, 0), np.nan) for _ in range(len(forms))]
    ok = np.ones(n_v, dtype=bool)

    def disc(t):  # D, D', D'' of every group at times t (V, M): (V, M, G) each
        return _discriminants(forms, q0, drive, flips, eta, t)

    g0 = 0
    while g0 < len(forms):  # again from a group past which the signs changed
        d, m, _ = disc(ts)
        tg = _with_low_minima(ts, d, m, g0, hi)
        if tg is not ts:
            d, m, _ = disc(tg)
        ok &= np.all(d[..., g0:] >= -DISC_TOL, axis=(-2, -1))
        for g in range(g0, len(forms)):
            brackets = _minimum_brackets(tg, d[..., g], m[..., g])
            if brackets is None:
                continue
            valid, a_t, b_t = brackets
            tm = _minimum_in(disc, g, a_t, b_t, 1e-9 * fine)
            dm = disc(tm)[0][..., g]
            ok &= np.all(~valid | (dm >= -DISC_TOL), axis=-1)
            f = np.where(valid & (np.abs(dm) <= DISC_TOL), tm, np.nan)
            flips[g] = f[:, ~np.all(np.isnan(f), axis=0)]  # a column of NaN counts nowhere
            if not np.all(np.isnan(flips[g])):
                break  # the later groups see these change points
        g0 = g + 1
    return flips, ok


def _discriminants(forms, q0: np.ndarray, drive: Drive, flips: list, eta: float, t):
    """D, D', D'' of every group's closed form at times ``t (V, M)`` on the branches the
    change points ``flips`` so far give, the derivatives by central differences of step
    ``eta``: ``(V, M, G)`` each."""
    at = t[None] + np.array([-eta, 0.0, eta])[:, None, None]
    at = np.moveaxis(at, 0, -1).reshape(len(q0), -1)
    _, d = _closed_forms(forms, at.shape + q0.shape[-1:], drive(at)[0], _branch_signs(flips, at))
    d = d.reshape(t.shape + (3, -1))
    return (
        d[..., 1, :],
        (d[..., 2, :] - d[..., 0, :]) / (2 * eta),
        (d[..., 2, :] - 2 * d[..., 1, :] + d[..., 0, :]) / eta**2,
    )


def _with_low_minima(ts: np.ndarray, d: np.ndarray, m: np.ndarray, g0: int, hi: float):
    """``ts (V, M)`` with the interior minima of the cubic Hermite interpolant of the
    discriminants ``d`` (slopes ``m``; groups from ``g0`` on) that lie low (≤ 10
    ``DISC_NEAR``) added as samples, sorted (rows padded with ``hi``); ``ts`` itself where
    there are none."""
    h = np.diff(ts, axis=-1)[..., None]
    d0, d1, m0, m1 = d[:, :-1], d[:, 1:], m[:, :-1] * h, m[:, 1:] * h
    b = -6 * d0 - 4 * m0 + 6 * d1 - 2 * m1  # Hermite p'(s) = a s² + b s + c, p'' > 0 root
    a = 6 * d0 + 3 * m0 - 6 * d1 + 3 * m1
    with np.errstate(all="ignore"):
        s = 2 * m0 / (-b - np.sqrt(b * b - 4 * a * m0))
    low = (
        (s * s * (2 * s - 3) + 1) * d0
        + s * (s - 1) ** 2 * m0
        + s * s * (3 - 2 * s) * d1
        + s * s * (s - 1) * m1
    )  # the interpolant's minimum
    inner = (s > 0) & (s < 1) & (low <= 10 * DISC_NEAR)
    inner[..., :g0] = False
    if not inner.any():
        return ts
    extra = np.where(inner, ts[:, :-1, None] + np.where(inner, s, 0.0) * h, np.nan)
    extra = np.sort(extra.reshape(len(ts), -1), axis=-1)[:, : int(inner.sum((-2, -1)).max())]
    return np.sort(np.concatenate((ts, np.where(np.isnan(extra), hi, extra)), axis=-1), axis=-1)


def _minimum_brackets(tg: np.ndarray, dg: np.ndarray, mg: np.ndarray):
    """(valid, a_t, b_t) ``(V, K)``: the samples ``tg`` between which one group's
    discriminant ``dg`` (slope ``mg``) has a local minimum (the slope turns from − to +
    with a sample beside it at D ≤ ``DISC_NEAR``), padded where a variant has fewer
    (``valid`` False); None where none has any."""
    br = (mg[:, :-1] < 0) & (mg[:, 1:] >= 0) & (np.minimum(dg[:, :-1], dg[:, 1:]) <= DISC_NEAR)
    n_k = int(br.sum(axis=-1).max())
    if n_k == 0:
        return None
    idx = np.argsort(~br, axis=-1, kind="stable")[:, :n_k]
    return (
        np.take_along_axis(br, idx, -1),
        np.take_along_axis(tg[:, :-1], idx, -1),
        np.take_along_axis(tg[:, 1:], idx, -1),
    )


def _minimum_in(disc, g: int, a_t: np.ndarray, b_t: np.ndarray, tol: float) -> np.ndarray:
    """The minima of group ``g``'s discriminant in the brackets [a_t, b_t] (D' < 0 at
    a_t, ≥ 0 at b_t) by a safeguarded Newton iteration on D'(t) = 0 (bisection where a
    step leaves the bracket), to ``tol`` in t; ``disc(t)`` gives D, D', D''."""
    tm = 0.5 * (a_t + b_t)
    for _ in range(MAX_ITER):
        _, mm, c = (x[..., g] for x in disc(tm))
        a_t, b_t = np.where(mm < 0, tm, a_t), np.where(mm < 0, b_t, tm)
        with np.errstate(all="ignore"):
            tn = tm - mm / c
        inside = (c > 0) & (tn > a_t) & (tn < b_t)
        tn = np.where(inside, tn, 0.5 * (a_t + b_t))
        done = np.all(np.abs(tn - tm) <= tol)
        tm = tn
        if done:
            break
    return tm


def closed_form_near(
    forms: ClosedForms, guess: np.ndarray, psi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(q, ok): the closed forms' pass at driver coordinates ``psi``, angles taken
    nearest to ``guess``; ``ok (...)`` where every group's margin √D stays above
    ``dyads.MARGIN``."""
    q, disc = forms.run(guess.copy(), psi, None)
    ok = np.all(disc >= MARGIN**2, axis=-1)
    ang = slice(2, None, 3)
    q[..., ang] += 2 * np.pi * np.round((guess[..., ang] - q[..., ang]) / (2 * np.pi))
    return q, ok
