"""The instant centres (速度瞬心) of a mechanism at one position, by Kennedy's theorem.

Of N bodies (the frame among them) there are N(N−1)/2 instant centres P_ij, the points
where bodies i and j have one velocity.  A pair gives its own directly (the joint contract's
``instant_centre``: a pin's centre, a slide's centre at infinity normal to it, a toothed
pair's pitch point).  Kennedy's theorem (三心定理: the three centres of three bodies lie on
one line) gives the others: P_ij lies on the line through P_ik and P_kj for every third
body k, so two such lines, through k and through l, meet at P_ij.  :func:`instant_centres`
repeats this until nothing new is found; what it cannot find (a centre of a body of a
class-III group, whose lines need the centres being sought) it says, per pair.

The check: from the centres alone and one angular velocity of the pipeline (the reference
body's, the driven link's), each body's angular velocity and the velocity of its centre of
mass, ω_i from P_0i, P_mi and a body m already known: the velocity of P_mi is the same on
both bodies, v_m(P_mi) = ω_i × (P_mi − P_0i).  They are compared with the pipeline's.

Geometry in the frame's global axes, m; a centre at infinity is stored as the unit
direction it lies along.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, replace

import numpy as np

from ..analysis.results import Result
from ..base.geometry import cross, perp
from ..structure.system import link_pair

__all__ = ["Centre", "BodyCheck", "InstantCentres", "instant_centres", "centres_at"]

# two lines whose directions' cross product is smaller than this are parallel; two points
# closer than this times the mechanism's size are one
PARALLEL = 1e-13
COINCIDENT = 1e-12

_Pole = tuple[np.ndarray, bool]  # (point, or unit direction at infinity; at infinity)


@dataclass(frozen=True)
class Centre:
    """The instant centre of ``bodies`` (i, j).

    ``xy``: the point (m), or the unit direction it lies along when ``at_infinity``, or
    None when it was not found.  ``how``: ``"joint"`` (given by the pair ``joint`` of type
    ``kind``), ``"kennedy"`` (the meeting point of the two ``lines``, each through two
    centres named by their bodies) or ``"not found"``, with the Assur ``groups`` its
    bodies belong to (a class-III group's, typically).
    """

    bodies: tuple[str, str]
    xy: tuple[float, float] | None
    at_infinity: bool = False
    how: str = "not found"
    joint: str = ""
    kind: str = ""
    lines: tuple[tuple[tuple[str, str], tuple[str, str]], ...] = ()
    groups: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        return {
            "bodies": list(self.bodies),
            "xy": None if self.xy is None else list(self.xy),
            "at_infinity": self.at_infinity,
            "how": self.how,
            "joint": self.joint,
            "kind": self.kind,
            "lines": [[list(a), list(b)] for a, b in self.lines],
            "groups": list(self.groups),
        }


@dataclass(frozen=True)
class BodyCheck:
    """One moving body's velocities from the centres against the pipeline's.

    ``omega`` (rad/s) and ``velocity`` (of its centre of mass, m/s) from the centres (None
    where they do not determine them), ``ratio`` = ω_i/ω_ref, ``via`` the known body whose
    common centre gave them; ``omega_result``, ``velocity_result`` the pipeline's;
    ``error`` the larger of |Δω|/max|ω| and |Δv|/max|v| over the bodies (None if not
    determined)."""

    body: str
    omega: float | None
    velocity: tuple[float, float] | None
    ratio: float | None
    via: str
    omega_result: float
    velocity_result: tuple[float, float]
    error: float | None

    def to_dict(self) -> dict:
        return {
            "body": self.body,
            "omega": self.omega,
            "velocity": None if self.velocity is None else list(self.velocity),
            "ratio": self.ratio,
            "via": self.via,
            "omega_result": self.omega_result,
            "velocity_result": list(self.velocity_result),
            "error": self.error,
        }


@dataclass(frozen=True)
class InstantCentres:
    """All N(N−1)/2 instant centres at ``row`` (time ``t``, driver ``coordinate``): the
    bodies, the frame first; the centre of each pair (i < j in that order); the check of
    each moving body against the pipeline, from the ``reference`` body's angular velocity
    (``omega_reference``); ``max_error`` the largest of the checks' errors."""

    row: int
    t: float
    coordinate: float
    bodies: tuple[str, ...]
    centres: tuple[Centre, ...]
    reference: str
    omega_reference: float
    checks: tuple[BodyCheck, ...]
    max_error: float

    @property
    def not_found(self) -> tuple[Centre, ...]:
        return tuple(c for c in self.centres if c.xy is None)

    def centre(self, a: str, b: str) -> Centre:
        """The centre of bodies ``a`` and ``b`` (either order); KeyError if there is none."""
        for c in self.centres:
            if set(c.bodies) == {a, b} and a != b:
                return c
        raise KeyError(f"no instant centre of {a!r} and {b!r}; the bodies: {self.bodies}")

    def to_dict(self) -> dict:
        """JSON-safe: what methods.json holds under ``instant_centres`` for this row."""
        return {
            "row": self.row,
            "t": self.t,
            "coordinate": self.coordinate,
            "bodies": list(self.bodies),
            "centres": [c.to_dict() for c in self.centres],
            "found": len(self.centres) - len(self.not_found),
            "total": len(self.centres),
            "reference": self.reference,
            "omega_reference": self.omega_reference,
            "checks": [c.to_dict() for c in self.checks],
            "max_error": self.max_error,
        }


# -- the centres the pairs give ------------------------------------------------------
def _given(result: Result, row: int) -> tuple[dict, dict]:
    """The centres the pairs give, (a, b) -> (pole, joint), and the lines they give,
    (a, b) -> ((point, unit direction), joint); a < b body indices (the frame 0, link k
    as k + 1)."""
    system = result.system
    n = len(system.links)
    q = np.asarray(result.q[row], dtype=float)
    known: dict = {}
    loci: dict = {}
    for k, joint in enumerate(system.joints):
        pole = joint.instant_centre(*link_pair(system, q, k))
        if pole is None:
            continue
        a, b = ((e + 1) % (n + 1) for e in system.ends[k])  # ground (index n) is body 0
        key, xy = (min(a, b), max(a, b)), np.asarray(pole.xy, dtype=float)
        if pole.along is not None:
            loci.setdefault(key, ((xy, np.asarray(pole.along, dtype=float)), joint))
        else:
            known.setdefault(key, ((xy, bool(pole.at_infinity)), joint))
    return known, loci


# -- Kennedy's theorem ---------------------------------------------------------------
def _line(p: _Pole, r: _Pole, size: float):
    """The line through two poles: (point, unit direction), "infinity" (the line at
    infinity) or None (undetermined: one point twice)."""
    (x, x_inf), (y, y_inf) = p, r
    if x_inf and y_inf:
        return None if abs(cross(x, y)) <= PARALLEL else "infinity"
    if x_inf or y_inf:
        return (y, x) if x_inf else (x, y)
    d = y - x
    length = float(np.hypot(*d))
    return None if length <= COINCIDENT * size else (x, d / length)


def _meet(l1, l2, size: float) -> tuple[_Pole, float] | None:
    """Where two lines meet, with the sine of their angle (1 with the line at infinity),
    or None (both at infinity, or one line twice)."""
    if isinstance(l1, str) and isinstance(l2, str):
        return None
    if isinstance(l1, str) or isinstance(l2, str):
        d = l2[1] if isinstance(l1, str) else l1[1]
        return (d, True), 1.0
    (p1, d1), (p2, d2) = l1, l2
    sine = float(cross(d1, d2))
    if abs(sine) <= PARALLEL:
        apart = abs(float(cross(d1, p2 - p1)))
        return ((d1, True), 0.0) if apart > COINCIDENT * size else None
    return (p1 + d1 * (float(cross(p2 - p1, d2)) / sine), False), abs(sine)


def _kennedy(known: dict, loci: dict, n_bodies: int, size: float) -> dict:
    """(a, b) -> (pole, (k, m)) found by Kennedy's theorem, round after round until a round
    finds nothing: the meeting point of the line through the centres with a third body k
    and that with m (−1: the line a pair gives, ``loci``); of a pair's candidates the one
    whose lines cross at the widest angle.  ``known`` (a, b) -> (pole, …) is not changed."""
    known = dict(known)

    def pole(a, b):
        return known.get((min(a, b), max(a, b)), (None,))[0]

    found: dict = {}
    while True:
        new = {}
        for a, b in itertools.combinations(range(n_bodies), 2):
            if (a, b) in known:
                continue
            lines = [(-1, loci[(a, b)][0])] if (a, b) in loci else []
            for k in range(n_bodies):
                if k in (a, b) or pole(a, k) is None or pole(k, b) is None:
                    continue
                if (line := _line(pole(a, k), pole(k, b), size)) is not None:
                    lines.append((k, line))
            best = None
            for (k, lk), (m, lm) in itertools.combinations(lines, 2):
                hit = _meet(lk, lm, size)
                if hit is not None and (best is None or hit[1] > best[1]):
                    best = (hit[0], hit[1], (k, m))
            if best is not None:
                new[(a, b)] = (best[0], best[2])
        if not new:
            return found
        for key, (p, via) in new.items():
            known[key] = (p, None)
            found[key] = (p, via)


# -- the velocities from the centres ---------------------------------------------------
def _field_at(field, p: np.ndarray) -> np.ndarray:
    """The velocity at p of a body moving with ``field`` = (ω, pole, at infinity, V)."""
    omega, c, inf, v = field
    return v if inf else omega * perp(p - c)


def _propagate(known: dict, n_bodies: int, ref: int, ref_field, size: float) -> dict:
    """Body -> (field, via): the reference's given, each other from the frame's centre and
    its centre with a body already known, until none is added."""
    fields = {ref: (ref_field, -1)}

    def pole(a, b):
        return known.get((min(a, b), max(a, b)), (None,))[0]

    added = True
    while added:
        added = False
        for i in range(1, n_bodies):
            if i in fields or pole(0, i) is None:
                continue
            for m, (fm, _) in list(fields.items()):
                if (f := _field_of(pole(0, i), pole(m, i), fm, size)) is not None:
                    fields[i], added = (f, m), True
                    break
    return fields


def _field_of(p0i: _Pole, pmi: _Pole | None, fm, size: float):
    """Body i's field from its centre with the frame and with a known body m, or None."""
    if pmi is None:
        return None
    (c, c_inf), (p, p_inf) = p0i, pmi
    if p_inf:  # i translates relative to m: ω_i = ω_m
        return None if c_inf else (fm[0], c, False, None)
    v = _field_at(fm, p)
    if c_inf:  # i translates: every point moves as P_mi
        return (0.0, None, True, v)
    r = p - c
    r2 = float(r @ r)
    if r2 <= (COINCIDENT * size) ** 2:
        return None
    return (float(cross(r, v)) / r2, c, False, None)


# -- the stage ---------------------------------------------------------------------------
def instant_centres(result: Result, row: int) -> InstantCentres:
    """All instant centres of ``result``'s mechanism at ``row`` and their check.

    The pairs give theirs (``Joint.instant_centre``), Kennedy's theorem the others where two
    of its lines meet; the velocities they give, from the reference body's angular velocity
    alone (the driven link's), are compared with the pipeline's."""
    system = result.system
    bodies = (system.model.ground.name, *system.links)
    size = float(np.max(system.l_ref))
    given, loci = _given(result, row)
    known = {key: (pole, None) for key, (pole, _) in given.items()}
    found = _kennedy(known, loci, len(bodies), size)
    known |= {key: (pole, None) for key, (pole, _) in found.items()}
    centres = tuple(
        _centre(bodies, (a, b), given.get((a, b)), found.get((a, b)), loci.get((a, b)))
        for a, b in itertools.combinations(range(len(bodies)), 2)
    )
    group_of = {name: p.group.label for p in system.plans for name in p.group.links}
    centres = tuple(
        replace(c, groups=tuple(dict.fromkeys(group_of[b] for b in c.bodies if b in group_of)))
        if c.xy is None
        else c
        for c in centres
    )
    ref = _reference(result, row, known)
    q, qd = np.asarray(result.q[row], float), np.asarray(result.qd[row], float)
    ref_field = _reference_field(known, ref, q, qd)
    fields = _propagate(known, len(bodies), ref, ref_field, size)
    checks = _checks(bodies, fields, q, qd, size, float(ref_field[0]))
    errors = [c.error for c in checks if c.error is not None]
    return InstantCentres(
        row=int(row),
        t=float(result.t[row]),
        coordinate=float(result.coordinate[row]),
        bodies=bodies,
        centres=centres,
        reference=bodies[ref],
        omega_reference=float(ref_field[0]),
        checks=checks,
        max_error=max(errors, default=0.0),
    )


def centres_at(result: Result, rows) -> tuple[InstantCentres, ...]:
    """:func:`instant_centres` at each of ``rows``."""
    return tuple(instant_centres(result, int(r)) for r in rows)


def _centre(bodies, key, given, found, locus) -> Centre:
    names = (bodies[key[0]], bodies[key[1]])
    if given is not None:
        (xy, inf), joint = given
        return Centre(names, _pair(xy), inf, "joint", joint.name, joint.kind)
    joint, kind = (locus[1].name, locus[1].kind) if locus is not None else ("", "")
    if found is not None:
        (xy, inf), (k, m) = found
        a, b = key
        lines = tuple(((bodies[a], bodies[c]), (bodies[c], bodies[b])) for c in (k, m) if c >= 0)
        if -1 not in (k, m):
            joint = kind = ""
        return Centre(names, _pair(xy), inf, "kennedy", joint, kind, lines)
    return Centre(names, None, joint=joint, kind=kind)


def _pair(xy: np.ndarray) -> tuple[float, float]:
    return float(xy[0]), float(xy[1])


def _reference(result: Result, row: int, known: dict) -> int:
    """The reference body: the driven link when its centre with the frame is known, else
    the one that turns fastest among those whose centre with the frame is known."""
    system = result.system
    n = len(system.links)
    with_pole = [i for i in range(1, n + 1) if (0, i) in known]
    if not with_pole:
        raise ValueError("no moving body has a known instant centre with the frame")
    for driver in system.motion_drivers:
        for name in driver.links:
            if name in system.links and system.link_index(name) + 1 in with_pole:
                return system.link_index(name) + 1
    omega = np.abs(np.asarray(result.qd[row], float)[2::3])
    return max(with_pole, key=lambda i: omega[i - 1])


def _reference_field(known: dict, ref: int, q: np.ndarray, qd: np.ndarray):
    """The reference body's field: its angular velocity (the pipeline's) about its centre
    with the frame; a translating one's velocity (the pipeline's) where that is at infinity."""
    (c, inf), _ = known[(0, ref)]
    k = 3 * (ref - 1)
    if inf:
        return (0.0, None, True, qd[k : k + 2].copy())
    return (float(qd[k + 2]), c, False, None)


def _checks(bodies, fields, q, qd, size: float, omega_ref: float) -> tuple[BodyCheck, ...]:
    """Each moving body's check; the velocity scale is the largest of the centres of
    mass' speeds and the largest |ω| times the mechanism's size (a body at rest, a centre
    of mass on its pivot)."""
    n = len(bodies) - 1
    omega_res = qd[2::3]
    v_res = qd.reshape(n, 3)[:, :2]
    w_scale = max(float(np.max(np.abs(omega_res))), 1e-300)
    v_scale = max(float(np.max(np.hypot(v_res[:, 0], v_res[:, 1]))), w_scale * size, 1e-300)
    out = []
    for i in range(1, n + 1):
        w_r, v_r = float(omega_res[i - 1]), _pair(v_res[i - 1])
        if i not in fields:
            out.append(BodyCheck(bodies[i], None, None, None, "", w_r, v_r, None))
            continue
        field, via = fields[i]
        omega = float(field[0])
        v = _field_at(field, q[3 * i - 3 : 3 * i - 1])
        error = max(abs(omega - w_r) / w_scale, float(np.hypot(*(v - v_r))) / v_scale)
        ratio = omega / omega_ref + 0.0 if omega_ref else None  # + 0.0: no −0
        name = bodies[via] if via >= 0 else ""
        out.append(BodyCheck(bodies[i], omega, _pair(v), ratio, name, w_r, v_r, error))
    return tuple(out)
