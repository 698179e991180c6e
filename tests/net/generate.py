"""Random planar linkages for the verification net (docs/verification.md).

``generate(seed)`` returns a mechanism as a YAML-like dict (fed through
``kinetostatics.loads(yaml.safe_dump(doc))``) that assembles over a full turn
of its crank with every Assur group's condition number below ``COND_MAX``.
It is deterministic in ``seed``.

Asking for features
-------------------
Besides the linkage, a mechanism gets *features* (``FEATURES``), each drawn with
its ``PROBABILITY`` from the seed (about four mechanisms in five get at least one):

=================  ==========================================================
``cam``            the crank is a disc cam driving a follower (below)
``elements``       1–3 springs, dampers, torsion springs, rotary dampers
``tables``         1–2 tables: load tables (force, torque, resistance,
                   resisting torque), a table spring, an effort table, a cam
                   law given as a table
``resisting``      a resisting torque (half of them relative to a revolute)
``effort``         an effort driver at another revolute (a known torque,
                   constant or tabulated over its own angle)
``drive``          ``drive:`` (reduction, motor and ratings), half with
                   ``flywheel:``
``counterweights`` 1–2 counter-masses on moving links
=================  ==========================================================

To ask for mechanisms that have some features for sure, name them::

    generate(seed, features=("cam",))              # a mechanism with a cam
    generate(seed, features=("elements", "tables"))

(the other features are still drawn as usual; the same ``seed`` and ``features``
give the same mechanism).  ``features(doc)`` tells which ones a document has.

How a mechanism is built (all in SI, then written in random units):

* a crank pivoted on the ground, driven at a constant speed of random sign;
  optionally a second crank coupled to it by a gear pair (equal teeth, or the
  second gear half the size so it turns twice per cycle — the pose is then
  periodic in the crank angle);
* with ``cam``, the crank is a disc cam about its pivot and its follower is the
  first group: translating (along a guide on the ground, offset either side) or
  oscillating (an arm on a ground pivot on either side, with the ``rise`` sense that
  moves it outwards there), with a knife edge, a roller or a flat face; the cam turns
  either way; its law is rise–dwell–return–dwell with random laws, or a table.  The
  follower is placed where the law's zero puts it (the crank's axes are the frame's at
  the start), so the cam starts in phase with its law;
* a chain of 1 to 3 Assur groups (the cam's follower counts as one), each attached
  to points of earlier links (new points are added to those links) or to new ground
  points: dyads RRR, RRP, RPR, PRP, and in about a quarter of the mechanisms a
  class-III triad (a ternary link held by three binary links, as in a Stephenson
  six-bar).

The start pose is drawn first (joint positions) and the links are drawn
from it: every moving link's local frame is the global frame at the start
pose, so its local points *are* the start positions, the sketch is exact and
the start assembles by construction.  The groups are shaped so that their
triangles are far from flat at the start (transmission angles of 40°–140°)
and the crank is short compared with the links it drives, which makes most
of them run through a full turn; candidates that do not (assembly error,
singular position, condition number above ``COND_MAX`` at 36 positions over
the turn) are rejected and the next attempt of the same seed is drawn.  The
features that do not change the motion (all but ``cam``) are added to an
accepted candidate, from its checked turn: a spring's or damper's ends stay
apart over the turn, a torsion spring sits at a revolute that does not turn
fully, a table spring's lengths (angles) span the element's range.

Loads: constant forces at link points, torques, resistances along a slider's
axis, with random ``active:`` windows (angle bands, ``moving:``, ``travel:``
bands).  Random masses, centres of mass, inertias and gravity
(magnitude 0 or 9.81 in a random direction); friction at some joints (friction
circles of 0.3–2 mm, Coulomb coefficients 0.02–0.12 at slides and 0.01–0.08 at
cams, mesh efficiency 0.97).
"""

from __future__ import annotations

import copy
import functools
import math
import warnings

import numpy as np
import yaml

COND_MAX = 1e6
DEFAULT_POSITIONS = 24
MAX_ATTEMPTS = 60

LENGTH_UNITS = {"m": 1.0, "mm": 1e-3}
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180}
SPEED_UNITS = {"rad/s": 1.0, "rpm": 2 * math.pi / 60}


class Rejected(Exception):
    """A candidate that does not meet the generator's acceptance rules."""


def _unit(a):
    return np.array([math.cos(a), math.sin(a)])


def _round(x):
    return float(f"{float(x):.12g}")


class _Builder:
    def __init__(self, rng):
        self.rng = rng
        self.links = {"ground": {"points": {}}}
        self.joints = {}
        self.sketch = {}
        self.moving_points = []  # (link, point, position) on moving links
        self.sliders = []  # (slider link, point, axis unit) for resistances
        self.n = 0
        self.kinds = []

    def name(self, prefix):
        self.n += 1
        return f"{prefix}{self.n}"

    def add_point(self, link, point, pos):
        self.links[link]["points"][point] = [float(pos[0]), float(pos[1])]
        if link != "ground":
            self.moving_points.append((link, point, np.asarray(pos, float)))

    def new_link(self, name, points):
        L = (
            max(
                (
                    np.linalg.norm(np.subtract(p, q))
                    for p in points.values()
                    for q in points.values()
                ),
                default=0.0,
            )
            or 0.05
        )
        rng = self.rng
        pts = np.array(list(points.values()))
        com = pts.mean(axis=0) + rng.normal(0, 0.1 * L, 2)
        mass = rng.uniform(0.2, 3.0)
        self.links[name] = {
            "points": {},
            "com": [float(com[0]), float(com[1])],
            "mass": mass,
            "inertia": mass * max(L, 0.05) ** 2 / 12 * rng.uniform(0.5, 1.5),
        }
        for p, pos in points.items():
            self.add_point(name, p, pos)

    def revolute(self, links, pos):
        j = self.name("J")
        self.joints[j] = {"type": "revolute", "links": list(links)}
        if links[0] != "ground":
            self.sketch[j] = [float(pos[0]), float(pos[1])]
        return j

    def attach_point(self, exclude=(), moving=True):
        """A point on an earlier moving link: an existing one or a new one nearby."""
        fixed = [np.asarray(v) for v in self.links["ground"]["points"].values()]
        choices = [
            m
            for m in self.moving_points
            if m[0] not in exclude  # not on a pivot:
            and all(np.linalg.norm(m[2] - f) > 1e-6 for f in fixed)
        ]  # it would not move
        link, point, pos = choices[self.rng.integers(len(choices))]
        if self.rng.random() < 0.4:  # a new point on that link, near the old one
            new = pos + self.rng.normal(0, 0.05, 2)
            point = self.name("p")
            self.add_point(link, point, new)
            pos = new
        return link, point, np.asarray(pos)

    def ground_point(self, pos):
        point = self.name("G")
        self.add_point("ground", point, pos)
        return "ground", point, np.asarray(pos)


def _triangle_ok(P1, C, P2, lo=40, hi=140):
    a, b = P1 - C, P2 - C
    ang = math.degrees(math.acos(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1)))
    return lo <= ang <= hi


def _rrr(B, rng):
    L1, p1, P1 = B.attach_point()
    for _ in range(50):
        if rng.random() < 0.6:
            P2 = P1 + rng.uniform(0.3, 0.7) * _unit(rng.uniform(0, 2 * math.pi))
            second = None
        else:
            second = (
                B.attach_point(exclude=(L1,)) if len({m[0] for m in B.moving_points}) > 1 else None
            )
            if second is None:
                continue
            P2 = second[2]
        d = np.linalg.norm(P2 - P1)
        if d < 0.15:
            continue
        phi = math.atan2(*(P2 - P1)[::-1]) + rng.choice([-1, 1]) * rng.uniform(0.4, 1.2)
        C = P1 + rng.uniform(0.5, 1.1) * d * _unit(phi)
        if _triangle_ok(P1, C, P2):
            break
    else:
        raise Rejected("no RRR triangle")
    L2, p2, P2 = second if second is not None else B.ground_point(P2)
    b1, b2 = B.name("b"), B.name("b")
    jC = B.name("J")
    B.new_link(b1, {p1: P1, jC: C})
    B.new_link(b2, {p2: P2, jC: C})
    B.joints[jC] = {"type": "revolute", "links": [b1, b2]}
    B.sketch[jC] = [float(C[0]), float(C[1])]
    _pin(B, L1, p1, b1, P1)
    _pin(B, L2, p2, b2, P2)
    B.kinds.append("RRR")


def _pin(B, link, point, other, pos):
    """A revolute between ``link`` (its point ``point``) and ``other``'s point of that name."""
    j = B.name("J")
    B.joints[j] = {"type": "revolute", "links": [link, other], "points": [point, point]}
    if link != "ground":
        B.sketch[f"{other}.{point}"] = [float(pos[0]), float(pos[1])]
    return j


def _axis_link(B, rng, moving_ok=True, exclude=()):
    """The link carrying a guide: the ground mostly, sometimes an earlier moving
    link (not one in ``exclude``: a dyad with both ends on one link is rigid)."""
    choices = [m for m in B.moving_points if m[0] not in exclude]
    if moving_ok and choices and rng.random() < 0.3:
        link, _, _ = choices[rng.integers(len(choices))]
        return link
    return "ground"


def _prismatic(B, guide, slider, P, u, point):
    j = B.name("S")
    A = P - rng_offset(B) * u
    a = B.name("a")
    B.links[guide]["points"][a] = [float(A[0]), float(A[1])]
    B.joints[j] = {
        "type": "prismatic",
        "links": [guide, slider],
        "axis": {"point": a, "direction": [float(u[0]), float(u[1])]},
        "point": point,
    }
    B.sketch[j] = [float(P[0]), float(P[1])]
    return j


def rng_offset(B):
    return B.rng.uniform(-0.2, 0.2)


def _rrp(B, rng):
    L1, p1, P1 = B.attach_point()
    guide = _axis_link(B, rng, exclude=(L1,))
    rod_dir = rng.uniform(0, 2 * math.pi)
    C = P1 + rng.uniform(0.3, 0.7) * _unit(rod_dir)
    u = _unit(
        rod_dir + rng.choice([-1, 1]) * rng.uniform(0, math.radians(45)) + rng.choice([0, math.pi])
    )
    rod, sl = B.name("b"), B.name("b")
    jC = B.name("C")
    B.new_link(rod, {p1: P1, jC: C})
    B.new_link(sl, {jC: C})
    B.joints[jC] = {"type": "revolute", "links": [rod, sl]}
    B.sketch[jC] = [float(C[0]), float(C[1])]
    _pin(B, L1, p1, rod, P1)
    _prismatic(B, guide, sl, C, u, jC)
    B.sliders.append((sl, jC, u))
    B.kinds.append("RRP")


def _rpr(B, rng):
    L1, p1, P1 = B.attach_point()
    d = rng.uniform(0.25, 0.6)
    P2 = P1 + d * _unit(rng.uniform(0, 2 * math.pi))
    L2, p2, P2 = B.ground_point(P2)
    delta = rng.uniform(-1, 1) * math.radians(15)
    v = (P1 - P2) / d
    u = np.array(
        [
            v[0] * math.cos(delta) - v[1] * math.sin(delta),
            v[0] * math.sin(delta) + v[1] * math.cos(delta),
        ]
    )
    block, slot = B.name("b"), B.name("b")
    B.new_link(block, {p1: P1})
    tip = B.name("tip")
    B.new_link(slot, {p2: P2, tip: P2 + 1.5 * d * u})
    B.sketch[f"{slot}.{tip}"] = [float(x) for x in P2 + 1.5 * d * u]  # decides the slot's branch
    _pin(B, L1, p1, block, P1)
    _pin(B, L2, p2, slot, P2)
    _prismatic(B, slot, block, P1, u, p1)
    B.kinds.append("RPR")


def _prp(B, rng):
    L1, _, P1 = B.attach_point()
    guide2 = _axis_link(B, rng, moving_ok=False)
    C = P1 + rng.uniform(0.1, 0.4) * _unit(rng.uniform(0, 2 * math.pi))
    a1 = rng.uniform(0, 2 * math.pi)
    a2 = a1 + rng.choice([-1, 1]) * rng.uniform(math.radians(50), math.radians(130))
    s1, s2 = B.name("b"), B.name("b")
    jC = B.name("C")
    B.new_link(s1, {jC: C})
    B.new_link(s2, {jC: C})
    B.joints[jC] = {"type": "revolute", "links": [s1, s2]}
    B.sketch[jC] = [float(C[0]), float(C[1])]
    _prismatic(B, L1, s1, C, _unit(a1), jC)
    _prismatic(B, guide2, s2, C, _unit(a2), jC)
    B.sliders.append((s2, jC, _unit(a2)))
    B.kinds.append("PRP")


def _triad(B, rng):
    D1 = B.moving_points[0][2] + rng.uniform(0.3, 0.5) * _unit(rng.uniform(0, 2 * math.pi))
    side = rng.uniform(0.1, 0.25)
    phi = rng.uniform(0, 2 * math.pi)
    D = [D1, D1 + side * _unit(phi), D1 + side * _unit(phi + rng.uniform(1.0, 2.1))]
    attach = [B.attach_point()]
    for k in (1, 2):
        ang = rng.uniform(0, 2 * math.pi)
        attach.append(B.ground_point(D[k] + rng.uniform(0.25, 0.5) * _unit(ang)))
    beam = B.name("t")
    names = [B.name("D") for _ in range(3)]
    B.new_link(beam, dict(zip(names, D)))
    for (L, p, P), dn, Dk in zip(attach, names, D):
        c = B.name("b")
        B.new_link(c, {p: P, dn: Dk})
        B.joints[dn] = {"type": "revolute", "links": [c, beam]}
        B.sketch[dn] = [float(Dk[0]), float(Dk[1])]
        _pin(B, L, p, c, P)
    B.kinds.append("triad")


def candidate(seed: int, attempt: int = 0, features=()) -> dict:
    """One unchecked candidate (SI units) without the features added after the kinematic
    check (elements, tables, ...); ``generate`` filters them and adds those."""
    return _candidate(seed, attempt, _plan(seed, attempt, features))


def _candidate(seed: int, attempt: int, plan: dict) -> dict:
    rng = np.random.default_rng([seed, attempt])
    B = _Builder(rng)
    pivot = rng.uniform(-0.2, 0.2, 2)
    r = rng.uniform(0.03, 0.09)
    psi0 = rng.uniform(0, 2 * math.pi)
    A = pivot + r * _unit(psi0)
    B.add_point("ground", "O", pivot)
    B.new_link("crank", {"O": pivot, "A": A})
    B.joints["O"] = {"type": "revolute", "links": ["ground", "crank"]}
    B.sketch["crank.A"] = [float(A[0]), float(A[1])]
    B.kinds.append("crank")
    omega = rng.choice([-1, 1]) * rng.uniform(3, 30)
    # a second crank through a gear pair (not on a cam: relations.transformed turns a cam's
    # axes with the frame, which a gear's phase to the other crank does not follow)
    if rng.random() < 0.2 and not plan["cam"]:
        z1 = int(rng.choice([20, 30, 40]))
        z2 = int(rng.choice([z1, z1 // 2]))
        m = rng.uniform(0.002, 0.004)
        d = m * (z1 + z2) / 2
        beta = rng.uniform(0, 2 * math.pi)
        O2 = pivot + d * _unit(beta)
        B2 = O2 + rng.uniform(0.03, 0.08) * _unit(rng.uniform(0, 2 * math.pi))
        B.add_point("ground", "O2", O2)
        B.new_link("crank2", {"O2": O2, "B": B2})
        B.joints["O2"] = {"type": "revolute", "links": ["ground", "crank2"]}
        B.sketch["crank2.B"] = [float(B2[0]), float(B2[1])]
        r1, r2 = m * z1 / 2, m * z2 / 2
        phase = -beta * (1 + r1 / r2)  # θ_j − β = φ when θ_i − β = 0, both θ = 0 now
        phase = math.remainder(phase, 2 * math.pi * math.gcd(z1, z2) / z2)
        B.joints["mesh"] = {
            "type": "gear",
            "links": ["crank", "crank2"],
            "centres": ["O", "O2"],
            "teeth": [z1, z2],
            "module": m,
            "mesh": "external",
            "flank": str(rng.choice(["cw", "ccw"])),
            "phase": phase,
        }
        B.kinds.append(f"gear{z1}:{z2}")
    builders = [_rrr, _rrp, _rpr, _prp]
    weights = np.array([0.4, 0.25, 0.2, 0.15])
    n_groups = int(rng.integers(1, 4))
    triad_at = int(rng.integers(n_groups)) if rng.random() < 0.25 else -1
    if plan["cam"]:  # the crank is a disc cam: its follower is the first group
        _cam(B, plan["rng"], pivot, plan["tables"])
        n_groups -= 1
        triad_at -= 1
    for k in range(n_groups):
        if k == triad_at:
            _triad(B, rng)
        else:
            builders[rng.choice(4, p=weights)](B, rng)
    doc = {
        "name": f"generated {seed}/{attempt}",
        "units": {"length": "m", "angle": "rad", "speed": "rad/s"},
    }
    g = 0.0 if rng.random() < 0.15 else 9.81
    ga = rng.uniform(0, 2 * math.pi) if rng.random() < 0.5 else -math.pi / 2
    doc["gravity"] = [g * math.cos(ga), g * math.sin(ga)]
    doc["links"] = B.links
    doc["joints"] = B.joints
    if rng.random() < 0.5:  # friction at some joints
        for j in B.joints.values():
            if rng.random() < 0.7:
                if j["type"] == "revolute":
                    j["friction"] = {"radius": rng.uniform(0.0003, 0.002)}
                elif j["type"] == "prismatic":
                    j["friction"] = {"coefficient": rng.uniform(0.02, 0.12)}
                elif j["type"] == "gear":
                    j["friction"] = {"efficiency": 0.97}
                elif j["type"] == "cam":
                    j["friction"] = {"coefficient": rng.uniform(0.01, 0.08)}
    doc["drivers"] = {
        "motor": {"joint": "O", "motion": {"speed": float(omega)}, "points": ["x", "A"]}
    }
    doc["loads"] = _loads(B, rng, r)
    doc["sketch"] = B.sketch
    doc["analysis"] = {"start": psi0, "sweep": 2 * math.pi, "positions": DEFAULT_POSITIONS}
    return _clean(doc)


# ------------------------------------------------------------------ features

FEATURES = ("cam", "elements", "tables", "resisting", "effort", "drive", "counterweights")
PROBABILITY = {
    "cam": 0.25,
    "elements": 0.3,
    "tables": 0.25,
    "resisting": 0.2,
    "effort": 0.12,
    "drive": 0.25,
    "counterweights": 0.2,
}


def _plan(seed: int, attempt: int, features=()) -> dict:
    """Which features candidate ``attempt`` of ``seed`` gets: each drawn with its
    ``PROBABILITY`` from a stream of its own (the linkage's draws are those of a mechanism
    without features), those named in ``features`` always."""
    want = set(features)
    unknown = want - set(FEATURES)
    if unknown:
        raise ValueError(f"unknown features {sorted(unknown)}; known: {', '.join(FEATURES)}")
    rng = np.random.default_rng([seed, attempt, 97])
    plan = {f: bool(rng.random() < PROBABILITY[f]) or f in want for f in FEATURES}
    plan["rng"] = rng
    return plan


def _perp(u):
    return np.array([-u[1], u[0]])


def _cam_law(rng, lift, table):
    """A law of one turn (rad) that starts at lift 0: rise, dwell, return, dwell with random
    laws and spans, or a periodic table of 8–12 lifts with 0 at cam angle 0."""
    if table:
        n = int(rng.integers(8, 13))
        angles = 2 * math.pi * np.arange(n) / n
        lifts = lift * 0.5 * (1 - np.cos(angles)) * rng.uniform(0.85, 1.0, n)
        lifts[0] = 0.0
        return {"angle": angles, "lift": lifts}
    rise, ret = rng.uniform(math.radians(90), math.radians(150), 2)
    rest = 2 * math.pi - rise - ret
    d0, d1 = rest * rng.uniform(0.05, 0.3), rest * rng.uniform(0.2, 0.5)
    laws = ["harmonic", "cycloidal", "polynomial", "polynomial7"]
    # a dwell first and last: the start (cam angle 0, where a row always is) is then no
    # break of the law; a rise starting there would put the first row on a jump of s″ or
    # s‴, whose side is decided by the round-off of the solved cam angle
    return [
        {"dwell": d0},
        {"rise": lift, "over": rise, "law": str(rng.choice(laws))},
        {"dwell": d1},
        {"return": lift, "over": ret, "law": str(rng.choice(laws))},
        {"dwell": 2 * math.pi - rise - ret - d0 - d1},
    ]


def _cam(B, rng, O, table=False):  # noqa: E741 - the pivot O
    """The crank as a disc cam about its pivot O, and its follower on the ground.

    The follower is translating (along a guide on the ground) or oscillating (an arm on a
    ground pivot), with a knife edge, a roller or a flat face; the cam turns either way
    (``rotation``) and the follower sits on either side (a random direction of rise, offset
    of either sign, a pivot on either side with the ``rise`` sense that moves the follower
    outwards there).  The geometry is that of docs/yaml.md (``type: cam``) at lift 0: the
    crank's axes are the frame's at the start (every moving link's are), so the cam angle is
    0 there and the follower is placed where the law's zero puts it — in phase."""
    rb = rng.uniform(0.04, 0.08)
    kind = str(rng.choice(["roller", "knife", "flat"], p=[0.5, 0.2, 0.3]))
    oscillating = rng.random() < 0.5
    sigma = int(rng.choice([1, -1]))
    rr = rng.uniform(0.2, 0.4) * rb if kind == "roller" else 0.0
    rp = rb + rr
    f = B.name("f")
    C = B.name("c")
    joint = {
        "type": "cam",
        "links": ["crank", f],
        "centre": "O",
        "point": C,
        "follower": kind,
        "base_radius": rb,
        "rotation": "ccw" if sigma > 0 else "cw",
    }
    if kind == "roller":
        joint["radius"] = rr
    if not oscillating:
        u = _unit(rng.uniform(0, 2 * math.pi))
        if kind == "flat":
            F = rb * u + rng.uniform(-0.3, 0.3) * rb * _perp(u)  # a point of the face
            joint["face_normal"] = [float(x) for x in -u]
            joint["translating"] = {"direction": [float(x) for x in u]}
            lift = rng.uniform(0.1, 0.3) * rb
        else:
            e = rng.uniform(-0.4, 0.4) * rp
            w = -sigma * _perp(u)  # the side where the cam's surface moves along u
            F = e * w + math.sqrt(rp * rp - e * e) * u
            joint["translating"] = {"direction": [float(x) for x in u], "offset": e}
            lift = rng.uniform(0.15, 0.45) * rb
        P = O + F
        tip = B.name("p")
        B.new_link(f, {C: P, tip: P + rng.uniform(0.05, 0.15) * u})
        # both points sketched: the follower's axes from them (one point alone would give
        # its axes as +x, a guess that a frame turned by the rigid relation contradicts)
        B.sketch[f"{f}.{tip}"] = B.links[f]["points"][tip]
        _prismatic(B, "ground", f, P, u, C)
        B.sliders.append((f, C, u))
        B.kinds.append(f"cam-{kind}-translating")
    else:
        if kind == "flat":
            N = _unit(rng.uniform(0, 2 * math.pi))  # the face's normal, from cam to follower
            off = rng.uniform(0.0, 0.3) * rb
            t = rng.choice([-1, 1]) * rng.uniform(1.5, 3.0) * rb
            A = (rb + off) * N + t * _perp(N)  # the face at off from the pivot: N·A − off = rb
            kappa = 1 if t > 0 else -1  # the rise moves the face away: κ (N × A) > 0
            F = A - off * N  # the pivot's foot on the face
            joint["face_normal"] = [float(x) for x in -N]
            joint["oscillating"] = {"pivot": A, "rise": "ccw" if kappa > 0 else "cw", "offset": off}
            lift = rng.uniform(math.radians(5), math.radians(12))
            ends = {C: O + F, B.name("p"): O + F - np.sign(t) * rng.uniform(0.05, 0.1) * _perp(N)}
        else:
            gamma = rng.uniform(0, 2 * math.pi)
            F = rp * _unit(gamma)
            L = rng.uniform(0.12, 0.3)
            d = _unit(gamma + rng.choice([-1, 1]) * (math.pi / 2 + rng.uniform(-0.4, 0.4)))
            A = F - L * d
            kappa = 1 if d[0] * A[1] - d[1] * A[0] > 0 else -1  # the rise moves F outwards
            joint["oscillating"] = {"pivot": A, "arm": L, "rise": "ccw" if kappa > 0 else "cw"}
            lift = min(rng.uniform(0.15, 0.4) * rb / L, math.radians(20))
            ends = {C: O + F}
        G = B.name("G")
        B.add_point("ground", G, O + A)
        B.new_link(f, {G: O + A, **ends})
        B.joints[G] = {"type": "revolute", "links": ["ground", f]}
        B.kinds.append(f"cam-{kind}-oscillating")
    joint["motion"] = _cam_law(rng, lift, table and rng.random() < 0.5)
    B.joints[B.name("cam")] = joint
    B.sketch[f"{f}.{C}"] = [float(x) for x in O + F]


def _track(res, link, point):
    """A link point's positions over the checked turn (a ground point: its fixed place)."""
    return np.stack([np.asarray(res[f"{link}.{point}.x"]), np.asarray(res[f"{link}.{point}.y"])], 1)


def _relative_turn(res, doc, joint):
    """The relative rotation θ_j − θ_i of a revolute's links over the checked turn (rad,
    unwrapped from the start, where it is 0: every link's axes are the frame's there)."""
    ground = doc.get("ground", "ground")
    li, lj = doc["joints"][joint]["links"][:2]
    th = [
        np.zeros(len(res)) if k == ground else np.radians(np.asarray(res[f"{k}.theta"]))
        for k in (li, lj)
    ]
    return np.unwrap(th[1] - th[0])


def _element_ends(points, res, rng, extra, far=0.02):
    """Two ends for a spring or damper: a moving point and a new ground point near it (put
    in ``extra``), or two points of different links; their distance stays above ``far``
    over the turn (a zero length has no direction)."""
    for _ in range(20):
        l1, p1 = points[rng.integers(len(points))]
        a = _track(res, l1, p1)
        if rng.random() < 0.5:
            G = a[0] + rng.uniform(0.1, 0.3) * _unit(rng.uniform(0, 2 * math.pi))
            name = f"E{len(extra)}"
            b, ends = np.broadcast_to(G, a.shape), [f"ground.{name}", f"{l1}.{p1}"]
        else:
            l2, p2 = points[rng.integers(len(points))]
            if l2 == l1:
                continue
            name, b, ends = None, _track(res, l2, p2), [f"{l1}.{p1}", f"{l2}.{p2}"]
        length = np.hypot(*(a - b).T)
        if length.min() > far:
            if name:
                extra[name] = G
            return ends, length
    raise Rejected("no element ends that stay apart")


def _decorate(doc: dict, res, plan: dict) -> dict:
    """``doc`` (accepted kinematically, ``res`` its checked turn) with the features of
    ``plan`` that do not change its motion: elements, tables, a resisting torque, an effort
    driver, a drive and a flywheel, counterweights."""
    rng = plan["rng"]
    d = copy.deepcopy(doc)
    loads = d.setdefault("loads", {})
    tables = plan["tables"]
    table_kinds = []
    if tables:  # which tables: one or two of those the mechanism can take
        kinds = ["force", "torque", "resisting_torque"]
        kinds += ["resistance"] if any(ld["type"] == "resistance" for ld in loads.values()) else []
        kinds += ["spring"] if plan["elements"] else []
        kinds += ["effort"] if plan["effort"] else []
        table_kinds = list(
            rng.choice(kinds, size=min(len(kinds), int(rng.integers(1, 3))), replace=False)
        )
    if plan["elements"] or "spring" in table_kinds:
        _add_elements(d, rng, plan, table_kinds, res)
    _add_tables(d, rng, table_kinds)
    if plan["resisting"]:
        _add_resisting(d, rng)
    if plan["effort"]:
        _add_effort(d, rng, table_kinds)
    if plan["drive"]:
        _add_drive(d, rng)
    if plan["counterweights"]:
        _add_counterweights(d, rng)
    return _clean(d)


def _add_elements(d, rng, plan, table_kinds, res):
    """1–3 springs, dampers, torsion springs, rotary dampers; a table spring for a table."""
    ground = d.get("ground", "ground")
    moving = [n for n in d["links"] if n != ground]
    revolutes = [n for n, j in d["joints"].items() if j["type"] == "revolute"]
    points = [(n, p) for n in moving for p in d["links"][n]["points"]]
    elements = d.setdefault("elements", {})
    extra = {}
    n = int(rng.integers(1, 4)) if plan["elements"] else 0
    kinds = [str(k) for k in rng.choice(["spring", "damper", "torsion", "rotary"], size=n)]
    if "spring" in table_kinds:
        kinds.append(str(rng.choice(["spring_table", "torsion_table"])))
    for k, kind in enumerate(kinds):
        name = f"e{k}"
        if kind in ("spring", "damper", "spring_table"):
            ends, length = _element_ends(points, res, rng, extra)
            el = {"type": "damper" if kind == "damper" else "spring", "between": ends}
            if kind == "spring":
                el.update(
                    stiffness=rng.uniform(50, 2000),
                    free_length=length[0] * rng.uniform(0.7, 1.3),
                    preload=rng.uniform(0, 50),
                )
            elif kind == "damper":
                el["damping"] = rng.uniform(1, 50)
            else:
                lo, hi = length.min(), length.max()
                at = np.sort(
                    rng.uniform(lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo), int(rng.integers(3, 6)))
                )
                el["table"] = {"length": at, "force": np.sort(rng.uniform(-50, 300, len(at)))}
        else:
            joint = revolutes[rng.integers(len(revolutes))]
            rel = _relative_turn(res, d, joint)
            if kind != "rotary" and np.ptp(rel) > math.radians(300):
                kind = "rotary"  # a joint that turns fully: a spring would wind up
            el = {
                "type": "rotary_damper" if kind == "rotary" else "torsion_spring",
                "joint": joint,
            }
            if kind == "torsion":
                el.update(
                    stiffness=rng.uniform(0.5, 20),
                    free_angle=rng.uniform(-0.5, 0.5),
                    preload=rng.uniform(-2, 2),
                )
            elif kind == "rotary":
                el["damping"] = rng.uniform(0.01, 0.5)
            else:
                lo, hi = rel.min(), rel.max()
                at = np.sort(rng.uniform(lo - 0.2, hi + 0.2, int(rng.integers(3, 6))))
                el["table"] = {"angle": at, "torque": np.sort(rng.uniform(-5, 10, len(at)))}
        elements[name] = el
    for name, pos in extra.items():
        d["links"][ground]["points"][name] = [float(pos[0]), float(pos[1])]


def _add_tables(d, rng, table_kinds):
    """Load tables over the driver coordinate (force, torque, resisting torque, resistance)."""
    ground = d.get("ground", "ground")
    moving = [n for n in d["links"] if n != ground]
    loads = d.setdefault("loads", {})
    for kind in table_kinds:
        at = np.sort(rng.uniform(0, 2 * math.pi, int(rng.integers(3, 7))))
        if kind in ("spring",):
            continue
        if kind == "effort":
            continue  # below, with the effort driver
        link = moving[rng.integers(len(moving))]
        if kind == "force":
            pts = sorted(d["links"][link]["points"])
            load = {"type": "force", "link": link, "point": pts[rng.integers(len(pts))]}
            values = [rng.uniform(10, 200) * _unit(rng.uniform(0, 2 * math.pi)) for _ in at]
        elif kind == "torque":
            load = {"type": "torque", "link": link}
            values = [rng.choice([-1, 1]) * rng.uniform(1, 20) for _ in at]
        elif kind == "resisting_torque":
            load = {"type": "resisting_torque", "link": link}
            values = list(rng.uniform(0, 20, len(at)))
        else:
            res_load = [ld for ld in loads.values() if ld["type"] == "resistance"][0]
            load = {k: res_load[k] for k in ("type", "link", "point", "axis")}
            values = list(rng.uniform(0, 300, len(at)))
        load["table"] = {"at": at, "value": values}
        loads[f"T{len(loads)}"] = load


def _add_resisting(d, rng):
    """A resisting torque, against the link's rotation or relative to a revolute holding it."""
    ground = d.get("ground", "ground")
    moving = [n for n in d["links"] if n != ground]
    revolutes = [n for n, j in d["joints"].items() if j["type"] == "revolute"]
    loads = d.setdefault("loads", {})
    link = moving[rng.integers(len(moving))]
    rt = {"type": "resisting_torque", "link": link, "value": rng.uniform(1, 20)}
    holders = [n for n in revolutes if link in d["joints"][n]["links"]]
    if holders and rng.random() < 0.5:
        rt["joint"] = holders[rng.integers(len(holders))]
    if rng.random() < 0.3:
        rt["active"] = [{"angle": _band(rng)}]
    loads[f"R{len(loads)}"] = rt


def _add_effort(d, rng, table_kinds):
    """An effort driver at another revolute: a torque, constant or tabulated over its own angle."""
    ground = d.get("ground", "ground")
    revolutes = [n for n, j in d["joints"].items() if j["type"] == "revolute"]
    own = d["drivers"]["motor"]["joint"]
    cands = [n for n in revolutes if n != own and d["joints"][n]["links"][1] != ground]
    if cands:
        joint = cands[rng.integers(len(cands))]
        spec = d["joints"][joint]
        pts = []
        for k, link in enumerate(spec["links"][:2]):
            if link == ground:
                pts.append("x")
                continue
            centre = spec.get("points", [joint, joint])[k]
            c = np.asarray(d["links"][link]["points"][centre])
            far = [
                p
                for p, v in d["links"][link]["points"].items()
                if np.hypot(*(np.asarray(v) - c)) > 1e-3
            ]
            if not far:
                break
            pts.append(far[rng.integers(len(far))])
        if len(pts) == 2:
            if "effort" in table_kinds:
                at = np.sort(rng.uniform(0, 2 * math.pi, int(rng.integers(3, 7))))
                effort = {"table": {"at": at, "value": rng.uniform(-5, 5, len(at))}}
            else:
                effort = float(rng.uniform(-5, 5))
            d["drivers"]["helper"] = {"joint": joint, "effort": effort, "points": pts}


def _add_drive(d, rng):
    """A drive (reduction and motor with ratings) and, half the time, a flywheel."""
    i = rng.uniform(5, 40)
    rated = rng.uniform(0.2, 5.0)
    d["drive"] = {
        "reduction": {
            "ratio": i,
            "efficiency": rng.uniform(0.8, 1.0),
            "inertia": rng.uniform(0, 1e-4),
        },
        "motor": {
            "inertia": rng.uniform(0, 1e-3),
            "rated_torque": rated,
            "peak_torque": rated * rng.uniform(1, 4),
            "rated_speed": abs(float(d["drivers"]["motor"]["motion"]["speed"]))
            * i
            * rng.uniform(0.8, 1.5),
        },
    }
    if rng.random() < 0.5:
        d["flywheel"] = {"delta": rng.uniform(0.02, 0.1)}


def _add_counterweights(d, rng):
    """One or two counter-masses on moving links."""
    ground = d.get("ground", "ground")
    moving = [n for n in d["links"] if n != ground]
    for k in range(int(rng.integers(1, 3))):
        link = d["links"][moving[rng.integers(len(moving))]]
        pts = np.array(list(link["points"].values()))
        at = pts.mean(axis=0) + rng.normal(0, 0.05, 2)
        cw = {"at": [float(at[0]), float(at[1])], "mass": rng.uniform(0.1, 1.5)}
        if rng.random() < 0.5:
            cw["inertia"] = rng.uniform(0, 1e-3)
        link.setdefault("counterweights", {})[f"cw{k}"] = cw


def features(doc: dict) -> set[str]:
    """The features (``FEATURES``) a generated document has."""
    out = set()
    joints = doc["joints"].values()
    loads = doc.get("loads", {}).values()
    if any(j["type"] == "cam" for j in joints):
        out.add("cam")
    if doc.get("elements"):
        out.add("elements")
    if (
        any("table" in ld for ld in loads)
        or any("table" in e for e in doc.get("elements", {}).values())
        or any(j["type"] == "cam" and isinstance(j["motion"], dict) for j in joints)
        or any(isinstance(v.get("effort"), dict) for v in doc["drivers"].values())
    ):
        out.add("tables")
    if any(ld["type"] == "resisting_torque" for ld in loads):
        out.add("resisting")
    if any("effort" in v for v in doc["drivers"].values()):
        out.add("effort")
    if "drive" in doc:
        out.add("drive")
    if any("counterweights" in link for link in doc["links"].values()):
        out.add("counterweights")
    return out


def _band(rng):
    a = rng.uniform(0, 2 * math.pi)
    return [a, a + rng.uniform(0.5, 3.5)]


def _loads(B, rng, r):
    loads = {}
    moving = [m for m in B.moving_points]
    for k in range(int(rng.integers(1, 4))):
        kind = rng.choice(["force", "torque", "resistance"] if B.sliders else ["force", "torque"])
        name = f"L{k}"
        if kind == "force":
            link, point, _ = moving[rng.integers(len(moving))]
            F = rng.uniform(10, 200) * _unit(rng.uniform(0, 2 * math.pi))
            load = {
                "type": "force",
                "link": link,
                "point": point,
                "value": [float(F[0]), float(F[1])],
            }
        elif kind == "torque":
            link, _, _ = moving[rng.integers(len(moving))]
            load = {
                "type": "torque",
                "link": link,
                "value": float(rng.choice([-1, 1]) * rng.uniform(1, 20)),
            }
        else:
            sl, point, u = B.sliders[rng.integers(len(B.sliders))]
            load = {
                "type": "resistance",
                "link": sl,
                "point": point,
                "value": float(rng.uniform(50, 300)),
                "axis": [float(u[0]), float(u[1])],
            }
        active = []
        for _ in range(int(rng.integers(0, 3))):
            which = rng.choice(["angle", "moving", "travel"])
            link, point, _ = moving[rng.integers(len(moving))]
            a = _unit(rng.uniform(0, 2 * math.pi))
            if which == "angle":
                active.append({"angle": _band(rng)})
            elif which == "moving":
                active.append({"moving": [float(a[0]), float(a[1])], "point": f"{link}.{point}"})
            else:
                lo = rng.uniform(0, 0.8) * r
                active.append(
                    {
                        "travel": [lo, lo + rng.uniform(0.3, 1.2) * r],
                        "along": [float(a[0]), float(a[1])],
                        "point": f"{link}.{point}",
                    }
                )
        if active:
            load["active"] = active
        loads[name] = load
    return loads


def _clean(x):
    if isinstance(x, np.ndarray):
        return _clean(x.tolist())
    if isinstance(x, dict):
        return {k: _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if isinstance(x, (np.floating, float)):
        return _round(x)
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.str_):
        return str(x)
    return x


# --------------------------------------------------------------------- units


def in_units(doc: dict, length: str = "m", angle: str = "rad", speed: str = "rad/s") -> dict:
    """The same SI mechanism written with other length, angle and speed units."""
    fl, fa, fs = 1 / LENGTH_UNITS[length], 1 / ANGLE_UNITS[angle], 1 / SPEED_UNITS[speed]
    d = copy.deepcopy(doc)
    assert d.get("units", {"length": "m", "angle": "rad", "speed": "rad/s"}) == {
        "length": "m",
        "angle": "rad",
        "speed": "rad/s",
    }, "in_units needs an SI document"
    d["units"] = {"length": length, "angle": angle, "speed": speed}
    L = lambda v: [_round(x * fl) for x in v] if isinstance(v, list) else _round(v * fl)  # noqa: E731
    A = lambda v: [_round(x * fa) for x in v] if isinstance(v, list) else _round(v * fa)  # noqa: E731
    for link in d["links"].values():
        link["points"] = {k: L(v) for k, v in link["points"].items()}
        if "com" in link:
            link["com"] = L(link["com"])
    for j in d["joints"].values():
        fr = j.get("friction", {})
        if "radius" in fr:
            fr["radius"] = L(fr["radius"])
        if "length" in j:
            j["length"] = L(j["length"])
        for key in ("module", "radii", "radius"):
            if key in j:
                j[key] = L(j[key])
        if "pressure_angle" in j:
            j["pressure_angle"] = A(j["pressure_angle"])
        if "phase" in j:
            j["phase"] = (A if j["type"] == "gear" else L)(j["phase"])
        if j["type"] == "cam":
            _cam_units(j, L, A)
    for drv in d["drivers"].values():
        if "speed" in drv.get("motion", {}):
            drv["motion"]["speed"] = _round(drv["motion"]["speed"] * fs)
    _feature_units(d, L, A, fl, fa, fs)
    for load in d.get("loads", {}).values():
        if "table" in load:  # over the driver coordinate, an angle
            load["table"]["at"] = A(load["table"]["at"])
        for c in load.get("active", []):
            if "angle" in c:
                c["angle"] = A(c["angle"])
            if "travel" in c:
                c["travel"] = L(c["travel"])
    d["sketch"] = {k: L(v) for k, v in d["sketch"].items()}
    an = d["analysis"]
    for k in ("start", "sweep"):
        if k in an:
            an[k] = A(an[k])
    if an.get("at"):
        an["at"] = A(an["at"])
    return d


def random_units(doc: dict, seed: int) -> dict:
    rng = np.random.default_rng([seed, 7])
    return in_units(
        doc,
        str(rng.choice(list(LENGTH_UNITS))),
        str(rng.choice(list(ANGLE_UNITS))),
        str(rng.choice(list(SPEED_UNITS))),
    )


# ------------------------------------------------------------------ loading

_Dumper = getattr(yaml, "CSafeDumper", yaml.SafeDumper)
_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def to_text(doc: dict) -> str:
    return yaml.dump(doc, Dumper=_Dumper, sort_keys=False)


@functools.lru_cache(maxsize=64)
def system_of(text: str):
    """The built system of a document's text (cached: the relations reuse it)."""
    import kinetostatics as ks

    return ks.build_system(ks.loads(text))


def load(doc: dict):
    import kinetostatics as ks

    return ks.loads(to_text(doc))


def check(doc: dict, positions: int = 36):
    """Raise Rejected unless ``doc`` runs through a full turn well-conditioned."""
    import kinetostatics as ks

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            system = system_of(to_text(doc))
            turn = 2 * math.pi / abs(float(doc["drivers"]["motor"]["motion"]["speed"]))
            res = ks.analyze(
                system, times=np.arange(positions) * turn / positions, kinematics_only=True
            )  # followed through the whole turn
    except ks.KinetostaticsError as exc:
        raise Rejected(f"{type(exc).__name__}: {str(exc)[:120]}") from None
    conds = [c for c in res.names if c.endswith(".cond")]
    cmax = max((float(np.nanmax(res[c])) for c in conds), default=1.0)
    if not cmax < COND_MAX:
        raise Rejected(f"cond {cmax:.3g}")
    if getattr(res, "singular", None):
        raise Rejected("singular positions")
    for c in res.names:
        if not np.all(np.isfinite(res[c])):
            raise Rejected(f"non-finite {c}")
    return res


def _grid(doc, n):
    an = doc["analysis"]
    sign = math.copysign(1, doc["drivers"]["motor"]["motion"]["speed"])
    return an["start"] + sign * an["sweep"] * np.arange(n) / n


STATS = {"generated": 0, "rejected": 0}


@functools.cache
def _generate(seed: int, features: frozenset = frozenset()) -> tuple[str, int]:
    import kinetostatics as ks

    for attempt in range(MAX_ATTEMPTS):
        plan = _plan(seed, attempt, features)
        doc = _candidate(seed, attempt, plan)
        try:
            res = check(doc)
            doc = _decorate(doc, res, plan)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                system_of(to_text(doc))  # the features read and built
        except Rejected:
            continue
        except ks.KinetostaticsError:
            continue
        return to_text(doc), attempt
    raise RuntimeError(f"seed {seed}: no acceptable mechanism in {MAX_ATTEMPTS} attempts")


def generate(seed: int, features=()) -> dict:
    """An accepted random mechanism (SI units), deterministic in ``seed`` (and
    ``features``): with each of ``features`` (names from ``FEATURES``) for sure, the
    others as drawn."""
    text, attempts = _generate(seed, frozenset(features))
    return yaml.load(text, Loader=_Loader)


def rejections(seed: int, features=()) -> int:
    """How many candidates ``generate(seed, features)`` rejected before accepting one."""
    return _generate(seed, frozenset(features))[1]


def _cam_units(j, L, A):
    """A cam joint's keys in other units: lengths, angles, and lifts (a length for a
    translating follower, an angle for an oscillating one)."""
    j["base_radius"] = L(j["base_radius"])
    lift = A if "oscillating" in j else L
    for key in ("translating", "oscillating"):
        for k in ("offset", "arm", "pivot"):
            if k in j.get(key, {}):
                j[key][k] = L(j[key][k])
    m = j["motion"]
    if isinstance(m, dict):
        m["angle"], m["lift"] = A(m["angle"]), lift(m["lift"])
        return
    for seg in m:
        for k in ("over", "dwell"):
            if k in seg:
                seg[k] = A(seg[k])
        for k in ("rise", "return"):
            if k in seg:
                seg[k] = lift(seg[k])


def _element_units(el, fl, fa):
    """An element's keys in other length and angle units (forces and torques stay in N and
    N·m): a stiffness or damping per length (angle) unit, lengths, angles."""
    rotational = "joint" in el
    f = fa if rotational else fl
    for key in ("stiffness", "damping"):
        if key in el:
            el[key] = _round(el[key] / f)
    for key in ("free_length", "free_angle"):
        if key in el:
            el[key] = _round(el[key] * f)
    if "table" in el:
        key = "angle" if rotational else "length"
        el["table"][key] = [_round(x * f) for x in el["table"][key]]


def _feature_units(d, L, A, fl, fa, fs):
    """``in_units`` of effort tables, counterweights, elements and the drive's speed."""
    for drv in d["drivers"].values():
        if isinstance(drv.get("effort"), dict):  # over the joint's own angle
            drv["effort"]["table"]["at"] = A(drv["effort"]["table"]["at"])
    for link in d["links"].values():
        for cw in link.get("counterweights", {}).values():
            cw["at"] = L(cw["at"])
    for el in d.get("elements", {}).values():
        _element_units(el, fl, fa)
    if "drive" in d and "rated_speed" in d["drive"].get("motor", {}):
        d["drive"]["motor"]["rated_speed"] = _round(d["drive"]["motor"]["rated_speed"] * fs)
