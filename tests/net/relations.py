"""The verification net's relations (docs/verification.md).

Each ``relation_*(doc, seed)`` takes a mechanism as a YAML-like dict (SI
units as written by ``generate``, or a shipped file read with
``yaml.safe_load``) and returns the largest relative discrepancy it finds
(0 when the relation does not apply is reported as ``None``).  Relative means:
per result column, |a − b| / (max over the reference column of |b| + floor),
the accuracy measure of docs/conventions.md.  ``TOLERANCE`` gives the bound each relation
is held to; the tests and ``long_run.py`` share both.
"""

from __future__ import annotations

import copy
import math
import warnings

import numpy as np

from kinetostatics.dynamics.stages import cycle_stage, full_summary

try:
    from . import generate as G
except ImportError:  # run as a script from tests/net
    import generate as G

TOLERANCE = {
    "subset": 1e-7,
    "rigid": 1e-7,
    "units": 1e-7,
    "mirror": 1e-7,
    "power": 1e-7,
    "power_fd": 1e-4,
    "balance_at": 1e-6,
    "sketch": 1e-7,
    "grid": 1e-7,
    "derivatives": 1e-3,
    "energy": 1e-4,
    "quadrature": 1e-7,
    "cam_phase": 1e-9,
    "cycle_means": 1e-12,
}
FAMILY_FLOOR = 1e-6  # a column's scale is at least this much of its kind's largest
WORST = [0.0, ""]
DERIV = []  # the worst column seen (for messages)
SKIP = {"time", "travel", "friction.iterations", "power.residual", "power.residual_friction"}


def analyze(doc, **kw):
    """``kinetostatics.analyze`` of a document (the built system cached per text)."""
    import kinetostatics as ks

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ks.analyze(G.system_of(G.to_text(doc)), **kw)


def speed(doc):
    return float(doc["drivers"]["motor"]["motion"]["speed"])


def shipped(path):
    """A shipped mechanism file as an SI document (the loader's own ``dump``), with its
    loads and their conditions, and without event rows: the relations compare the rows
    they ask for, as a generated document's (``relation_subset`` asks for the events)."""
    import yaml

    import kinetostatics as ks
    from kinetostatics.io import dump

    doc = yaml.safe_load(dump(ks.load(path)))
    doc["analysis"]["events"] = False
    return doc


def grid(doc, n):
    return G._grid(doc, n)


def _angle_cols(names):
    return {c for c in names if c == "angle" or c.endswith((".theta", ".cam_angle"))}


def _wrap(d):
    return (d + 180.0) % 360.0 - 180.0


def _wrap_rad(d):
    return (d + math.pi) % (2 * math.pi) - math.pi


_FORCES = {"F", "N", "Fx", "Fy", "F_friction", "N_friction", "Fx_friction", "Fy_friction"}
_MOMENTS = {"M", "M_friction"}
# angles in degrees that are not positions (compared on their own scale, not modulo 360°):
# one kind with the links' θ, so that one that is 0 in exact arithmetic (the pressure angle
# of a flat face on a translating follower, ±4e-14°) is not measured against its round-off
_DEGREES = {"pressure_angle", "transmission_angle"}
# an element's length and speed (m, m/s; a rotational one's rad/s) are measured with the
# positions and velocities too: a spring to a fixed point of the crank has speed ±1e-15
_ELEMENT_KINDS = {"length": ("x", "y"), "speed": ("vx", "vy", "omega")}


def _family(c):
    """The kind of a column: its last name part (all ``.ax`` columns ...); all
    powers are one kind, and so are all reaction forces."""
    if c.startswith("power."):
        return "power"
    tail = c.rpartition(".")[2]
    if tail in _DEGREES:
        return "theta"
    return "force" if tail in _FORCES else tail


def _ratio_denominator(b, c):
    """The effort with friction an ``<driver>.efficiency`` column is divided by: the
    ratio's round-off grows as that effort passes near 0 (seed 1005557: 5e-7 of its
    peak gave η = 18,866, whose last seven digits are round-off of the two efforts)."""
    if not c.endswith(".efficiency"):
        return None
    head = c[: -len("efficiency")]
    for word in ("torque_friction", "force_friction"):
        if head + word in b.names:
            return head + word
    return None


def compare(a, b, rows_a=None, rows_b=None, columns=None, floor=1e-9, scales=None):
    """Max over columns of max_k |a_k − b_k| / (max_k |b_k| + floor·scale).

    Each kind's largest value (the scale of its round-off floor) is taken over
    ``scales``, a result over the run, when given: ``b`` of one or a few rows may sit
    where a whole kind vanishes (a cam's dwell: every torque ±1e-16 N·m, round-off
    zeros of either sign), and its own largest would then be round-off."""
    rows_a = slice(None) if rows_a is None else rows_a
    rows_b = slice(None) if rows_b is None else rows_b
    names = [c for c in (columns or b.names) if c not in SKIP and c in a.names]
    ang = _angle_cols(names)
    scales = b if scales is None else scales
    family = {}
    for c in scales.names:
        v = np.asarray(scales[c], float)
        if v.size and np.any(np.isfinite(v)):
            t = _family(c)
            family[t] = max(family.get(t, 0.0), float(np.nanmax(np.abs(v))))
    # a prismatic pair's moment reaction is a force times an offset along the guide: its
    # round-off is that of the forces times the mechanism's size (seed 1004917: a slide's
    # M_friction of 0.08 N·m beside normal forces of 3.7e14 N near a dead point)
    size = max(family.get("x", 0.0), family.get("y", 0.0))
    # a driving torque too, from the same reactions (seed 1003542: ±1e-16 N·m in a cam's
    # dwell where the run's largest torque was 5e-5 N·m beside reactions of 43 N)
    for t in [*_MOMENTS, *(t for t in family if t.startswith("torque"))]:
        if t in family:
            family[t] = max(family[t], family.get("force", 0.0) * size)
    # a power is a force times a speed and a moment times an angular speed: its round-off
    # is theirs, though the run's powers may all be small (seed 1003542: a load active at
    # one row only, in a cam's dwell, gave power.external ±1e-15 W where the run's largest
    # power was 5e-3 W, and 2.4e-7 of that between a grid row and the pose alone)
    if "power" in family:
        speed = max(family.get("vx", 0.0), family.get("vy", 0.0))
        effort = max(family.get(t, 0.0) for t in ("M", "torque"))
        turn = family.get("omega", 0.0)
        family["power"] = max(family["power"], family.get("force", 0.0) * speed, effort * turn)
    worst = 0.0
    for c in names:
        x, y = np.asarray(a[c], float)[rows_a], np.asarray(b[c], float)[rows_b]
        if x.size == 0:
            continue
        if c == "friction.status":  # 0 and 1 both mean solved (by the fixed point or by the
            x, y = np.where(x == 1, 0, x), np.where(y == 1, 0, y)  # homotopy): a method
        both_nan = np.isnan(x) & np.isnan(y)
        if np.any(np.isnan(x) != np.isnan(y)):
            WORST[:] = [math.inf, c + " (nan)"]
            return math.inf
        x, y = x[~both_nan], y[~both_nan]
        if x.size == 0:
            continue
        den = _ratio_denominator(b, c)
        if c in ang:
            d = np.abs(_wrap(x - y)) / 360.0
        elif den is not None:  # η = T/T_f: errors of T, T_f of their scale, divided by T_f
            t_f = np.asarray(b[den], float)[rows_b][~both_nan]
            d = np.abs(x - y) * np.abs(t_f) / (np.nanmax(np.abs(t_f)) * (1.0 + np.abs(y)))
        else:
            kind = family.get(_family(c), 0.0)
            if _family(c) == "alpha":  # α ~ ω² where every α is zero in exact arithmetic
                kind = max(kind, family.get("omega", 0.0) ** 2)
            for tail, like in _ELEMENT_KINDS.items():  # an element's length, speed: of the
                if _family(c) == tail:  # kinds of the points' and links' motion
                    kind = max([kind] + [family.get(k, 0.0) for k in like])
            scale = np.nanmax(np.abs(np.asarray(b[c], float))) + max(FAMILY_FLOOR * kind, floor)
            d = np.abs(x - y) / scale
        if float(np.max(d)) > worst:
            worst = float(np.max(d))
            if worst > WORST[0]:
                WORST[:] = [worst, c]
    return worst


def match_rows(a, b, tol=1e-7, same_time=False):
    """Pairs of rows (i in a, j in b) with the same driver angle (and, with
    ``same_time``, the same time: a row one turn later is another state where the
    cycle does not close, e.g. the end row of an ``events: true`` run)."""
    ia, ib = [], []
    ang_b = np.asarray(b["angle"], float)
    t_a, t_b = np.asarray(a.t, float), np.asarray(b.t, float)
    for i, x in enumerate(np.asarray(a["angle"], float)):
        d = np.abs(_wrap(ang_b - x))
        j = int(np.argmin(d))
        if same_time and abs(t_a[i] - t_b[j]) > 1e-9 * max(1.0, abs(t_b[j])):
            continue
        if d[j] < tol:
            ia.append(i)
            ib.append(j)
    return np.array(ia, int), np.array(ib, int)


# ------------------------------------------------------------------ relations


def relation_subset(doc, seed, n=24):
    """A random subset, another start, ``at:`` rows and ``events: true`` give
    the same numbers row for row as the full cycle."""
    rng = np.random.default_rng([seed, 11])
    full = analyze(doc, positions=grid(doc, n))
    psi = grid(doc, n)
    worst = 0.0
    idx = np.sort(rng.choice(n, size=max(2, n // 4), replace=False))
    part = analyze(doc, positions=psi[idx])
    worst = max(worst, compare(part, full, rows_b=idx))
    k = int(rng.integers(1, n))
    rolled = analyze(doc, positions=np.roll(psi, -k))
    ia, ib = match_rows(rolled, full)
    if len(ia) != n:
        return math.inf
    worst = max(worst, compare(rolled, full, ia, ib))
    d2 = copy.deepcopy(doc)
    d2["analysis"]["at"] = [float(x) for x in psi[rng.choice(n, 2, replace=False)] + 1e-3]
    d2["analysis"]["positions"] = n
    d2["analysis"]["events"] = True
    withat = analyze(d2)
    # by time too (both start at the same angle): where the cycle does not close (the
    # closure self-check warns: seed 1000172, a group that changes branch over the turn)
    # the end row of the events run is not its first
    ia, ib = match_rows(withat, full, same_time=True)
    if len(ia) < n:
        return math.inf
    worst = max(worst, compare(withat, full, ia, ib))
    extra = np.setdiff1d(np.arange(len(withat["angle"])), ia)
    if extra.size:  # at: and event rows against an exact analysis there
        ex = analyze(doc, positions=np.radians(np.asarray(withat["angle"])[extra]) + 0.0)
        kin = [
            c
            for c in ex.names
            if c.split(".")[-1] in ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "alpha")
        ]
        worst = max(
            worst, compare(withat, ex, extra, np.arange(extra.size), columns=kin, scales=full)
        )
        at_rows = [
            i
            for i in extra
            if np.min(np.abs(_wrap(np.degrees(d2["analysis"]["at"]) - withat["angle"][i]))) < 1e-7
        ]
        if at_rows:  # the at: rows (not events, where loads switch) in full
            ex2 = analyze(doc, positions=np.radians(np.asarray(withat["angle"])[at_rows]))
            worst = max(
                worst,
                compare(withat, ex2, np.array(at_rows), np.arange(len(at_rows)), scales=full),
            )
    return worst


def _rot(v, phi):
    c, s = math.cos(phi), math.sin(phi)
    return [c * v[0] - s * v[1], s * v[0] + c * v[1]]


def transformed(doc, phi=0.0, shift=(0.0, 0.0), mirror=False):
    """The mechanism rotated by phi and shifted (ground, sketch, directions in
    global axes, gravity, angle bands and start), or mirrored y → −y (then
    also moving links' local points, speeds, torques, gear phase and flank); a
    load table's driver coordinates move as the start does.  A resisting torque
    opposes the rotation whatever its sense: its magnitude stays."""
    d = copy.deepcopy(doc)
    M = (lambda v: [v[0], -v[1]]) if mirror else (lambda v: v)
    P = lambda v: [a + b for a, b in zip(_rot(M(v), phi), shift)]  # noqa: E731
    V = lambda v: _rot(M(v), phi)  # noqa: E731
    ground = d.get("ground", "ground")
    cams = _cam_links(d)
    _check_cams(d, cams)
    for name, link in d["links"].items():
        if name == ground:
            link["points"] = {k: P(v) for k, v in link["points"].items()}
            continue
        # a cam's profile is made in the frame's axes from the follower's placement there,
        # and the cam angle is 0 where the cam's axes are the frame's: a cam turns with the
        # frame as the frame turns, its own axes with it (so it starts in phase)
        L = V if name in cams else M
        link["points"] = {k: L(v) for k, v in link["points"].items()}
        if "com" in link:
            link["com"] = L(link["com"])
        for cw in link.get("counterweights", {}).values():
            cw["at"] = L(cw["at"])
    for j in d["joints"].values():
        if j["type"] == "prismatic":
            ax = j["axis"]
            turned = j["links"][0] == ground or j["links"][0] in cams  # axes turned by phi
            if turned:
                if "direction" in ax:
                    ax["direction"] = V(ax["direction"])
            elif mirror and "direction" in ax:
                ax["direction"] = M(ax["direction"])
            if mirror and "angle" in j:
                j["angle"] = -j["angle"]
            if turned:  # the slider's frame turns with the guide
                j["angle"] = j.get("angle", 0.0) + phi
        if j["type"] == "gear" and mirror:
            j["phase"] = -j.get("phase", 0.0)
        if j["type"] in ("gear", "rack") and mirror:
            j["flank"] = {"cw": "ccw", "ccw": "cw"}[j.get("flank", "ccw")]
        if j["type"] == "cam":
            _mirror_cam(j, M) if mirror else None
            _turn_cam(j, phi)
    sgn = -1 if mirror else 1
    _transform_features(d, phi, sgn, cams)
    d["gravity"] = V(d.get("gravity", [0, -9.81]))
    drv = d["drivers"]["motor"]
    if mirror:
        drv["motion"]["speed"] = -drv["motion"]["speed"]
    for load in d.get("loads", {}).values():
        if "table" in load:
            _move_table(load, V, sgn, phi)
        elif load["type"] == "force":
            load["value"] = V(load["value"])
        elif load["type"] == "torque" and mirror:
            load["value"] = -load["value"]
        if "axis" in load:
            load["axis"] = V(load["axis"])
        for c in load.get("active", []):
            for key in ("moving", "along"):
                if key in c:
                    c[key] = V(c[key])
            if "angle" in c:
                a, b = c["angle"]
                c["angle"] = [sgn * a + phi, sgn * b + phi]
    d["sketch"] = {k: P(v) for k, v in d["sketch"].items()}
    an = d["analysis"]
    an["start"] = sgn * an.get("start", 0.0) + phi
    return d


def _move_table(load, V, sgn, phi):
    """A load table carried through ``transformed``: over the driver coordinate ψ, which
    becomes sgn ψ + φ (rows sorted again); its forces turned, its torques × sgn."""
    t = load["table"]
    if load["type"] == "force":
        values = [V(v) for v in t["value"]]
    elif load["type"] == "torque":
        values = [sgn * v for v in t["value"]]
    else:  # a resistance's or a resisting torque's magnitude
        values = list(t["value"])
    rows = sorted(zip((sgn * a + phi for a in t["at"]), values))
    t["at"], t["value"] = [a for a, _ in rows], [v for _, v in rows]


def _vector_pairs(names):
    pairs = []
    for c in names:
        for sx, sy in (
            (".x", ".y"),
            (".vx", ".vy"),
            (".ax", ".ay"),
            (".Fx", ".Fy"),
            (".Fx_friction", ".Fy_friction"),
        ):
            if c.endswith(sx) and c[: -len(sx)] + sy in names:
                pairs.append((c, c[: -len(sx)] + sy, sx == ".x"))
    return pairs


def _expected(res, doc, phi, shift, mirror):
    """The original results carried through the transformation (a dict of columns)."""
    names = res.names
    out = {c: np.asarray(res[c], float).copy() for c in names}
    pairs = _vector_pairs(names)
    sg = -1.0 if mirror else 1.0
    paired = set()
    for cx, cy, is_pos in pairs:
        x, y = out[cx], sg * out[cy]
        c, s = math.cos(phi), math.sin(phi)
        out[cx], out[cy] = c * x - s * y, s * x + c * y
        if is_pos:
            out[cx] += shift[0]
            out[cy] += shift[1]
        paired |= {cx, cy}
    kinds = {j: v["type"] for j, v in doc["joints"].items()}
    cams = _cam_links(doc)
    elements = doc.get("elements") or {}
    for c in names:
        if c in paired or c in SKIP:
            continue
        head, _, tail = c.rpartition(".")
        if head in elements and "joint" in elements[head] and tail in ("angle", "speed"):
            turn = _turn_of(doc, elements[head]["joint"], phi, cams) if tail == "angle" else 0
            out[c] = sg * out[c] + math.degrees(turn)
        elif head in elements and tail == "energy" and mirror and "joint" in elements[head]:
            # a table spring's energy counts from its first table angle, which the mirror
            # makes the last: E(−s) = E(s) − ∫ f over the whole table (exact, piecewise linear)
            t = elements[head].get("table")
            if t is not None:
                out[c] = out[c] - float(np.trapezoid(t["torque"], t["angle"]))
        elif c == "angle" or tail == "theta":
            out[c] = sg * out[c] + (0.0 if head in cams else math.degrees(phi))
        elif not mirror:
            continue
        elif tail in (
            "omega",
            "alpha",
            "torque",
            "torque_friction",
            "torque_friction_approx",
            "M",
            "M_friction",
            "N",
            "N_friction",
        ):
            out[c] = -out[c]
        elif tail in ("friction", "friction_approx") and kinds.get(head) in (
            "revolute",
            "gear",
            "cam",
        ):
            # signed along a sense of rotation (a cam's tangent turns with the cam)
            out[c] = -out[c]
    return out


class _Cols:
    def __init__(self, cols):
        self.cols = cols
        self.names = list(cols)

    def __getitem__(self, c):
        return self.cols[c]


def relation_rigid(doc, seed, n=12):
    """Rotating and shifting the whole mechanism rotates the vectors and leaves
    torques, powers and efforts unchanged."""
    rng = np.random.default_rng([seed, 13])
    phi = float(rng.uniform(-math.pi, math.pi))
    L = (
        max(abs(x) for link in doc["links"].values() for p in link["points"].values() for x in p)
        or 1.0
    )
    shift = tuple(float(x) for x in rng.uniform(-2 * L, 2 * L, 2))
    base = analyze(doc, positions=grid(doc, n))
    moved = analyze(transformed(doc, phi, shift), positions=grid(transformed(doc, phi, shift), n))
    exp = _Cols(_expected(base, doc, phi, shift, False))
    # shaking.M is a moment about the origin; the groups' condition numbers
    # depend on the orientation of the axes (docs/verification.md)
    cols = [c for c in base.names if c != "shaking.M" and not c.endswith(".cond")]
    return compare(moved, exp, columns=cols, floor=1e-9)


def relation_mirror(doc, seed, n=12):
    """The mirror image (y → −y, hence the crank turning the other way) gives
    the mirrored results: CCW quantities change sign, y components flip."""
    base = analyze(doc, positions=grid(doc, n))
    m = transformed(doc, mirror=True)
    res = analyze(m, positions=grid(m, n))
    exp = _Cols(_expected(base, doc, 0.0, (0.0, 0.0), True))
    cols = [c for c in base.names if c != "shaking.M"]
    return compare(res, exp, columns=cols)


def relation_units(doc, seed, n=12):
    """The same generated mechanism in mm/deg/rpm and in m/rad/(rad/s); with ``drive:`` or
    ``flywheel:`` also the drive's sizing and the flywheel's design of the summary."""
    d = copy.deepcopy(doc)
    d["analysis"]["positions"] = n
    a = analyze(d)
    b = analyze(G.in_units(d, "mm", "deg", "rpm"))
    worst = compare(b, a)
    if "drive" in d or "flywheel" in d:
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            sb, sa = full_summary(b), full_summary(a)
        # where the stage warns that the rows miss a pole (``stages.between_rows``, seed
        # 1007872), the drive's peaks near it are not claimed to round-off
        if not any("between the analysed rows" in str(w.message) for w in said):
            worst = max(worst, compare_summaries(sb, sa))
    return worst


def _leaves(x, path=""):
    """The numbers (and booleans) of a summary section, by their path."""
    if isinstance(x, dict):
        for k, v in x.items():
            yield from _leaves(v, f"{path}.{k}")
    elif isinstance(x, (list, tuple)):
        for k, v in enumerate(x):
            yield from _leaves(v, f"{path}[{k}]")
    elif isinstance(x, (bool, int, float)) or x is None:
        yield path, x


def compare_summaries(a, b):
    """The largest relative difference between the numbers of the ``drive`` and ``flywheel``
    sections of two summaries (SI both), each measured against |b| plus 10⁻⁶ of the
    section's largest number (a mean torque of ±10⁻¹³ N·m is a round-off zero); a
    boolean that differs, a number where the other has none: inf."""
    worst = 0.0
    for section in ("drive", "flywheel"):
        if section not in b:
            continue
        la, lb = dict(_leaves(a.get(section))), dict(_leaves(b[section]))
        if la.keys() != lb.keys():
            WORST[:] = [math.inf, f"summary {section}: keys differ"]
            return math.inf
        floats = [abs(v) for v in lb.values() if type(v) is float and math.isfinite(v)]
        floor = FAMILY_FLOOR * max(floats, default=0.0) + 1e-300
        for k, y in lb.items():
            x = la[k]
            if isinstance(y, bool) or y is None or x is None or isinstance(x, bool):
                bad = x != y
            elif math.isnan(y) or math.isnan(x):
                bad = math.isnan(y) != math.isnan(x)
            else:
                e = abs(x - y) / (abs(y) + floor)
                bad = False
                if e > worst:
                    worst = e
                    if e > WORST[0]:
                        WORST[:] = [e, f"summary {section}{k}"]
            if bad:
                WORST[:] = [math.inf, f"summary {section}{k}: {x!r} against {y!r}"]
                return math.inf
    return worst


def _masses(doc):
    """(mass, inertia about the centre of mass) of each moving link, its counterweights
    added by the parallel-axis theorem (docs/yaml.md, *Counterweights*)."""
    ground = doc.get("ground", "ground")
    out = {}
    for name, link in doc["links"].items():
        if name == ground:
            continue
        m0, J0 = float(link.get("mass", 0.0)), float(link.get("inertia", 0.0))
        c0 = np.asarray(link.get("com", [0.0, 0.0]), float)
        parts = [(m0, J0, c0)] + [
            (float(cw["mass"]), float(cw.get("inertia", 0.0)), np.asarray(cw["at"], float))
            for cw in link.get("counterweights", {}).values()
        ]
        m = sum(p[0] for p in parts)
        c = sum(p[0] * p[2] for p in parts) / m if m > 0 else c0
        J = sum(p[1] + p[0] * float(np.sum((p[2] - c) ** 2)) for p in parts)
        out[name] = (m, J)
    return out


def relation_power(doc, seed, n=12):
    """Σ driver power = dT/dt + dV/dt + P_ext (+ friction loss), from the
    power columns; dT/dt also from finite differences of the kinetic energy."""
    res = analyze(doc, positions=grid(doc, n))
    terms = ["power.kinetic", "power.potential", "power.elastic", "power.damping"]
    terms = [t for t in terms if t in res.names] + ["power.external"]
    scale = max(max(float(np.max(np.abs(res[t]))) for t in ["power.input", *terms]), 1e-12)
    stored = sum(res[t] for t in terms)
    w = effort_speed(doc, res)
    worst = float(np.max(np.abs(res["power.input"] - stored))) / scale
    worst = max(worst, _element_powers(doc, res) / scale)
    if w is None:  # the effort at a slide: power.input is the check
        return worst
    worst = max(worst, float(np.max(np.abs(res["motor.torque"] * w - res["power.input"]))) / scale)
    if "power.friction" in res.names and "motor.torque_friction" in res.names:
        ok = np.isfinite(res["motor.torque_friction"])
        pin_f = res["motor.torque_friction"][ok] * w[ok]
        bal = pin_f - stored[ok] - res["power.friction"][ok]
        worst = max(worst, float(np.max(np.abs(bal), initial=0.0)) / scale)
        if np.any(res["power.friction"][ok] < -1e-9 * scale):
            worst = math.inf
    return worst


def _element_powers(doc, res):
    """The largest |power.elastic − Σ springs' power| and |power.damping − Σ dampers'
    power| (each element's power f·ṡ from its own F or M and speed columns), inf where a
    damper's power is negative: it only dissipates."""
    elements = doc.get("elements") or {}
    if not elements:
        return 0.0
    worst = 0.0
    for term, kinds in (("power.elastic", ("spring", "torsion_spring")),
                        ("power.damping", ("damper", "rotary_damper"))):  # fmt: skip
        names = [n for n, e in elements.items() if e["type"] in kinds]
        if not names:
            continue
        each = [
            np.asarray(res[f"{n}.{'M' if 'joint' in elements[n] else 'F'}"])
            * np.asarray(res[f"{n}.speed"])
            for n in names
        ]
        worst = max(worst, float(np.max(np.abs(res[term] - sum(each)))))
        scale = max(float(np.max(np.abs(res[term]))), 1e-12)
        if term == "power.damping" and np.any(res[term] < -1e-12 * scale):
            return math.inf
    return worst


def effort_speed(doc, res):
    """The relative angular speed of the joint that carries the motor's effort, per row,
    from the links' ω columns (the driver's own joint, or ``balance_at``); None for a
    joint that does not turn (a slide)."""
    joint = doc["drivers"]["motor"].get("balance_at", doc["drivers"]["motor"]["joint"])
    spec = doc["joints"][joint]
    if spec["type"] != "revolute":
        return None
    ground = doc.get("ground", "ground")
    li, lj = spec["links"][:2]
    omega = [
        np.zeros(len(res)) if name == ground else np.asarray(res[f"{name}.omega"])
        for name in (li, lj)
    ]
    return omega[1] - omega[0]


def kinetic_energy(doc, res):
    T = 0.0
    for name, (m, J) in _masses(doc).items():
        T = (
            T
            + 0.5 * m * (res[f"{name}.vx"] ** 2 + res[f"{name}.vy"] ** 2)
            + 0.5 * J * res[f"{name}.omega"] ** 2
        )
    return T


def relation_power_fd(doc, seed, h=1e-4, k=3):
    """dT/dt by central differences of T along the motion = power.kinetic; the
    potential power likewise from V = −Σ m g·r_S."""
    rng = np.random.default_rng([seed, 17])
    w = speed(doc)
    g = np.asarray(doc.get("gravity", [0, -9.81]), float)
    psi = grid(doc, 36)[rng.choice(np.arange(2, 34), k, replace=False)]
    worst = 0.0
    ref = analyze(doc, positions=grid(doc, 36))
    scale = max(
        max(np.max(np.abs(ref[c])) for c in ref.names if c.startswith("power.")),
        abs(w) * np.max(kinetic_energy(doc, ref)),
        1e-12,
    )
    for p in np.sort(psi * np.sign(w)) * np.sign(w):
        pos = p + np.sign(w) * np.array([-h, 0.0, h])
        r = analyze(doc, positions=pos)
        dt = r["time"][2] - r["time"][0]
        T = kinetic_energy(doc, r)
        V = -sum(
            m * (g[0] * r[f"{name}.x"] + g[1] * r[f"{name}.y"])
            for name, (m, _) in _masses(doc).items()
        )
        worst = max(
            worst,
            abs((T[2] - T[0]) / dt - r["power.kinetic"][1]) / scale,
            abs((V[2] - V[0]) / dt - r["power.potential"][1]) / scale,
        )
    return worst


def _balance_joints(doc):
    """Revolutes other than the driver's whose relative rotation follows the crank."""
    own = doc["drivers"]["motor"]["joint"]
    return [j for j, v in doc["joints"].items() if v["type"] == "revolute" and j != own]


def relation_balance_at(doc, seed, n=12):
    """The effort taken at another revolute (``balance_at``) gives the same
    input power at rows where that joint's relative speed is not small."""
    rng = np.random.default_rng([seed, 19])
    cand = _balance_joints(doc)
    if not cand:
        return None
    j = cand[int(rng.integers(len(cand)))]
    base = analyze(doc, positions=grid(doc, n), friction=False)
    d2 = copy.deepcopy(doc)
    d2["drivers"]["motor"]["balance_at"] = j
    d2.pop("drive", None)  # a drive sizes the effort at the driver's own joint
    li, lj = doc["joints"][j]["links"]
    ground = doc.get("ground", "ground")
    wrel = (base[f"{lj}.omega"] if lj != ground else 0.0) - (
        base[f"{li}.omega"] if li != ground else 0.0
    )
    if np.max(np.abs(wrel)) < 1e-6 * abs(speed(doc)):
        return None  # a joint that does not turn cannot take the effort
    ok = np.abs(wrel) > 0.2 * np.max(np.abs(wrel))
    import kinetostatics as ks

    try:
        other = analyze(d2, positions=grid(doc, n), friction=False)
    except ks.KinetostaticsError:
        return None  # not admissible (the effort cannot balance there)
    if other.indeterminate:
        return None  # singular there: minimum-norm reactions, flagged
    scale = np.max(np.abs(base["power.input"])) + 1e-12
    p_other = other["motor.torque"] * wrel
    return max(
        float(np.max(np.abs(p_other[ok] - base["power.input"][ok]))) / scale,
        float(np.max(np.abs(other["power.input"][ok] - base["power.input"][ok]))) / scale,
    )


def relation_sketch(doc, seed, tol_rel=None):
    """Every sketched point is assembled where it was sketched (exactly, for a
    generated mechanism; for a shipped file its rough sketch is compared with
    ``tol_rel``) — returns max distance / longest link."""
    res = analyze(doc, positions=grid(doc, 1)[:1])
    L = _lref(doc)
    worst = 0.0
    ground = doc.get("ground", "ground")
    for key, xy in doc["sketch"].items():
        pts = []
        if "." in key:
            pts.append(key)
        else:
            j = doc["joints"][key]
            if j["type"] == "revolute":
                pi, pj = j.get("points", [key, key])
                pts += [f"{lk}.{p}" for lk, p in zip(j["links"], (pi, pj)) if lk != ground]
            else:
                pts.append(f"{j['links'][1]}.{j.get('point', key)}")
        for p in pts:
            x, y = float(res[p + ".x"][0]), float(res[p + ".y"][0])
            worst = max(worst, math.hypot(x - xy[0], y - xy[1]) / L)
    return worst


def _lref(doc):
    best = 0.0
    for link in doc["links"].values():
        pts = list(link["points"].values())
        for a in pts:
            for b in pts:
                best = max(best, math.hypot(a[0] - b[0], a[1] - b[1]))
    return best or 1.0


def relation_grid(doc, seed, n=24):
    """N, N+1 and random positions give the same values at each row as an
    exact re-analysis at that row's angle alone."""
    rng = np.random.default_rng([seed, 23])
    worst = 0.0
    sign = np.sign(speed(doc))
    start = doc["analysis"].get("start", 0.0)
    rand = start + sign * np.sort(rng.uniform(0, 2 * math.pi, 5))
    for pos in (grid(doc, n), grid(doc, n + 1), rand):
        res = analyze(doc, positions=pos)
        for i in rng.choice(len(pos), 2, replace=False):
            single = analyze(doc, positions=np.array([pos[i]]))
            worst = max(
                worst,
                compare(
                    res,
                    single,
                    np.array([i]),
                    np.array([0]),
                    columns=[c for c in single.names],
                    scales=res,
                ),
            )
    return worst


def _beyond(e: float, floor: float) -> float:
    """``e`` less its round-off ``floor`` (0 within it), with its sign."""
    return math.copysign(max(abs(float(e)) - floor, 0.0), e)


def relation_derivatives(doc, seed, h=2e-2, k=2, levels=8):
    """Central differences of positions in time agree with the exact velocities
    and accelerations: their error is O(h²) (checked against h/2), and what is
    compared is their Richardson extrapolation (4·D(h/2) − D(h))/3, whose error is
    O(h⁴).  The O(h²) term, h²/6·x⁽³⁾ for a velocity and h²/12·x⁽⁴⁾ for an
    acceleration, is as large against a column's own scale as the motion is sharp,
    so no fixed fraction bounds it: a column whose acceleration varies ~15× faster
    than the crank turns had 1.8·10⁻³ at h/2 (seed 1005196; it fell exactly as h²).
    The extrapolation removes that term whatever its size.

    Neither expansion holds unless the step resolves the motion, and no fixed h
    does: near a toggle an acceleration can swing by its own size within ±0.02 rad
    (seed 1002072: 44,201 at the centre, −12,614 one step back; the errors fell
    2.3×, not 4×, from h to h/2), and a narrow peak leaves an O(h⁴) term above the
    tolerance (seed 1003449: 4.4·10⁻³ extrapolated from h, 4·10⁻⁴ from h/2).  So
    the step is halved, as in Romberg's method, until two successive
    extrapolations agree to a tenth of the tolerance — their difference estimates
    the coarser one's error, so the step then resolves the motion — and the finer
    one is compared; the h² check applies to that last pair of steps.  The
    differences' own round-off (ε|x|/Δt, 4ε|x|/Δt²) grows as the step falls and is
    taken off each error: a crank's exact α = 0 met 10⁻⁵ of noise at h/128 while
    other columns still needed halving (seed 1005742).  Where a cam law's segment end
    lies within a step of the centre, the acceleration jumps inside the stencil and its
    difference is off by O(1) until the step no longer reaches it (seed 1006298: 0.07 of
    the scale at 3.1·10⁻⁴ rad, 10⁻⁷ at half that); extrapolating across that change is
    meaningless, so once the difference itself agrees to the resolution it is compared
    as it is.  A wrong
    exact derivative is a difference that does not fall with h: the extrapolations
    agree at once, on that difference."""
    rng = np.random.default_rng([seed, 29])
    w = speed(doc)
    sign = np.sign(w)
    start = doc["analysis"].get("start", 0.0)
    full = analyze(doc, positions=grid(doc, 24), kinematics_only=True)
    fam = {}
    for c in full.names:
        t = c.rpartition(".")[2]
        fam[t] = max(fam.get(t, 0.0), float(np.max(np.abs(full[c]))))
    vmax, amax = max(fam.get("vx", 0), fam.get("vy", 0)), max(fam.get("ax", 0), fam.get("ay", 0))
    resolved = TOLERANCE["derivatives"] / 10
    worst = 0.0
    for u in rng.uniform(0.3, 2 * math.pi - 0.3, k):
        errs, diffs, rich = [], [], {}
        for level in range(levels):
            hh = h / 2**level
            pos = start + sign * (u + np.array([-hh, 0.0, hh]))
            r = analyze(doc, positions=pos, kinematics_only=True)
            dt = hh / abs(w)
            d = {}  # (difference − exact) / scale, per velocity and acceleration column
            for c in r.names:
                base, _, tail = c.rpartition(".")
                if tail not in ("x", "y", "theta"):
                    continue
                x = np.asarray(r[c], float) * (math.pi / 180 if tail == "theta" else 1.0)
                v_name = f"{base}.{'omega' if tail == 'theta' else 'v' + tail}"
                a_name = f"{base}.{'alpha' if tail == 'theta' else 'a' + tail}"
                v_fd = (x[2] - x[0]) / (2 * dt)
                a_fd = (x[2] - 2 * x[1] + x[0]) / dt**2
                sv = (
                    np.max(np.abs(full[v_name]))
                    + 1e-3 * (fam["omega"] if tail == "theta" else vmax)
                    + 1e-12 * abs(w)
                )
                sa = (
                    np.max(np.abs(full[a_name]))
                    + 1e-3 * (fam["alpha"] if tail == "theta" else amax)
                    + 1e-12 * w * w
                )
                # round-off of the differences (x to ε|x| each) grows as the step falls:
                # it is no error of the exact derivative, so it is taken off
                xr = 4 * np.finfo(float).eps * float(np.max(np.abs(x)))
                d[v_name] = _beyond(v_fd - r[v_name][1], xr / dt) / sv
                d[a_name] = _beyond(a_fd - r[a_name][1], 4 * xr / dt**2) / sa
            errs.append(max((abs(x) for x in d.values()), default=0.0))
            diffs.append(d)
            if level == 0:
                continue
            if errs[-1] <= resolved:  # the difference itself agrees: no extrapolation with a
                # coarser step, which may straddle an acceleration's jump (seed 1006298)
                rich = {c: float(d[c]) for c in d}
                break
            # all steps share the centre, hence the exact value
            finer = {c: float((4 * d[c] - diffs[-2][c]) / 3) for c in d}
            change = max((abs(finer[c] - rich[c]) for c in rich), default=math.inf)
            rich = finer
            if change <= resolved:
                break
        for c, x in rich.items():
            if abs(x) > worst:
                worst = abs(x)
                if worst > WORST[0]:
                    WORST[:] = [worst, c]
        if errs[-2] > 1e-5 and errs[-1] > errs[-2] / 2.5:  # no h² convergence
            worst = max(worst, math.inf)
        DERIV.append(errs)
    return worst


def relation_energy(doc, seed, turns=0.3):
    """Frictionless forward dynamics with only gravity and the elements conserves
    T + V + the springs' energy + the work the dampers have dissipated.  The loads and
    the other drivers' efforts (known forces that are not conservative) are taken off,
    as friction is; springs and dampers stay, their energy and dissipation counted."""
    from kinetostatics import dynamics

    d = copy.deepcopy(doc)
    for j in d["joints"].values():
        j.pop("friction", None)
    d["loads"] = {}
    d["drivers"] = {"motor": d["drivers"]["motor"]}
    d.pop("drive", None)
    d.pop("flywheel", None)
    w = speed(d)
    drv = d["drivers"]["motor"]
    drv.pop("motion")
    drv.pop("balance_at", None)
    drv["effort"] = 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = G.load(d)
        start = d["analysis"].get("start", 0.0)
        sim = dynamics.simulate(
            model, turns * 2 * math.pi / abs(w), initial={"motor": (start, w)}, rtol=1e-9
        )
        cols, _ = sim.table(points=21)
    E = cols["energy.total"] + (cols["work.dampers"] if "work.dampers" in cols else 0.0)
    scale = max(np.max(np.abs(cols["energy.kinetic"])), 1e-12)
    return float(np.max(np.abs(E - E[0]))) / scale


def without_conditions(doc, kinds=("moving", "travel")):
    """The mechanism with the ``active:`` conditions of these kinds removed."""
    d = copy.deepcopy(doc)
    for load in d.get("loads", {}).values():
        load["active"] = [c for c in load.get("active", []) if not any(k in c for k in kinds)]
        if not load["active"]:
            load.pop("active")
    return d


def has_conditions(doc, kinds=("moving", "travel")):
    return any(
        k in c
        for load in doc.get("loads", {}).values()
        for c in load.get("active", [])
        for k in kinds
    )


def relation_quadrature(doc, seed):
    """The cycle's means and RMS values of the driving efforts (with friction where the
    mechanism has it) agree between 8-point and 16-point Gauss–Legendre on twice the
    pieces: so the integrand is smooth between the integrator's cuts (a jump or a kink
    it does not cut at, such as a friction reversal or a normal force through zero,
    leaves 1e-8 to 1e-4).  Relative to the RMS.  Held to 1e-7, as the other relations:
    a pin force passing close to zero gives ρ|F| a sharp though smooth minimum; the
    integrator halves the pieces there (checked on the efforts with friction), after
    which the two orders agree to 2e-8 on the long run's 104 seeds that failed before (up
    to 9e-6 then).  A column the cycle's stage warns has no solution between the rows (a
    self-locked zone or a dead centre the rows step over, seed 1007872) is not compared:
    its integral runs to the pole at the zone's edge."""
    from kinetostatics.analysis import cycle

    res = analyze(doc)
    efforts = {
        f"{w}{t}" for w in ("torque", "force") for t in ("", "_friction", "_friction_approx")
    }
    columns = [c for c in res.columns if c.startswith("motor.") and c[6:] in efforts]
    if not columns:
        return None
    from kinetostatics.dynamics.stages import between_rows

    saved = cycle.NODES, cycle.PIECES
    stats = []
    said = set()
    try:
        for nodes, pieces in ((8, 36), (16, 72)):
            cycle.NODES, cycle.PIECES = nodes, pieces
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = analyze(doc)
                quad = cycle.cycle_quadrature(r)
                stats.append(cycle.cycle_stats(r, columns, given=quad))
                said |= between_rows(r, quad)
    finally:
        cycle.NODES, cycle.PIECES = saved
    worst = 0.0
    for c in columns:
        if c in said and stats[1][c]["covered"] < 1:  # a self-locked zone or a dead centre
            continue  # between the rows, said: the integral runs to its pole
        a, b = stats[0][c], stats[1][c]
        if not (np.isfinite(b["rms"]) and b["rms"] > 0):
            continue
        for k in ("mean", "rms"):
            e = abs(a[k] - b[k]) / b["rms"]
            if e > worst:
                worst, WORST[:] = e, [e, f"{c} {k}"]
    return worst


def _law_value(motion, theta):
    """The lift s(θ) of a cam's ``motion:`` segments (SI), from the curves' closed forms
    (docs/yaml.md), written here again: the relation's own truth.  None for a table."""
    if isinstance(motion, dict):
        return None
    curves = {
        "harmonic": lambda u: (1 - np.cos(np.pi * u)) / 2,
        "cycloidal": lambda u: u - np.sin(2 * np.pi * u) / (2 * np.pi),
        "polynomial": lambda u: 10 * u**3 - 15 * u**4 + 6 * u**5,
        "polynomial7": lambda u: 35 * u**4 - 84 * u**5 + 70 * u**6 - 20 * u**7,
    }
    th = np.mod(theta, 2 * math.pi)
    out, start, base = np.zeros(th.shape), 0.0, 0.0
    for seg in motion:
        kind = next(k for k in ("rise", "dwell", "return") if k in seg)
        span = float(seg["dwell"] if kind == "dwell" else seg["over"])
        inside = (th >= start) & (th <= start + span)
        if kind == "dwell":
            out = np.where(inside, base, out)
        else:
            h = float(seg[kind]) * (1 if kind == "rise" else -1)
            u = np.clip((th - start) / span, 0.0, 1.0)
            out = np.where(inside, base + h * curves[seg.get("law", "cycloidal")](u), out)
            base += h
        start += span
    return out


def _cam_lift_measured(j, res):
    """The follower's lift measured on its pose in the frame (the result's point columns),
    by the placement's definition (docs/yaml.md): translating, the follower point's (a
    flat face's point's) distance along the rise less its distance at zero lift;
    oscillating knife or roller, the arm's turn κ(β − β₀) from where the follower point
    lies on the prime circle, on the side where a rise moves it outwards.  None for an
    oscillating flat face (its cam angle is checked)."""
    cam, fol = j["links"]
    centre = np.stack((res[f"{cam}.{j['centre']}.x"], res[f"{cam}.{j['centre']}.y"]), -1)
    P = np.stack((res[f"{fol}.{j['point']}.x"], res[f"{fol}.{j['point']}.y"]), -1) - centre
    rb, rr = float(j["base_radius"]), float(j.get("radius", 0.0))
    rp = rb + rr
    if "translating" in j:
        u = np.asarray(j["translating"]["direction"], float)
        u = u / np.hypot(*u)
        e = float(j["translating"].get("offset", 0.0))
        zero = rb if j["follower"] == "flat" else math.sqrt(rp * rp - e * e)
        return P @ u - zero
    if j["follower"] == "flat":
        return None
    osc = j["oscillating"]
    A, L = np.asarray(osc["pivot"], float), float(osc["arm"])
    kappa = 1 if osc.get("rise", "ccw") == "ccw" else -1
    a = math.hypot(*A)
    c = (rp * rp - a * a - L * L) / (2 * L * a)
    ang = math.atan2(A[1], A[0])
    b0 = None
    for b in (ang + math.acos(c), ang - math.acos(c)):
        dd = 1e-6
        far = np.hypot(*(A + L * np.array([math.cos(b + kappa * dd), math.sin(b + kappa * dd)])))
        if far > rp:
            b0 = b
    if b0 is None:  # the pivot on the cam centre's line of the rise: no such cam
        return None
    D = P - A
    beta = np.arctan2(D[:, 1], D[:, 0])
    return kappa * _wrap_rad(beta - b0)


def relation_cam_phase(doc, seed):
    """Every cam runs in phase with its law: at each row the contact's cam angle is the
    cam link's rotation from the frame in the cam's sense, and the follower's lift
    measured on its pose equals the law's value at that angle — in particular at the
    law's zero.  The largest of the angle's misfit (rad) and the lift's misfit relative to
    the largest lift; None without a cam."""
    cams = {n: j for n, j in doc["joints"].items() if j.get("type") == "cam"}
    if not cams:
        return None
    res = analyze(doc)
    worst = 0.0
    ground = doc.get("ground", "ground")
    for name, j in cams.items():
        sigma = 1 if j.get("rotation", "ccw") == "ccw" else -1
        rot = 0.0 if j["links"][0] == ground else np.radians(res[f"{j['links'][0]}.theta"])
        phase = np.mod(sigma * rot, 2 * math.pi) * np.ones(len(res["angle"]))
        found = np.radians(res[f"{name}.cam_angle"])
        e = float(np.max(np.abs(_wrap_rad(found - phase))))
        if e > worst:
            worst, WORST[:] = e, [e, f"{name}.cam_angle"]
        law = _law_value(j["motion"], phase)
        lift = _cam_lift_measured(j, res)
        if law is None or lift is None:
            continue
        scale = max(float(seg.get("rise", 0.0)) for seg in j["motion"])
        e = float(np.max(np.abs(lift - law))) / scale
        if e > worst:
            worst, WORST[:] = e, [e, f"{name} lift"]
    return worst


CONVERGED = ((8, 36), (16, 72))  # (nodes, pieces): today's quadrature, and twice the order
# on half the pieces


def relation_cycle_means(doc, seed):
    """The cycle's means converged: the frictionless mean and RMS of the driving effort,
    the flywheel's M_d and ΔW (a flywheel of δ = 0.05 on a constant-speed crank) and the
    drive's means (the file's drive, else a reduction of efficiency 0.85, whose motor-side
    torque has a kink at every zero of the effort) agree between 8-point Gauss–Legendre on
    the integrator's pieces and 16-point on twice as many, both between the same cuts, to
    1e-12 of each quantity's scale (an effort's largest |value| at the rows and the nodes,
    2π times it for a work, the motor's peak torque and power for the drive's): so every
    jump and kink of the integrand is a cut, located to round-off (a missed or misplaced
    one leaves 1e-10 to 1e-4).  Friction is left to ``relation_quadrature`` (its 1e-9 dead band at a
    reversal, docs/conventions.md)."""
    from dataclasses import replace

    from kinetostatics.analysis import cycle
    from kinetostatics.dynamics.drive import size
    from kinetostatics.dynamics.flywheel import design
    from kinetostatics.errors import KinetostaticsError
    from kinetostatics.model import DriveSpec

    res = analyze(doc)
    columns = [c for c in res.columns if c in ("motor.torque", "motor.force")]
    if not columns:
        return None
    model = res.system.model
    spec = replace(model.drive or DriveSpec(efficiency=0.85), friction=False)
    values: list[dict] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        quads = [cycle.cycle_quadrature(res, friction=False, quadrature=q) for q in CONVERGED]
        # the largest |effort| at the rows and at the nodes: near a dead point the effort
        # peaks between the rows (seed 1004622: 2.3e6 at the nodes, 689 at the rows), and
        # the sums' round-off is that of the values summed
        seen = [np.asarray(r[columns[0]]) for r in (res, *(q.nodes for q in quads))]
        scale = float(max(np.max(np.abs(v[np.isfinite(v)]), initial=0.0) for v in seen))
        if not scale > 0:
            return None
        for q, quad in zip(CONVERGED, quads):
            out = {}
            st = cycle.cycle_stats(res, columns, friction=False, quadrature=q, given=quad)
            st = st[columns[0]]
            out["mean"], out["rms"] = (st["mean"], scale), (st["rms"], scale)
            try:
                fw = design(res, delta=0.05, friction=False, quadrature=q, nodes=quad)
            except (KinetostaticsError, ValueError):  # not a constant-speed crank
                pass
            else:
                out["flywheel.M_d"] = (fw.mean_torque, scale)
                out["flywheel.dW"] = (fw.energy_swing, 2 * np.pi * scale)
            try:
                d = size(res, spec, quadrature=q, nodes=quad)
            except (KinetostaticsError, ValueError):  # no revolute motion driver
                pass
            else:
                top, power = d.motor["torque"]["peak"], d.motor["power"]["peak"]
                out["drive.motor_torque.mean"] = (d.motor["torque"]["mean"], top)
                out["drive.motor_torque.rms"] = (d.motor["torque"]["rms"], top)
                out["drive.motor_power.mean"] = (d.motor["power"]["mean"], power)
            values.append(out)
    worst = 0.0
    for key, (a, sc) in values[0].items():
        b = values[1][key][0]
        if not (np.isfinite(a) and np.isfinite(b)):
            continue
        e = abs(a - b) / sc
        if e > worst:
            worst, WORST[:] = e, [e, key]
    return worst


RELATIONS = {
    "subset": relation_subset,
    "rigid": relation_rigid,
    "units": relation_units,
    "mirror": relation_mirror,
    "power": relation_power,
    "power_fd": relation_power_fd,
    "balance_at": relation_balance_at,
    "sketch": relation_sketch,
    "grid": relation_grid,
    "derivatives": relation_derivatives,
    "energy": relation_energy,
    "quadrature": relation_quadrature,
    "cam_phase": relation_cam_phase,
    "cycle_means": relation_cycle_means,
}


def diagnose(relation: str, doc: dict, seed: int) -> str | None:
    """A hint for triaging a failure of a relation (the long run prints it beside the
    failure): whether the relation passes on the same mechanism without its ``moving`` or
    ``travel`` load conditions (a fault in locating switches and extremes), or None."""
    for kinds in (("travel",), ("moving", "travel")):
        if not has_conditions(doc, kinds):
            continue
        try:
            value = RELATIONS[relation](without_conditions(doc, kinds), seed)
        except Exception:  # noqa: BLE001
            continue
        if value is None or value <= TOLERANCE[relation]:
            return f"passes without its {'/'.join(kinds)} conditions"
    return None


def _mirror_cam(j, M):
    """A cam joint mirrored: its senses turn over, its placement and face are mirrored."""
    flip = {"cw": "ccw", "ccw": "cw"}
    tr, osc = j.get("translating"), j.get("oscillating")
    j["rotation"] = flip[j.get("rotation", "ccw")]
    if tr is not None:
        tr["direction"] = M(tr["direction"])
    if osc is not None:
        osc["pivot"] = M(osc["pivot"])
        osc["rise"] = flip[osc.get("rise", "ccw")]
    if "face_normal" in j:
        j["face_normal"] = M(j["face_normal"])


# -- batch row = single run ------------------------------------------------------------
FACTORS = ("mass_factor", "speed_factor")
ALONE = []  # (chunk, variants analysed one by one) of each batch: is the vectorised path run


def with_factors(doc):
    """The mechanism with two parameters, both 1 as written: ``mass_factor`` scales every
    link's mass and inertia, ``speed_factor`` the motion drivers' constant speeds (the
    variants of a batch; which numbers they scale moves every kinetic quantity)."""
    d = copy.deepcopy(doc)
    d["parameters"] = {**d.get("parameters", {}), FACTORS[0]: 1.0, FACTORS[1]: 1.0}
    for link in d["links"].values():
        for key in ("mass", "inertia"):
            if isinstance(link.get(key), (int, float)):
                link[key] = f"{float(link[key])!r} * {FACTORS[0]}"
    for drv in d.get("drivers", {}).values():
        motion = drv.get("motion")
        if isinstance(motion, dict) and isinstance(motion.get("speed"), (int, float)):
            motion["speed"] = f"{float(motion['speed'])!r} * {FACTORS[1]}"
    return d


def _finite(x):
    x = np.asarray(x, dtype=float)
    return x[np.isfinite(x)]


def _largest_abs(x):  # docs/batch.md: max |x| over the finite rows
    f = _finite(np.abs(np.asarray(x, dtype=float)))
    return float(f.max()) if f.size else math.nan


def _smallest(x):
    f = _finite(x)
    return float(f.min()) if f.size else math.nan


def _root_mean_square(x):
    f = _finite(x)
    return float(np.sqrt(np.mean(f * f))) if f.size else math.nan


def expected_row(doc, res):
    """Every quantity of a batch row (docs/batch.md, *The quantities of a row*), computed
    from a single run's columns and summary by those definitions, written out here (not
    by the batch's helpers): {name: float or str}; None where this relation cannot
    compute it independently (the name must still be in the row)."""
    cols = res.columns
    col = lambda name: np.asarray(cols[name], dtype=float)  # noqa: E731
    out = {"full_cycle": bool(res.full_cycle)}
    if doc.get("flywheel"):  # not an aggregate of columns: the design of the run
        from kinetostatics.dynamics.flywheel import design

        # design() alone, as the batch row's: on its own frictionless nodes (the cycle's
        # stage would pass it the nodes with friction, 2e-11 of inertia_net apart on the
        # slotting machine at 12 positions)
        fw = design(res)
        out["flywheel.inertia"], out["flywheel.inertia_net"] = fw.inertia, fw.inertia_net
    # the strokes and the locked zones' edges: the cycle's stages (no flywheel: above)
    summary = res.summary(cycle_stage(res, flywheel=False, drive=False))
    ground = res.system.model.ground.name
    joints = doc["joints"]
    motion = {
        name: d for name, d in doc.get("drivers", {}).items() if isinstance(d.get("motion"), dict)
    }
    driven = {d["joint"] for d in doc.get("drivers", {}).values()}
    # output slides: undriven prismatic pairs on the frame; else the row's output link
    slides = [
        n
        for n, j in joints.items()
        if j.get("type") == "prismatic" and ground in j["links"] and n not in driven
    ]
    for name in slides:
        slider = next(link for link in joints[name]["links"] if link != ground)
        stroke = summary.get("outputs", {}).get(name, {})
        out[f"{name}.stroke"] = stroke.get("stroke", math.nan)
        out[f"{name}.time_ratio"] = stroke.get("time_ratio", math.nan)
        # a slider on the frame does not turn: every point moves along the axis
        out[f"{name}.v_peak"] = _largest_abs(np.hypot(col(f"{slider}.vx"), col(f"{slider}.vy")))
        out[f"{name}.a_peak"] = _largest_abs(np.hypot(col(f"{slider}.ax"), col(f"{slider}.ay")))
    if not slides:  # the last Assur group's last link
        link = res.system.plans[-1].group.links[-1]
        out[f"{link}.omega_peak"] = _largest_abs(col(f"{link}.omega"))
        out[f"{link}.alpha_peak"] = _largest_abs(col(f"{link}.alpha"))
    omega = lambda link: 0.0 if link == ground else col(f"{link}.omega")  # noqa: E731
    for name, d in motion.items():
        at = d.get("balance_at") or d["joint"]
        revolute = joints[at].get("type") == "revolute"
        key = f"{name}.{'torque' if revolute else 'force'}"
        for suffix in ("", "_friction_approx", "_friction"):
            if key + suffix in cols:
                out[f"{key}{suffix}_peak"] = _largest_abs(col(key + suffix))
                out[f"{key}{suffix}_rms"] = _root_mean_square(col(key + suffix))
        if key + "_friction" not in cols:
            continue
        out[f"{name}.efficiency_min"] = _smallest(col(f"{name}.efficiency"))
        if revolute:  # the relative angular speed of the effort's joint
            a, b = joints[at]["links"]
            rate = np.broadcast_to(omega(b) - omega(a), col(key).shape)
        elif at == d["joint"] and isinstance(d["motion"].get("speed"), (int, float, str)):
            rate = np.ones_like(col(key))  # its own slide at a constant speed
        else:
            out[f"{name}.efficiency_cycle"] = None
            continue
        tau, tau_f = col(key), col(key + "_friction")
        both = np.isfinite(tau) & np.isfinite(tau_f)
        w, w_f = np.sum((tau * rate)[both]), np.sum((tau_f * rate)[both])
        out[f"{name}.efficiency_cycle"] = w / w_f if w_f > 0 else math.nan
    if "friction.status" in cols:
        out["friction.self_locking_positions"] = float(np.sum(col("friction.status") == 2))
        text = lambda v: "…" if v is None else f"{v:.10g}"  # noqa: E731
        out["friction.self_locking"] = "; ".join(
            f"{text(z['from'])}–{text(z['to'])}" for z in summary.get("self_locking", [])
        )
    for name in joints:
        for suffix in ("", "_friction"):
            if f"{name}.Fx{suffix}" in cols:
                out[f"{name}.reaction_peak{suffix}"] = _largest_abs(
                    np.hypot(col(f"{name}.Fx{suffix}"), col(f"{name}.Fy{suffix}"))
                )
    for name in cols:
        if name.endswith(".pressure_angle"):
            out[name + "_max"] = _largest_abs(col(name))
        elif name.endswith(".transmission_angle"):
            mu = col(name)
            out[name + "_min"] = _smallest(np.minimum(mu, 180.0 - mu))
    if "shaking.Fx" in cols:
        force = np.hypot(col("shaking.Fx"), col("shaking.Fy"))
        out["shaking.force_peak"] = _largest_abs(force)
        out["shaking.force_rms"] = _root_mean_square(force)
        out["shaking.moment_peak"] = _largest_abs(col("shaking.M"))
        out["shaking.moment_rms"] = _root_mean_square(col("shaking.M"))
    return out


def _cell(text):
    if text in ("True", "False"):
        return text == "True"
    try:
        return float(text) if text != "" else math.nan
    except ValueError:
        return text


def batch_rows(doc, overrides, chunk, folder):
    """The rows of ``kinetostatics batch`` of ``doc`` (with :func:`with_factors`) over the
    variants ``overrides``, in chunks of ``chunk``, serial: [{name: value}]."""
    from kinetostatics.batch import Task, read_summary, run_batch

    path = folder / "mechanism.yaml"
    path.write_text(G.to_text(doc))
    out = folder / f"chunk{chunk}"
    tasks = [Task(str(k), 0, ov) for k, ov in enumerate(overrides)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        done = run_batch(str(path), tasks, out, executor="serial", chunk=chunk, progress=False)
    ALONE.append((chunk, done.alone))
    header, rows = read_summary(out / "summary.csv")
    params = header[1 : header.index("status")]
    return [
        {k: _cell(v) for k, v in row.items() if k not in params and k != "variant"}
        for row in sorted(rows, key=lambda r: int(r["variant"]))
    ]


def relation_batch_row(doc, seed, n=3, positions=12):
    """Each quantity of a batch row equals the same quantity computed from the single run
    of that variant (:func:`expected_row`): variants of the mechanism (masses and speed
    scaled, :func:`with_factors`), batched in one chunk (the vectorised analysis) and in
    chunks of one, against ``kinetostatics.analyze`` of each variant's file.  The row
    names exactly the quantities computed; a variant fails in the batch exactly when its
    single run fails, with the same reason.  Relative to each quantity's largest value
    over the variants, a dimensionless one's 1 at least (text and counts: equal)."""
    import tempfile
    from pathlib import Path

    rng = np.random.default_rng([seed, 37])
    base = with_factors(doc)
    base["analysis"] = {**base.get("analysis", {}), "positions": positions}
    base["analysis"].pop("at", None)
    base["analysis"]["events"] = False  # event rows: one by one (docs/batch.md)
    # one speed for all (variants that differ in speed are analysed one by one: the
    # vectorised analysis takes one schedule), the masses of each its own
    speed = round(float(rng.uniform(0.7, 1.4)), 6)  # written to the file exactly
    overrides = [{FACTORS[0]: 1.0, FACTORS[1]: speed}] + [
        {FACTORS[0]: round(float(rng.uniform(0.5, 2.0)), 6), FACTORS[1]: speed}
        for _ in range(n - 1)
    ]
    expected = []
    for ov in overrides:
        d = copy.deepcopy(base)
        d["parameters"].update(ov)
        try:
            res = analyze(d)
        except Exception as exc:  # noqa: BLE001 - the batch row must say the same
            expected.append(str(exc).splitlines()[0])
            continue
        expected.append(expected_row(d, res))
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        batches = {c: batch_rows(base, overrides, c, Path(tmp)) for c in (n, 1)}
    from kinetostatics.batch.variants import ROW_UNITS

    scale = {}
    for exp in expected:
        if isinstance(exp, dict):
            for k, v in exp.items():
                if isinstance(v, float) and math.isfinite(v):
                    # a dimensionless quantity on its unit's scale, 1 at least: a cycle
                    # efficiency of a cycle without net work is a quotient of round-off
                    unit = 1.0 if ROW_UNITS.get(k.rpartition(".")[2]) == "1" else 0.0
                    scale[k] = max(scale.get(k, unit), abs(v))
    for chunk, rows in batches.items():
        for v, (row, exp) in enumerate(zip(rows, expected, strict=True)):
            where = f"chunk {chunk}, variant {v}"
            if isinstance(exp, str):
                if row["status"] != "failed" or row["reason"] != exp:
                    WORST[:] = [math.inf, f"{where}: {row['status']} {row['reason']!r} != {exp!r}"]
                    return math.inf
                continue
            if row["status"] != "ok":
                WORST[:] = [math.inf, f"{where}: {row['status']} {row['reason']!r}"]
                return math.inf
            names = set(row) - {"status", "reason"}
            if names != set(exp):
                WORST[:] = [
                    math.inf,
                    f"{where}: row only {sorted(names - set(exp))}, "
                    f"single run only {sorted(set(exp) - names)}",
                ]
                return math.inf
            for k, want in exp.items():
                got = row[k]
                if want is None:
                    continue
                if isinstance(want, str) and isinstance(got, float) and math.isnan(got):
                    got = ""  # an empty cell
                if isinstance(want, (bool, str)) or isinstance(got, (bool, str)):
                    e = 0.0 if got == want else math.inf
                elif math.isnan(want) or math.isnan(got):
                    e = 0.0 if math.isnan(want) and math.isnan(got) else math.inf
                else:
                    e = abs(got - want) / (scale.get(k, 0.0) + 1e-300)
                if e > worst:
                    worst = e
                    WORST[:] = [e, f"{k} ({where}): batch {got!r}, single run {want!r}"]
    return worst


RELATIONS["batch_row"] = relation_batch_row
# the batch's rows are the single runs' to rounding (docs/batch.md: 5e-14 of each column)
TOLERANCE["batch_row"] = 1e-10


def _cam_links(doc):
    """The links that carry a cam (link i of a cam joint)."""
    return {j["links"][0] for j in doc["joints"].values() if j["type"] == "cam"}


def _check_cams(d, cams):
    """``transformed`` turns a cam's axes with the frame: a gear or rack on a cam's link
    would need its phase moved too, which it does not do."""
    for name, j in d["joints"].items():
        if j["type"] in ("gear", "rack") and cams & set(j["links"]):
            raise NotImplementedError(f"transformed: {name} meshes with a cam's link")


def _turn_cam(j, phi):
    """A cam's placement in the frame turned by ``phi`` with the frame."""
    if not phi:
        return
    tr, osc = j.get("translating"), j.get("oscillating")
    if tr is not None:
        tr["direction"] = _rot(tr["direction"], phi)
    if osc is not None:
        osc["pivot"] = _rot(osc["pivot"], phi)


def _turn_of(doc, joint, phi, cams):
    """How much θ_j − θ_i of a revolute's links grows when the mechanism is turned by
    ``phi``: a moving link's angle grows by phi, the ground's and a cam's (whose axes turn
    with the frame: ``transformed``) do not."""
    ground = doc.get("ground", "ground")
    li, lj = doc["joints"][joint]["links"][:2]
    turns = [0.0 if k == ground or k in cams else phi for k in (li, lj)]
    return turns[1] - turns[0]


def _move_rotational(el, sgn, delta):
    """A torsion spring carried through ``transformed``: s → sgn·s + delta, torque × sgn."""
    if "free_angle" in el:
        el["free_angle"] = sgn * el["free_angle"] + delta
    if "preload" in el:
        el["preload"] = sgn * el["preload"]
    if "table" in el:
        t = el["table"]
        rows = sorted(zip((sgn * a + delta for a in t["angle"]), (sgn * v for v in t["torque"])))
        t["angle"], t["torque"] = [a for a, _ in rows], [v for _, v in rows]


def _transform_features(d, phi, sgn, cams):
    """``transformed`` of the torsion springs and the effort drivers (angles between two
    links: mirrored, and turned where one of them is fixed)."""
    ground = d.get("ground", "ground")
    for el in d.get("elements", {}).values():
        if "joint" in el:  # s = θ_j − θ_i: mirrored, and turned where one link is fixed
            _move_rotational(el, sgn, _turn_of(d, el["joint"], phi, cams))
    for drv in d["drivers"].values():
        if "effort" in drv:  # its own angle, to a +x axis where link i is the ground
            li, lj = d["joints"][drv["joint"]]["links"][:2]
            delta = phi * ((lj != ground) - (li != ground))
            if isinstance(drv["effort"], dict):
                t = drv["effort"]["table"]
                rows = sorted(
                    zip((sgn * a + delta for a in t["at"]), (sgn * v for v in t["value"]))
                )
                t["at"], t["value"] = [a for a, _ in rows], [v for _, v in rows]
            else:
                drv["effort"] = sgn * drv["effort"]
