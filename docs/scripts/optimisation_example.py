#!/usr/bin/env python
"""The worked example of docs/optimisation.md: the slotting machine's dimensions for the
least peak motor torque, its time ratio K and ram stroke H held.

``mechanisms/slotting_machine.yaml`` is written in K and H: θ = 180°(K − 1)/(K + 1), the
crank L_O2A = L_O2O3·sin(θ/2) and the guide bar L_O3B = (H/2)/sin(θ/2) are computed from
them.  The search varies the frame distance L_O2O3 (the crank follows), the rod BC_ratio
(L_BC / L_O3B) and the ram line X, so K and H are held by construction; the block says how
closely every design the search analysed kept them.

    python docs/scripts/optimisation_example.py            # print the block
    python docs/scripts/optimisation_example.py --write    # rewrite it in docs/optimisation.md
    python docs/scripts/optimisation_example.py --workers 2
    python docs/scripts/optimisation_example.py --scheduler tcp://127.0.0.1:8786

The block sits between ``<!-- BEGIN slotting-optimum -->`` and
``<!-- END slotting-optimum -->`` in docs/optimisation.md; ``tests/docs/test_docs_optimisation.py``
checks its claims independently (and, in the long run, that it is current).  Same block on
every executor.  About 20 s serially on one core.
"""

from __future__ import annotations

import argparse
import re
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

import kinetostatics as ks  # noqa: E402
from kinetostatics.batch.sources import variant_parameters  # noqa: E402
from kinetostatics.batch.variants import Template, analyze_variants  # noqa: E402
from kinetostatics.dynamics.stages import full_summary  # noqa: E402

FILE = ROOT / "mechanisms" / "slotting_machine.yaml"
DOC = ROOT / "docs" / "optimisation.md"
NAME = "slotting-optimum"
BLOCK_RE = re.compile(rf"<!-- BEGIN {NAME} -->\n(.*?)\n?<!-- END {NAME} -->", re.S)

# the problem, as docs/optimisation.md states it
VARY = {"L_O2O3": (120.0, 200.0), "BC_ratio": (0.5, 1.5), "X": (85.0, 105.0)}
MINIMIZE = "motor.torque_friction_peak"
SUBJECT_TO = ["rod_ram.pressure_angle_max <= 10"]
SEARCH = dict(seed=0, popsize=8, maxiter=30)

ROWS = [  # (label, row key, scale, format)
    ("time ratio K", "guide.time_ratio", 1.0, "{:.9f}"),
    ("ram stroke H (mm)", "guide.stroke", 1000.0, "{:.9f}"),
    ("peak motor torque, friction (N·m)", "motor.torque_friction_peak", 1.0, "{:.3f}"),
    ("peak motor torque, no friction (N·m)", "motor.torque_peak", 1.0, "{:.3f}"),
    ("RMS motor torque over the rows, friction (N·m)", "motor.torque_friction_rms", 1.0, "{:.3f}"),
    ("largest pressure angle at the ram (°)", "rod_ram.pressure_angle_max", 1.0, "{:.2f}"),
]


def run(executor="serial", workers=None) -> ks.Optimum:
    return ks.optimize(
        FILE,
        VARY,
        MINIMIZE,
        SUBJECT_TO,
        executor=executor,
        workers=workers,
        progress=False,
        **SEARCH,
    )


def block(best: ks.Optimum) -> str:
    """The Markdown of the block: the file as written against the optimum (their batch
    rows; the optimum's parameters rounded as shown), the search's counts, how closely every
    analysed design kept K and H, and the optimum to full precision."""
    template = Template.load(FILE)
    p0 = template.parameters
    (row0,) = analyze_variants(template, [{}], flywheel=False)
    p1 = variant_parameters(template, best.parameters)
    lines = ["| | as written | optimum |", "|---|---:|---:|"]
    dims = [
        ("frame distance L_O2O3 (mm)", "L_O2O3"),
        ("crank L_O2A = L_O2O3·sin(θ/2) (mm)", "L_O2A"),
        ("guide bar L_O3B = (H/2)/sin(θ/2) (mm)", "L_O3B"),
        ("rod L_BC = BC_ratio·L_O3B (mm)", "L_BC"),
        ("ram line X (mm)", "X"),
    ]
    for label, key in dims:
        lines.append(f"| {label} | {p0[key]:.2f} | {p1[key]:.2f} |")
    for label, key, scale, fmt in ROWS:
        a, b = (fmt.format(float(r[key]) * scale) for r in (row0, best.row))
        lines.append(f"| {label} | {a} | {b} |")
    rms = [  # summary.json's: exact between the load events (the rows' is first-order there)
        full_summary(ks.analyze(template.model(p)))["drivers"]["motor"]["rms_friction"]
        for p in ({}, best.parameters)
    ]
    after = next(k for k, line in enumerate(lines) if line.startswith("| RMS motor torque"))
    lines.insert(
        after + 1,
        "| RMS motor torque over the cycle, friction (N·m; summary.json) | "
        f"{rms[0]:.3f} | {rms[1]:.3f} |",
    )
    counts = {s: sum(d["status"] == s for d in best.designs) for s in ("ok", "infeasible")}
    failed = len(best.designs) - counts["ok"] - counts["infeasible"]
    # the designs' rows hold what the search's expressions read: their whole rows again,
    # as one batch
    ok = [{n: d[n] for n in best.parameters} for d in best.designs if d["status"] != "failed"]
    analysed = [r for r in analyze_variants(template, ok, flywheel=False) if r["status"] == "ok"]
    dk = max(abs(float(r["guide.time_ratio"]) - p0["K"]) for r in analysed)
    dh = max(abs(float(r["guide.stroke"]) * 1000.0 - p0["H"]) for r in analysed)
    gain = 1.0 - best.objective / float(row0[MINIMIZE])
    lines += [
        "",
        f"{len(best.designs)} designs evaluated ({counts['ok']} feasible, "
        f"{counts['infeasible']} breaking the pressure-angle limit, {failed} failed); "
        f"over the {len(analysed)} that the batch analysed, |time ratio − K| {_bound(dk)} "
        f"and |stroke − H| {_bound(dh)} mm. The peak torque falls by {100 * gain:.1f} %.",
        "",
        "The optimum to full precision: "
        + ", ".join(f"`{k} = {v!r}`" for k, v in best.parameters.items())
        + ".",
    ]
    return "\n".join(lines)


def _bound(x: float) -> str:
    """``< 1e-12`` for rounding-level numbers (the same text on any machine), else the value."""
    return "< 1e-12" if x < 1e-12 else f"≤ {x:.1e}"


def write(text: str, path: Path = DOC) -> None:
    doc = path.read_text(encoding="utf-8")
    if not BLOCK_RE.search(doc):
        raise SystemExit(f"{path}: no <!-- BEGIN {NAME} --> … <!-- END {NAME} --> block")
    new = BLOCK_RE.sub(lambda m: f"<!-- BEGIN {NAME} -->\n{text}\n<!-- END {NAME} -->", doc)
    path.write_text(new, encoding="utf-8")


def doc_block(path: Path = DOC) -> str:
    m = BLOCK_RE.search(path.read_text(encoding="utf-8"))
    if m is None:
        raise SystemExit(f"{path}: no {NAME} block")
    return m.group(1)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="rewrite the block in the doc")
    ex = ap.add_mutually_exclusive_group()
    ex.add_argument("--workers", type=int, help="evaluate each population on N processes")
    ex.add_argument("--scheduler", metavar="ADDRESS", help="... or on a Dask cluster")
    args = ap.parse_args(argv)
    executor = args.scheduler or ("processes" if args.workers else "serial")
    t0 = time.perf_counter()
    best = run(executor, args.workers)
    seconds = time.perf_counter() - t0
    text = block(best)
    if args.write:
        write(text)
    print(text)
    print(f"\n({best.message}; {seconds:.1f} s on {executor})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
