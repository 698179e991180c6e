#!/usr/bin/env python
"""Exact kinematics and kinetostatics of the slotting machine (docs/validation.md,
"The reference machines") at the 12 course-design positions and at the start/end
of cutting (1′, 8′), and the comparison with the values printed in the course-design report.

Every number comes from ``kinetostatics.analyze`` on
``mechanisms/slotting_machine.yaml``; quantities the library does not give
directly (Coriolis term, relative sliding, bar point coincident with A, ...)
are computed from its outputs with the short formulas of
``docs/validation.md`` (functions ``kinematics`` and ``forces`` below).

    python docs/scripts/slotting_validation.py            # print the tables
    python docs/scripts/slotting_validation.py --update   # rewrite them in docs/validation.md

The output is a sequence of Markdown blocks, each between
``<!-- BEGIN name -->`` and ``<!-- END name -->``; ``docs/validation.md``
holds the same blocks verbatim (checked by ``tests/docs/test_validation_doc.py``).
"""

from __future__ import annotations

import dataclasses
import re
import sys
from pathlib import Path

import numpy as np

import kinetostatics as ks

ROOT = Path(__file__).resolve().parents[2]
YAML = ROOT / "mechanisms" / "slotting_machine.yaml"
DOC = ROOT / "docs" / "validation.md"

REPORT_POSITIONS = ("7", "2")  # the only positions the report works


# ---------------------------------------------------------------- analysis


def course_positions() -> list[tuple[str, float]]:
    """(label, crank angle of O2→A in degrees, CCW from +x) of positions 1…12."""
    return [(str(k), float((300 - 30 * (k - 1)) % 360)) for k in range(1, 13)]


def run(model=None, friction: bool = True):
    """Analyse the 12 positions plus the exact cutting events (rows in time order).

    Returns ``(result, labels)``; ``labels[i]`` is "1"…"12", "1′" or "8′".
    """
    model = ks.load(YAML) if model is None else model
    angles = np.radians([a for _, a in course_positions()])
    r = ks.analyze(model, positions=angles, events=True, friction=friction)
    return r, row_labels(r)


def row_labels(r) -> list[str]:
    """Label each row by its course-design position or cutting event."""
    named = dict((round(a, 6), k) for k, a in course_positions())
    events = {
        round(float(np.degrees(e.coordinate)) % 360.0, 6): ("1′" if e.switch == "on" else "8′")
        for e in r.events
        if e.load == "cutting"
    }
    labels = []
    for a in r["angle"]:
        key = round(float(a) % 360.0, 6)
        labels.append(named.get(key) or events[key])
    return labels


def event_angles(r) -> dict[str, float]:
    """Crank angle (deg) of 1′ (cutting starts) and 8′ (cutting ends)."""
    return {
        ("1′" if e.switch == "on" else "8′"): float(np.degrees(e.coordinate)) % 360.0
        for e in r.events
        if e.load == "cutting"
    }


def _vec(r, name, kind=""):
    """Stack ``name.<kind>x``, ``name.<kind>y`` into (n, 2)."""
    return np.stack([r[f"{name}.{kind}x"], r[f"{name}.{kind}y"]], axis=-1)


def _dot(a, b):
    return np.sum(a * b, axis=-1)


def _norm(a):
    return np.hypot(a[..., 0], a[..., 1])


def kinematics(r, labels) -> dict[str, np.ndarray]:
    """Velocities and accelerations of the course design, from library outputs.

    e = unit vector O3→A, t = e turned +90° (CCW); L = |O3A|.
    ṙ = V_A2·e = dL/dt (the block's sliding speed along the bar, + away from O3);
    V_A3A2 = V_A3 − V_A2 = −ṙ e;  V_A3 = ω3 L t;  a^k_A3A2 = 2ω3 k×V_A3A2 = −2ω3ṙ t;
    a^t_A3 = α3 L t;  a^n_A3 = −ω3² L e;  a^r_A3A2 = −r̈ e with r̈ = a_A2·e + ω3² L.
    Ram values (s_C, V_C, a_C) are positive downward, as in the report.
    """
    A = _vec(r, "crank.A") - _vec(r, "bar.O3")
    L = _norm(A)
    e = A / L[:, None]
    t = np.stack([-e[:, 1], e[:, 0]], axis=-1)
    vA2, aA2 = _vec(r, "crank.A", "v"), _vec(r, "crank.A", "a")
    w3, al3 = r["bar.omega"], r["bar.alpha"]
    w4, al4 = r["rod.omega"], r["rod.alpha"]
    CB = _vec(r, "rod.C") - _vec(r, "rod.B")
    L_BC = _norm(CB)
    rdot = _dot(vA2, e)
    top = labels.index("1")  # position 1: ram at its top
    k = {}
    k["phi"] = r["angle"]
    k["s_C"] = (r["ram.C.y"][top] - r["ram.C.y"]) * 1e3  # mm below the top
    k["L_O3A"] = L * 1e3  # mm
    k["V_A2"] = _norm(vA2)
    k["V_A3"] = np.abs(w3) * L
    k["rdot"] = rdot
    k["V_A3A2"] = np.abs(rdot)
    k["omega3"] = w3
    k["omega3_abs"] = np.abs(w3)
    k["V_S3"] = _norm(_vec(r, "bar.S3", "v"))
    k["V_B"] = _norm(_vec(r, "bar.B", "v"))
    k["V_CB"] = _norm(_vec(r, "rod.C", "v") - _vec(r, "rod.B", "v"))
    k["omega4"] = w4
    k["V_C"] = -r["ram.C.vy"]
    k["a_A2"] = _norm(aA2)
    k["a_A2t"] = _dot(aA2, t)
    k["a_k_t"] = -2.0 * w3 * rdot
    k["a_k"] = np.abs(k["a_k_t"])
    k["a_n_A3"] = w3**2 * L
    k["a_t_A3_t"] = al3 * L
    k["a_t_A3"] = np.abs(al3) * L
    k["rddot"] = _dot(aA2, e) + w3**2 * L
    k["a_r"] = np.abs(k["rddot"])
    k["a_A3"] = L * np.hypot(w3**2, al3)
    k["alpha3"] = al3
    k["a_S3"] = _norm(_vec(r, "bar.S3", "a"))
    k["a_B"] = _norm(_vec(r, "bar.B", "a"))
    k["a_n_CB"] = w4**2 * L_BC
    k["a_t_CB"] = np.abs(al4) * L_BC
    k["alpha4"] = al4
    k["a_C"] = -r["ram.C.ay"]
    return k


def forces(r, model) -> dict[str, np.ndarray]:
    """Loads and reactions.  Library names: O2 [frame, crank] = F61, A [crank, block] = F12,
    slot [bar, block] = F32, O3 [frame, bar] = F63, B [bar, rod] = F34, C [rod, ram] = F45,
    guide [frame, ram] = F65 (normal force and couple about C), motor.torque = M_b.
    F23 = −F32 (block on bar); crank, block and rod are massless, so
    F61 = F12 = F23 = −F21 and F34 = F45 = −F54 (as forces)."""
    m3, m5 = model.link("bar").mass, model.link("ram").mass
    J3 = model.link("bar").inertia
    g = float(-model.gravity[1])
    f = {}
    # ram: vertical equilibrium gives the cutting force actually applied
    f["Q"] = m5 * (g + r["ram.ay"]) - r["C.Fy"] - r["guide.Fy"]
    f["F_I5"] = m5 * r["ram.ay"]  # d'Alembert −m5·a_C, positive downward
    f["F45x"], f["F45y"] = r["C.Fx"], r["C.Fy"]
    f["F45"] = np.hypot(r["C.Fx"], r["C.Fy"])
    f["F65x"], f["M65"] = r["guide.Fx"], r["guide.M"]
    f["F_I3x"], f["F_I3y"] = -m3 * r["bar.ax"], -m3 * r["bar.ay"]
    f["F_I3"] = m3 * np.hypot(r["bar.ax"], r["bar.ay"])
    f["M_I3"] = -J3 * r["bar.alpha"]
    f["F23x"], f["F23y"] = -r["slot.Fx"], -r["slot.Fy"]
    f["F23"] = np.abs(r["slot.N"])
    f["F63x"], f["F63y"] = r["O3.Fx"], r["O3.Fy"]
    f["F63"] = np.hypot(r["O3.Fx"], r["O3.Fy"])
    f["F61"] = np.hypot(r["O2.Fx"], r["O2.Fy"])
    f["M_b"] = r["motor.torque"]
    return f


# ------------------------------------------------------------- formatting


def _fmt(x, nd):
    if x is None or (isinstance(x, float) and np.isnan(x)):
        return ""
    if isinstance(x, str):
        return x
    return f"{round(float(x), nd) + 0.0:.{nd}f}"


def table(header: list[str], rows: list[list], left: tuple[int, ...] = (0,)) -> str:
    """A Markdown table; columns in ``left`` are left-aligned, the others right-aligned."""
    n = len(header)
    align = [":---" if c in left or c - n in left else "---:" for c in range(n)]
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join(rows_i) + " |" for rows_i in rows]
    return "\n".join(out)


def _columns(labels, columns) -> str:
    """columns: list of (header, values, decimals)."""
    header = ["pos"] + [h for h, _, _ in columns]
    rows = [[lab] + [_fmt(v[i], nd) for _, v, nd in columns] for i, lab in enumerate(labels)]
    return table(header, rows)


# ------------------------------------------------------ report reproduction

# Values printed in the report (docs/report_values.md §4, §5), position → symbol → value.
REPORT = {
    "7": {
        "L_O3A": 198.42,
        "V_A2": 0.47,
        "V_A3A2": 0.31,
        "V_A3": 0.36,
        "V_B": 0.18,
        "V_CB": 0.06,
        "V_C": 0.17,
        "V_S3": 0.22,
        "omega3_abs": 1.80,
        "a_A2": 2.96,
        "a_k": 1.11,
        "a_r": 1.60,
        "a_n_A3": 0.64,
        "a_t_A3": 3.05,
        "a_A3": 3.11,
        "a_B": 1.57,
        "a_n_CB": 0.03,
        "a_t_CB": 0.20,
        "a_C": -1.52,
        "a_S3": 1.96,
    },
    "2": {
        "L_O3A": 167.72,
        "V_A2": 0.47,
        "V_A3A2": 0.42,
        "V_A3": 0.21,
        "V_B": 0.13,
        "V_CB": 0.06,
        "V_C": 0.09,
        "V_S3": 0.16,
        "omega3_abs": 1.26,
        "a_A2": 2.96,
        "a_k": 1.06,
        "a_r": 1.06,
        "a_n_A3": 0.26,
        "a_t_A3": 1.59,
        "a_A3": 1.61,
        "a_B": 0.96,
        "a_n_CB": 0.04,
        "a_t_CB": 0.28,
        "a_C": 0.94,
        "a_S3": 1.20,
    },
}
REPORT_FORCES_7 = {
    "F_I5": -48.62,
    "F45": 728.67,
    "F45x": 8.66,
    "F65x": 8.66,
    "F_I3": 31.37,
    "M_I3": 0.27,
    "L1": 94.09,
    "L2": 91.88,
    "L3": 198.42,
    "F23": 419.63,
    "F63": 955.98,
    "F61": 419.63,
    "M_b": -23.79,
}
G3, G5, Q = 160.0, 320.0, 1000.0  # N (design data)

KIN_ROWS = [  # (key, symbol, unit, decimals)
    ("L_O3A", "L_O3A", "mm", 3),
    ("V_A2", "V_A2", "m/s", 4),
    ("V_A3A2", "V_A3A2", "m/s", 4),
    ("V_A3", "V_A3", "m/s", 4),
    ("V_B", "V_B", "m/s", 4),
    ("V_CB", "V_CB", "m/s", 4),
    ("V_C", "V_C (↓+)", "m/s", 4),
    ("V_S3", "V_S3", "m/s", 4),
    ("omega3_abs", "\\|ω3\\|", "rad/s", 4),
    ("a_A2", "a_A2", "m/s²", 4),
    ("a_k", "a^k_A3A2", "m/s²", 4),
    ("a_r", "a^r_A3A2", "m/s²", 4),
    ("a_n_A3", "a^n_A3", "m/s²", 4),
    ("a_t_A3", "a^t_A3", "m/s²", 4),
    ("a_A3", "a_A3", "m/s²", 4),
    ("a_B", "a_B", "m/s²", 4),
    ("a_n_CB", "a^n_CB", "m/s²", 4),
    ("a_t_CB", "a^t_CB", "m/s²", 4),
    ("a_C", "a_C (↓+)", "m/s²", 4),
    ("a_S3", "a_S3", "m/s²", 4),
]


def reversed_coriolis(r, k, i) -> dict[str, float]:
    """Row i redone as the report did at position 7: the Coriolis term added to the
    tangential component of a_A2 instead of subtracted (exact velocities otherwise)."""
    A = np.array([r["crank.A.x"][i], r["crank.A.y"][i]]) - np.array(
        [r["bar.O3.x"][i], r["bar.O3.y"][i]]
    )
    L = float(np.hypot(*A))
    e = A / L
    w3, w4 = r["bar.omega"][i], r["rod.omega"][i]
    at = k["a_A2t"][i] - k["a_k_t"][i]  # wrong sense of a^k
    al3 = at / L
    an = w3**2 * L
    aA3 = float(np.hypot(at, an))

    def bar_acc(p):  # acceleration of a bar point at p (from O3)
        return al3 * np.array([-p[1], p[0]]) - w3**2 * p

    rB = np.array([r["bar.B.x"][i], r["bar.B.y"][i]])
    rS = np.array([r["bar.S3.x"][i], r["bar.S3.y"][i]])
    aB = bar_acc(rB)
    CB = np.array([r["rod.C.x"][i] - r["rod.B.x"][i], r["rod.C.y"][i] - r["rod.B.y"][i]])
    # a_C = a_B + α4 k×CB − ω4² CB with a_C horizontal component 0 (vertical guide)
    al4 = (aB[0] - w4**2 * CB[0]) / CB[1]
    aC = aB[1] + al4 * CB[0] - w4**2 * CB[1]
    return {
        "a_t_A3": abs(at),
        "alpha3": al3,
        "a_A3": aA3,
        "a_B": float(np.hypot(*aB)),
        "a_t_CB": abs(al4) * float(np.hypot(*CB)),
        "a_C": -aC,
        "a_S3": float(np.hypot(*bar_acc(rS))),
        "a_S3_vec": bar_acc(rS),
        "e": e,
    }


def report_force_redo(r, k, f, i, model) -> dict[str, float]:
    """Position-7 kinetostatics redone with the report's own errors (see validation.md)."""
    m3, m5 = model.link("bar").mass, model.link("ram").mass
    J3 = model.link("bar").inertia
    w = reversed_coriolis(r, k, i)
    th4 = np.arctan2(r["rod.C.y"][i] - r["rod.B.y"][i], r["rod.C.x"][i] - r["rod.B.x"][i])
    out = {}
    out["F_I5"] = m5 * w["a_C"]  # +m·a (report), ↓+
    f45y = Q - G5 + m5 * (-w["a_C"])  # its vertical equation
    out["F45"] = f45y / abs(np.sin(th4))
    out["F45x"] = f45y * abs(np.cos(th4) / np.sin(th4))
    out["F65x"] = out["F45x"]
    out["F_I3"] = m3 * w["a_S3"]
    out["M_I3"] = w["a_S3"] * J3  # "M3 = a_s3·Js3"
    rep = REPORT_FORCES_7
    # its moment equation about O3 without M3 and without the moment of F3
    out["F23"] = (rep["F45"] * rep["L1"] + G3 * rep["L2"]) / rep["L3"]
    out["F61"] = out["F23"]
    A = np.array([r["crank.A.x"][i], r["crank.A.y"][i]])
    O2 = np.array([r["crank.O2.x"][i], r["crank.O2.y"][i]])
    lever = abs(float((A - O2) @ w["e"]))  # F21 is ⊥ bar at A
    out["M_b"] = -rep["F23"] * lever
    out["lever_Mb"] = lever * 1e3
    # correct-sign ram inertia with the report's a_C, and the exact-a_C reference
    out["F45_report_aC_right_sign"] = (Q - G5 - m5 * (-w["a_C"])) / abs(np.sin(th4))
    out["alpha3"] = w["alpha3"]
    out["M_I3_alpha"] = abs(w["alpha3"]) * J3
    out["a_S3_vec"] = w["a_S3_vec"]
    return out


def force_polygon_variants(r, i, a_S3_vec, m3) -> dict[str, float]:
    """|F63| from F54 + F23 + G3 + F3 + F63 = 0 with the report's printed F54 and F23
    (F23 ⊥ bar, sense from the moment equation), for three readings of F3."""
    rep = REPORT_FORCES_7
    F54 = np.array([-rep["F45x"], np.sqrt(rep["F45"] ** 2 - rep["F45x"] ** 2)])
    A = np.array([r["crank.A.x"][i], r["crank.A.y"][i]]) - np.array(
        [r["bar.O3.x"][i], r["bar.O3.y"][i]]
    )
    e = A / np.hypot(*A)
    n = np.array([-e[1], e[0]])
    rB = np.array([r["bar.B.x"][i], r["bar.B.y"][i]])
    rS = np.array([r["bar.S3.x"][i], r["bar.S3.y"][i]])
    Gv = np.array([0.0, -G3])

    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    sense = -np.sign(cross(rB, F54) + cross(rS, Gv)) * np.sign(cross(A, n))
    F23 = rep["F23"] * sense * n
    out = {}
    for name, F3 in (
        ("F3 = −m3·a_s3", -m3 * a_S3_vec),
        ("F3 = +m3·a_s3", m3 * a_S3_vec),
        ("F3 omitted", np.zeros(2)),
    ):
        out[name] = float(np.hypot(*(F54 + F23 + Gv + F3)))
    return out


# ------------------------------------------------------------------ blocks


def blocks() -> dict[str, str]:
    """All generated Markdown blocks, name → text."""
    model = ks.load(YAML)
    r, labels = run(model)
    k = kinematics(r, labels)
    f = forces(r, model)
    b = {}
    ev = event_angles(r)
    b["events"] = table(
        ["event", "crank angle φ (°)", "ram below its top (mm)", "ram velocity V_C (↓+, m/s)"],
        [
            [
                lab,
                _fmt(ev[lab], 4),
                _fmt(k["s_C"][labels.index(lab)], 4),
                _fmt(k["V_C"][labels.index(lab)], 4),
            ]
            for lab in ("1′", "8′")
        ],
    )
    b["velocities"] = _columns(
        labels,
        [
            ("φ (°)", k["phi"], 3),
            ("s_C ↓ (mm)", k["s_C"], 3),
            ("L_O3A (mm)", k["L_O3A"], 3),
            ("V_A2", k["V_A2"], 4),
            ("V_A3", k["V_A3"], 4),
            ("ṙ", k["rdot"], 4),
            ("ω3 (rad/s)", k["omega3"], 4),
            ("V_S3", k["V_S3"], 4),
            ("V_B", k["V_B"], 4),
            ("V_CB", k["V_CB"], 4),
            ("ω4 (rad/s)", k["omega4"], 4),
            ("V_C ↓", k["V_C"], 4),
        ],
    )
    b["accelerations_bar"] = _columns(
        labels,
        [
            ("a_A2", k["a_A2"], 4),
            ("a_A2·t", k["a_A2t"], 4),
            ("a^k·t = −2ω3ṙ", k["a_k_t"], 4),
            ("a^t·t = α3·L", k["a_t_A3_t"], 4),
            ("a^n_A3 = ω3²L", k["a_n_A3"], 4),
            ("r̈ (a^r = −r̈e)", k["rddot"], 4),
            ("a_A3", k["a_A3"], 4),
            ("α3 (rad/s²)", k["alpha3"], 4),
            ("a_S3", k["a_S3"], 4),
        ],
    )
    b["accelerations_ram"] = _columns(
        labels,
        [
            ("a_B", k["a_B"], 4),
            ("a^n_CB", k["a_n_CB"], 4),
            ("a^t_CB", k["a_t_CB"], 4),
            ("α4 (rad/s²)", k["alpha4"], 4),
            ("a_C ↓", k["a_C"], 4),
        ],
    )
    b["forces_ram"] = _columns(
        labels,
        [
            ("Q (N)", f["Q"], 2),
            ("F_I5 ↓ (N)", f["F_I5"], 2),
            ("F45x", f["F45x"], 2),
            ("F45y", f["F45y"], 2),
            ("\\|F45\\|", f["F45"], 2),
            ("F65x", f["F65x"], 2),
            ("M65 (N·m)", f["M65"], 2),
        ],
    )
    b["forces_bar"] = _columns(
        labels,
        [
            ("F_I3x", f["F_I3x"], 2),
            ("F_I3y", f["F_I3y"], 2),
            ("M_I3 (N·m)", f["M_I3"], 3),
            ("F23x", f["F23x"], 2),
            ("F23y", f["F23y"], 2),
            ("\\|F23\\|", f["F23"], 2),
            ("F63x", f["F63x"], 2),
            ("F63y", f["F63y"], 2),
            ("\\|F63\\|", f["F63"], 2),
            ("M_b (N·m)", f["M_b"], 3),
        ],
    )
    rev = ("O2", "A", "O3", "B", "C")
    b["friction_loads"] = _columns(
        labels,
        [
            *[(f"{j} approx", r[f"{j}.friction_approx"], 3) for j in rev],
            ("slot approx", r["slot.friction_approx"], 2),
            ("guide approx", r["guide.friction_approx"], 2),
            *[(f"{j} cons.", r[f"{j}.friction"], 3) for j in rev],
            ("slot cons.", r["slot.friction"], 2),
            ("guide cons.", r["guide.friction"], 2),
        ],
    )
    b["friction_reactions"] = _columns(
        labels,
        [
            ("\\|F61\\|", np.hypot(r["O2.Fx_friction"], r["O2.Fy_friction"]), 2),
            ("\\|F12\\|", np.hypot(r["A.Fx_friction"], r["A.Fy_friction"]), 2),
            ("N32", r["slot.N_friction"], 2),
            ("M32 (N·m)", r["slot.M_friction"], 3),
            ("\\|F32\\|", np.hypot(r["slot.Fx_friction"], r["slot.Fy_friction"]), 2),
            ("\\|F63\\|", np.hypot(r["O3.Fx_friction"], r["O3.Fy_friction"]), 2),
            ("\\|F34\\|", np.hypot(r["B.Fx_friction"], r["B.Fy_friction"]), 2),
            ("\\|F45\\|", np.hypot(r["C.Fx_friction"], r["C.Fy_friction"]), 2),
            ("N65", r["guide.N_friction"], 2),
            ("M65 (N·m)", r["guide.M_friction"], 2),
        ],
    )
    status = np.array([int(s) for s in r["friction.status"]])
    b["balancing_moment"] = _columns(
        labels,
        [
            ("φ (°)", k["phi"], 3),
            ("M_b no friction", r["motor.torque"], 3),
            ("M_b approx", r["motor.torque_friction_approx"], 3),
            ("M_b consistent", r["motor.torque_friction"], 3),
            ("approx − cons.", r["motor.torque_friction_approx"] - r["motor.torque_friction"], 4),
            ("η = M_b/M_b,f", r["motor.efficiency"], 4),
            ("status", [str(s) for s in status], 0),
        ],
    )
    # one-sided values at the events: the cutting force switched off
    idx = [labels.index(lab) for lab in ("1′", "8′")]
    r0 = ks.analyze(
        dataclasses.replace(model, loads=()), positions=np.radians([ev["1′"], ev["8′"]])
    )
    b["events_one_sided"] = table(
        [
            "event",
            "M_b with Q",
            "M_b without Q",
            "M_b approx with Q",
            "M_b approx without Q",
            "M_b cons. with Q",
            "M_b cons. without Q",
        ],
        [
            [
                lab,
                _fmt(r["motor.torque"][i], 3),
                _fmt(r0["motor.torque"][n], 3),
                _fmt(r["motor.torque_friction_approx"][i], 3),
                _fmt(r0["motor.torque_friction_approx"][n], 3),
                _fmt(r["motor.torque_friction"][i], 3),
                _fmt(r0["motor.torque_friction"][n], 3),
            ]
            for n, (lab, i) in enumerate(zip(("1′", "8′"), idx))
        ],
    )
    # comparison with the report
    for pos in REPORT_POSITIONS:
        i = labels.index(pos)
        redo = reversed_coriolis(r, k, i) if pos == "7" else {}
        rows = []
        for key, sym, unit, nd in KIN_ROWS:
            rep = REPORT[pos][key]
            ex = float(k[key][i])
            rows.append(
                [
                    sym,
                    unit,
                    _fmt(rep, 2),
                    _fmt(ex, nd),
                    _fmt(rep - ex, nd),
                    _fmt(redo.get(key), 4) if key in redo else "",
                    _note(pos, key, rep, ex),
                ]
            )
        header = ["quantity", "unit", "report", "exact", "report − exact"]
        if pos == "7":
            header.append("report's construction redone (a^k reversed)")
        else:
            rows = [row[:5] + row[6:] for row in rows]
        header.append("explanation")
        b[f"compare_kinematics_{pos}"] = table(header, rows, left=(0, -1))
    i = labels.index("7")
    redo = report_force_redo(r, k, f, i, model)
    exact = {
        "F_I5": f["F_I5"][i],
        "F45": f["F45"][i],
        "F45x": f["F45x"][i],
        "F65x": abs(f["F65x"][i]),
        "F_I3": f["F_I3"][i],
        "M_I3": abs(f["M_I3"][i]),
        "L1": _lever_F54(r, i),
        "L2": abs(r["bar.S3.x"][i] - r["bar.O3.x"][i]) * 1e3,
        "L3": k["L_O3A"][i],
        "F23": f["F23"][i],
        "F63": f["F63"][i],
        "F61": f["F61"][i],
        "M_b": f["M_b"][i],
    }
    rows = []
    for key, (sym, unit, nd) in FORCE_ROWS.items():
        rep = REPORT_FORCES_7[key]
        rows.append(
            [
                sym,
                unit,
                _fmt(rep, 2),
                _fmt(exact[key], nd),
                _fmt(rep - exact[key], nd),
                _fmt(redo.get(key), 2),
                FORCE_NOTES[key],
            ]
        )
    b["compare_forces_7"] = table(
        [
            "quantity",
            "unit",
            "report",
            "exact (no friction)",
            "report − exact",
            "redone with the report's errors",
            "explanation",
        ],
        rows,
        left=(0, -1),
    )
    poly = force_polygon_variants(r, i, redo["a_S3_vec"], model.link("bar").mass)
    b["report_checks_7"] = table(
        ["check at position 7", "value"],
        [
            [
                "F45 with the report's a_C but the correct inertia sign (N)",
                _fmt(redo["F45_report_aC_right_sign"], 2),
            ],
            ["α3 implied by the report's a^t_A3 (rad/s²)", _fmt(abs(redo["alpha3"]), 3)],
            ["M_I3 = Js3·α3 with that α3 (N·m)", _fmt(redo["M_I3_alpha"], 3)],
            ["exact \\|M_I3\\| = Js3·\\|α3\\| (N·m)", _fmt(abs(f["M_I3"][i]), 3)],
            ["F23 = (F54·L1 + G3·L2)/L3 from the printed numbers (N)", _fmt(redo["F23"], 2)],
            [
                "F23 with + M3 = 0.27 N·m in the same equation (N)",
                _fmt(
                    (
                        REPORT_FORCES_7["F45"] * REPORT_FORCES_7["L1"]
                        + G3 * REPORT_FORCES_7["L2"]
                        + 1e3 * REPORT_FORCES_7["M_I3"]
                    )
                    / REPORT_FORCES_7["L3"],
                    2,
                ),
            ],
            [
                "F23 with − M3 = 0.27 N·m in the same equation (N)",
                _fmt(
                    (
                        REPORT_FORCES_7["F45"] * REPORT_FORCES_7["L1"]
                        + G3 * REPORT_FORCES_7["L2"]
                        - 1e3 * REPORT_FORCES_7["M_I3"]
                    )
                    / REPORT_FORCES_7["L3"],
                    2,
                ),
            ],
            *[
                [f"\\|F63\\| from the report's F54, F23, G3 and {name} (N)", _fmt(v, 2)]
                for name, v in poly.items()
            ],
            ["lever of F21 about O2, (A − O2)·e (mm)", _fmt(redo["lever_Mb"], 3)],
            ["M_b = −F23·lever with the report's F23 (N·m)", _fmt(redo["M_b"], 3)],
            [
                "M_b = −F23·lever with the exact F23 (N·m)",
                _fmt(-f["F23"][i] * redo["lever_Mb"] / 1e3, 3),
            ],
        ],
    )
    return b


def _lever_F54(r, i) -> float:
    """Distance (mm) from O3 to the rod's line BC (the line of F54)."""
    B = np.array([r["rod.B.x"][i] - r["bar.O3.x"][i], r["rod.B.y"][i] - r["bar.O3.y"][i]])
    u = np.array([r["rod.C.x"][i] - r["rod.B.x"][i], r["rod.C.y"][i] - r["rod.B.y"][i]])
    u = u / np.hypot(*u)
    return abs(B[0] * u[1] - B[1] * u[0]) * 1e3


FORCE_ROWS = {  # key: (symbol, unit, decimals)
    "F_I5": ('F_I5 (report "F5", ↓+)', "N", 2),
    "F45": ("\\|F45\\|", "N", 2),
    "F45x": ("F45x", "N", 2),
    "F65x": ("\\|F65x\\|", "N", 2),
    "F_I3": ('\\|F_I3\\| (report "F3")', "N", 2),
    "M_I3": ('\\|M_I3\\| (report "M3")', "N·m", 3),
    "L1": ("L1 (lever of F54 about O3)", "mm", 3),
    "L2": ("L2 (lever of G3 about O3)", "mm", 3),
    "L3": ("L3 (lever of F23 about O3)", "mm", 3),
    "F23": ("\\|F23\\|", "N", 2),
    "F63": ("\\|F63\\|", "N", 2),
    "F61": ("\\|F61\\| = \\|F21\\|", "N", 2),
    "M_b": ("M_b (CCW +)", "N·m", 3),
}
FORCE_NOTES = {
    "F_I5": "(K) a_C wrong, and (I) +m·a used instead of −m·a",
    "F45": "(K) + (I)",
    "F45x": "follows \\|F45\\| (rod at 90.68°); sign as ours",
    "F65x": "follows F45; sign slip: its F65x = −F45x is −8.66 (exact F65x = −7.91); "
    "the couple M65 = −Q·d = −120 N·m is missing",
    "F_I3": "(K): m3 × wrong a_s3",
    "M_I3": "(M) a_s3·Js3 is not a moment; Js3·α3 is",
    "L1": "measured; matches",
    "L2": "(L) wrong: S3 is 125 mm from O3 along the bar",
    "L3": "measured; matches (= L_O3A)",
    "F23": "(K) + (I) + (F) M3 and the moment of F3 omitted",
    "F63": "(K) + (I) + (F); not reproducible (see checks)",
    "F61": "= F23 (massless block and crank)",
    "M_b": "= −F23·56.695 mm: consistent with its F23",
}


def _note(pos, key, rep, ex) -> str:
    """Short explanation of a kinematic difference (see validation.md for the letters)."""
    if pos == "7" and key in ("a_t_A3", "a_A3", "a_B", "a_t_CB", "a_C", "a_S3"):
        return "(K) Coriolis term in the wrong sense" if key == "a_t_A3" else "(K) follows a^t_A3"
    if pos == "2" and key == "V_C":
        return "(V) wrong: contradicts its own V_B, V_CB"
    if pos == "2" and key == "a_n_CB":
        return "0.06²/0.1 = 0.036 from the rounded V_CB"
    if key == "L_O3A":
        return "measured on the drawing"
    if abs(rep - ex) <= 0.005 + 1e-12:
        return "rounding"
    return "graphical accuracy"


# -------------------------------------------------------------------- main

BLOCK_RE = re.compile(r"<!-- BEGIN (\S+) -->\n(.*?)\n?<!-- END \1 -->", re.S)


def render(bl: dict[str, str]) -> str:
    return "\n\n".join(
        f"<!-- BEGIN {name} -->\n{text}\n<!-- END {name} -->" for name, text in bl.items()
    )


def doc_blocks(text: str) -> dict[str, str]:
    return {m.group(1): m.group(2) for m in BLOCK_RE.finditer(text)}


def update_doc(path: Path = DOC) -> None:
    """Replace every generated block of ``path`` by the current output."""
    bl = blocks()
    text = path.read_text(encoding="utf-8")
    missing = set(bl) - set(doc_blocks(text))
    if missing:
        raise SystemExit(f"{path}: no place for block(s) {sorted(missing)}")
    text = BLOCK_RE.sub(
        lambda m: f"<!-- BEGIN {m.group(1)} -->\n{bl[m.group(1)]}\n<!-- END {m.group(1)} -->", text
    )
    path.write_text(text, encoding="utf-8")


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv == ["--update"]:
        update_doc()
        return 0
    if argv:
        print("usage: slotting_validation.py [--update]", file=sys.stderr)
        return 2
    print(render(blocks()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
