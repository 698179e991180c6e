#!/usr/bin/env python
"""The worked example of docs/sensitivity.md: the slotting machine's sensitivities to its
time ratio K, stroke H, frame distance L_O2O3 and rod ratio BC_ratio, and a Monte Carlo of
those tolerances (1,000 designs, normal, seed 0) against two limits.

The same numbers as

    kinetostatics sensitivity mechanisms/slotting_machine.yaml --vary K=±1% --vary H=±0.5 \\
        --vary L_O2O3=±0.5 --vary BC_ratio=±2% --of guide.stroke --of guide.time_ratio \\
        --of motor.torque_friction_peak --of rod_ram.pressure_angle_max --positions 72 \\
        --samples 1000 --limit "motor.torque_friction_peak <= 44" \\
        --limit "rod_ram.pressure_angle_max <= 3.9" --serial --out out/sens

    python docs/scripts/sensitivity_example.py            # print the block
    python docs/scripts/sensitivity_example.py --write    # rewrite it in docs/sensitivity.md

The block sits between ``<!-- BEGIN slotting-sensitivity -->`` and
``<!-- END slotting-sensitivity -->``; ``tests/docs/test_docs_sensitivity.py`` checks its
claims against the file's closed forms.  About 3 s on one core.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

from kinetostatics.batch.runner import BatchOptions  # noqa: E402
from kinetostatics.batch.sensitivity import derivatives, study  # noqa: E402
from kinetostatics.batch.tolerance import run_samples  # noqa: E402

FILE = ROOT / "mechanisms" / "slotting_machine.yaml"
DOC = ROOT / "docs" / "sensitivity.md"
NAME = "slotting-sensitivity"
BLOCK_RE = re.compile(rf"<!-- BEGIN {NAME} -->\n(.*?)\n?<!-- END {NAME} -->", re.S)
VARY = ["K=±1%", "H=±0.5", "L_O2O3=±0.5", "BC_ratio=±2%"]
OF = [
    "guide.stroke",
    "guide.time_ratio",
    "motor.torque_friction_peak",
    "rod_ram.pressure_angle_max",
]
LIMITS = ["motor.torque_friction_peak <= 44", "rod_ram.pressure_angle_max <= 3.9"]
SAMPLES, SEED, DIST = 1000, 0, "normal"


def _g(x: float, digits: int = 6) -> str:
    return f"{x:.{digits}g}"


def doc_block() -> str:
    """The block: the derivatives table, then the Monte Carlo's spreads and limits."""
    st = study(FILE, VARY, OF, BatchOptions(executor="serial", positions=72, progress=False))
    sens = derivatives(st)
    linear = {q: sens.linear_sd(q, DIST) for q in sens.quantities}
    mc = run_samples(st, SAMPLES, DIST, SEED, LIMITS, None, linear)
    lines = [
        "| quantity | nominal | parameter | dQ/dp | error estimate | Q(p − t) | Q(p + t) |",
        "|---|---|---|---|---|---|---|",
    ]
    for k, q in enumerate(sens.quantities):
        unit = "" if sens.units[k] in ("", "1") else f" {sens.units[k]}"
        for j, d in enumerate(sens.of(q)):
            head = f"`{q}` | {_g(sens.nominal[k], 8)}{unit}" if j == 0 else " | "
            lines.append(
                f"| {head} | `{d.parameter}` | {_g(d.value, 8)} | {_g(d.error, 2)} | "
                f"{_g(d.low, 8)} | {_g(d.high, 8)} |"
            )
    lines += [
        "",
        f"Monte Carlo: {mc.samples} designs ({mc.dist}, ±t = 3σ, seed {mc.seed}), "
        f"{mc.analysed} analysed, {mc.failed} failed.",
        "",
        "| quantity | mean | sd | linearised sd | 0.135 % | 50 % | 99.865 % |",
        "|---|---|---|---|---|---|---|",
    ]
    for sp in mc.spreads:
        pts = dict(sp.percentiles)
        lines.append(
            f"| `{sp.quantity}` | {_g(sp.mean, 8)} | {_g(sp.sd, 4)} | {_g(sp.linear_sd, 4)} | "
            f"{_g(pts[0.135], 8)} | {_g(pts[50.0], 8)} | {_g(pts[99.865], 8)} |"
        )
    lines.append("")
    for lim in mc.limits:
        lines.append(
            f"- `{lim.text}`: {lim.outside} of {lim.analysed} designs outside "
            f"({_g(100 * lim.share, 4)} %)"
        )
    lines.append(
        f"- outside some limit or failed: {mc.outside_any + mc.failed} of {mc.samples} "
        f"({_g(100 * mc.share_lost, 4)} %)"
    )
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="rewrite the block in the page")
    args = ap.parse_args()
    block = doc_block()
    print(block)
    if args.write:
        text = DOC.read_text(encoding="utf-8")
        new, n = BLOCK_RE.subn(
            lambda _: f"<!-- BEGIN {NAME} -->\n{block}\n<!-- END {NAME} -->", text
        )
        if n != 1:
            raise SystemExit(f"{DOC}: no block {NAME}")
        DOC.write_text(new, encoding="utf-8")
        print(f"wrote {DOC}")


if __name__ == "__main__":
    main()
