"""Relations the graded methods obey on the shipped motion-driven files (issue 38), with
the verification net's transformations (tests/net/relations.py):

- **frame rotation**: the whole mechanism and gravity turned by φ (and shifted) turn every
  vector of methods.json by φ — the force polygons' vertices, the vector equations' terms,
  the instant centres (shifted too; a centre at infinity's direction turned) — and leave
  the balancing moment by the lever, the power method and the solution unchanged;
- **unit change**: the file written in mm/deg/rpm instead of m/rad/(rad/s) gives the same
  methods.json numbers (in SI: each scales by its unit, here 1);
- **subset**: the methods at one position, from an analysis of that position alone, are
  the full run's entry at that position.

Each number is compared on the scale of its kind (the largest force of its group, the
largest velocity or acceleration term of the run, the largest |M_b|), a centre on the
mechanism's size L times (D/L)² at its distance D (two of Kennedy's lines meeting far
away meet at a small angle: the centre's error grows so), to 1e-6 (1e-9 the rest).  The
default run takes two files; every motion-driven shipped file is the ``slow`` run."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from kinetostatics.methods.stage import methods_stage
from tests.helpers import ROOT, motion_driven
from tests.net import generate as G
from tests.net.relations import analyze, grid, shipped, transformed

TOL = 1e-9
TOL_CENTRES = 1e-6  # on the conditioned scale of _centres
N = 6  # positions per run
PARTS = ["balancing_moment", "force_polygons", "instant_centres", "vector_equations"]
FAST = ["slotting_machine", "geared_fivebar"]
FILES = [pytest.param(s, marks=() if s in FAST else pytest.mark.slow) for s in motion_driven()]


def _rot(v, phi):
    c, s = math.cos(phi), math.sin(phi)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _methods(doc, n=N, positions=None):
    """methods.json's entries at ``positions`` (SI driver coordinates), or at the file's
    own ``n`` positions (its start and sweep, in its units)."""
    if positions is None:
        doc = copy.deepcopy(doc)
        doc["analysis"]["positions"] = n
        result = analyze(doc)
    else:
        result = analyze(doc, positions=positions)
    rows = [(str(k + 1), k) for k in range(len(result.t))]
    return methods_stage(result, rows, parts=PARTS), result


def _size(result) -> float:
    return float(np.max(result.system.l_ref))


def _same_moments(a, b) -> float:
    if "balancing_moment" not in a:
        return 0.0
    pa, pb = a["balancing_moment"]["positions"], b["balancing_moment"]["positions"]
    values = [(x["M_b"][k], y["M_b"][k]) for x, y in zip(pa, pb, strict=True) for k in x["M_b"]]
    scale = max((abs(u) for u, _ in values if u is not None), default=0.0) or 1.0
    return max((abs(u - v) / scale for u, v in values if u is not None), default=0.0)


def _vectors(a, b, turn) -> float:
    """The largest difference of the polygons' vertices and the equations' terms, b against
    a turned, each on the scale of its group or equation."""
    worst = 0.0
    for pa, pb in zip(a.get("force_polygons", {}).get("positions", []),
                      b.get("force_polygons", {}).get("positions", []), strict=True):  # fmt: skip
        for ga, gb in zip(pa["groups"], pb["groups"], strict=True):
            assert ga["group"] == gb["group"]
            scale = ga["largest"] or 1.0
            # force by force (the chain leaves out a force of zero vector, which round-off
            # may make 1e-15 N in one frame and 0 in the other)
            fa = {f["name"]: f["vector"] for f in ga["forces"]}
            fb = {f["name"]: f["vector"] for f in gb["forces"]}
            assert fa.keys() == fb.keys()
            for name, va in fa.items():
                worst = max(worst, float(np.hypot(*(turn(va) - np.array(fb[name])))) / scale)
    # a term on the scale of the largest of its kind in the run (at a limit position, or
    # on a dwell, an equation's own terms are all round-off)
    scale = {}
    for ea in a["vector_equations"].values():
        for q in (q for g in ea["groups"] for q in g["equations"]):
            top = max(t["value"] for t in q["lhs"] + q["rhs"])
            scale[q["kind"]] = max(scale.get(q["kind"], 0.0), top)
    for label, ea in a["vector_equations"].items():
        eb = b["vector_equations"][label]
        for ga, gb in zip(ea["groups"], eb["groups"], strict=True):
            for qa, qb in zip(ga["equations"], gb["equations"], strict=True):
                assert qa["text"] == qb["text"]
                terms = list(zip(qa["lhs"] + qa["rhs"], qb["lhs"] + qb["rhs"], strict=True))
                for ta, tb in terms:
                    d = turn(ta["vector"]) - np.array(tb["vector"])
                    worst = max(worst, float(np.hypot(*d)) / (scale[qa["kind"]] or 1.0))
    return worst


def _centres(a, b, place, turn, size) -> float:
    worst = 0.0
    for label, ca in a["instant_centres"].items():
        cb = b["instant_centres"][label]
        assert ca["found"] == cb["found"]
        for x, y in zip(ca["centres"], cb["centres"], strict=True):
            assert x["bodies"] == y["bodies"] and x["how"] == y["how"]
            if x["xy"] is None:
                continue
            if x["at_infinity"]:  # a direction, up to its sign
                d = turn(x["xy"])
                worst = max(worst, min(np.hypot(*(d - y["xy"])), np.hypot(*(d + y["xy"]))))
            else:  # Kennedy's lines meet at distance D at an angle ~ size/D: error ~ D²/size
                far = max(1.0, float(np.hypot(*x["xy"])) / size) ** 2
                d = float(np.hypot(*(place(x["xy"]) - np.array(y["xy"]))))
                worst = max(worst, d / (size * far))
    return worst


@pytest.mark.parametrize("stem", FILES)
def test_turning_the_frame_turns_the_methods(stem):
    doc = shipped(ROOT / "mechanisms" / f"{stem}.yaml")
    phi, shift = 0.7, (0.13, -0.05)
    base, result = _methods(doc)
    moved = transformed(doc, phi, shift)
    turned, _ = _methods(moved)
    assert _same_moments(base, turned) <= TOL
    assert _vectors(base, turned, lambda v: _rot(v, phi)) <= TOL
    place = lambda v: _rot(v, phi) + shift  # noqa: E731
    assert _centres(base, turned, place, lambda v: _rot(v, phi), _size(result)) <= TOL_CENTRES
    for data in (base, turned):  # the closures hold in both frames
        if "force_polygons" in data:
            assert data["force_polygons"]["max_closure_error"] <= TOL
        assert max(p["max_residual"] for p in data["vector_equations"].values()) <= 1e-12


@pytest.mark.parametrize("stem", FILES)
def test_the_files_units_change_no_number(stem):
    doc = shipped(ROOT / "mechanisms" / f"{stem}.yaml")
    si, result = _methods(doc)
    mm, _ = _methods(G.in_units(doc, "mm", "deg", "rpm"))
    same = lambda v: np.asarray(v, float)  # noqa: E731
    assert _same_moments(si, mm) <= TOL
    assert _vectors(si, mm, same) <= TOL
    assert _centres(si, mm, same, same, _size(result)) <= TOL_CENTRES


@pytest.mark.parametrize("stem", FILES)
def test_one_position_alone_is_the_full_runs_entry(stem):
    doc = shipped(ROOT / "mechanisms" / f"{stem}.yaml")
    full, result = _methods(doc)
    k = 3
    alone, _ = _methods(doc, positions=grid(doc, N)[k : k + 1])
    # the full run's entry at position k + 1, relabelled as the single run's "1"
    entry = {
        "instant_centres": {"1": full["instant_centres"][str(k + 1)]},
        "vector_equations": {"1": full["vector_equations"][str(k + 1)]},
    }
    for part in ("balancing_moment", "force_polygons"):
        if part in full:
            entry[part] = {"positions": full[part]["positions"][k : k + 1]}
    same = lambda v: np.asarray(v, float)  # noqa: E731
    assert _same_moments(entry, alone) <= TOL
    assert _vectors(entry, alone, same) <= TOL
    assert _centres(entry, alone, same, same, _size(result)) <= TOL_CENTRES
