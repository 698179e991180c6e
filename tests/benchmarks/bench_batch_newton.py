"""Batches of mechanisms with a group that has no closed form — a triad (the Stephenson
six-bar), a link closed by a gear pair (the geared five-bar), by a rack (the rack-driven
rocker), by its cam (the oscillating flat-faced cam) — in variants per CPU-second: the
stacked analysis, whose rows come by Newton along the path for all variants at once
(``kinematics/stacked_path.py``), against the same variants analysed one by one
(``vectorise=False``), in this process, the two timed in turns round by round; a ratio
is the median of the rounds' ratios.  The variants scale the named parameters by
seeded random factors within ±3 % (those that leave a gear's or a cam's geometry
alone: a variant that changes it is analysed one by one either way), at the file's 360
positions with its friction and no flywheel.  Nothing here is a test.

    PYTHONPATH=src python tests/benchmarks/bench_batch_newton.py [--variants 48] [--rounds 3]
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

import numpy as np
from _common import ROOT, machine

from kinetostatics.batch.variants import Template, _analyze_variants

CASES = {  # file: the parameters varied (None: all)
    "stephenson_sixbar": None,
    "geared_fivebar": ("a1", "a2", "b1", "b2"),
    "rack_rocker": ("a", "b", "l"),
    "cam_flat_oscillating": ("l",),
}


def _variants(tpl: Template, keys, n: int) -> list[dict]:
    rng = np.random.default_rng(2026)
    base = tpl.parameters
    return [{k: base[k] * (1 + 0.03 * rng.uniform(-1, 1)) for k in keys or base} for _ in range(n)]


def _rate(tpl: Template, ovs: list[dict], vectorise: bool) -> tuple[float, int]:
    """(variants per CPU-second, how many were analysed one by one)."""
    t0 = time.process_time()
    rows, _, alone = _analyze_variants(tpl, ovs, vectorise=vectorise, flywheel=False)
    dt = time.process_time() - t0
    assert all(r["status"] == "ok" for r in rows), [r["reason"] for r in rows]
    return len(ovs) / dt, alone


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--variants", type=int, default=48)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    print(f"{machine()}; CPU time of this process; {args.variants} variants, {args.rounds} rounds")
    print("| mechanism | stacked [/CPU-s] | one by one [/CPU-s] | ratio | stacked: one by one |")
    print("|---|---|---|---|---|")
    for name, keys in CASES.items():
        tpl = Template.load(ROOT / "mechanisms" / f"{name}.yaml")
        ovs = _variants(tpl, keys, args.variants)
        _rate(tpl, ovs[:4], True), _rate(tpl, ovs[:2], False)  # warm: plans, caches
        fast, slow, alone = [], [], 0
        for _ in range(args.rounds):
            rate, alone = _rate(tpl, ovs, True)
            fast.append(rate)
            slow.append(_rate(tpl, ovs, False)[0])
        ratio = statistics.median(f / s for f, s in zip(fast, slow))
        print(
            f"| {name} | {statistics.median(fast):.0f} | {statistics.median(slow):.0f} "
            f"| {ratio:.1f}× | {alone} |"
        )


if __name__ == "__main__":
    main()
