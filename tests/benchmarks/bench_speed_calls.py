"""The fixed cost of an analysis counted: Python-level calls per stage, and the
kinematic plan's effect (kinematics/plan.py) against the general derivative stage.

For the rows of ``bench_speed.py`` (``ks.analyze`` of the slider-crank and the
slotting machine, kinematics only and frictionless, reading the columns the closed
form computes) at 10 and 360 positions, prints:

- the calls one analysis makes (cProfile's count: Python functions and the C
  functions called by name; NumPy's array operators are not calls), with the plan and
  without it (``kinematics.plan.ENABLED``), and their split over the stages that
  ``analyze`` calls in turn (the positions, the velocities and accelerations, the
  loads and reactions, the result, reading the columns);
- the time with the plan over the time without, the median of per-round ratios
  (CPU time of the process, the two timed in turns, as bench_speed.py times).

With ``--lines``, also the time of each line of the
slider-crank's and the slotting machine's generated plan at 360 positions (the
source instrumented with a clock between its statements), grouped as the joints'
formulas (``.jacobian``, ``.acceleration_rhs`` or the traced kernels' lines), the factorisation
(``invert``: the blocks' inverses) and the rest (gathers, scatters, substitutions).

Nothing here is a test.  docs/accuracy.md (section 8) quotes it.

    PYTHONPATH=src python tests/benchmarks/bench_speed_calls.py [--quick] [--lines]
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import time

import numpy as np
from bench_speed import LEVEL_KW, case, interleaved, median

import kinetostatics as ks
from kinetostatics.kinematics import plan
from kinetostatics.structure.system import link_poses

plan.PLAN_AFTER = (0, 0)  # the plans from a system's first analysis: their effect is measured

STAGES = {
    "solve_run": "positions",
    "_motion": "velocities and accelerations",
    "load_events": "load events",
    "inverse_dynamics": "loads, reactions, power",
    "_result": "result (conditions, checks, columns)",
}


def calls(fn) -> tuple[int, dict[str, int]]:
    """cProfile's count of one call of ``fn``, and the calls under each stage (after two
    calls: the first makes the kinematic plan, the second the residual plan)."""
    fn()
    fn()
    prof = cProfile.Profile()
    prof.enable()
    fn()
    prof.disable()
    total = pstats.Stats(prof).total_calls
    per = dict.fromkeys((*STAGES.values(), "reading the columns"), 0)

    def count(frame, event, arg):
        if event not in ("call", "c_call"):
            return
        f = frame
        while f is not None and f.f_back is not None:
            if f.f_back.f_code.co_name == "analyze" and f.f_code.co_name in STAGES:
                per[STAGES[f.f_code.co_name]] += 1
                return
            if f.f_back.f_code.co_name == "run" and f.f_code.co_name == "<listcomp>":
                per["reading the columns"] += 1  # bench_speed's reading of the result
                return
            f = f.f_back

    sys.setprofile(count)
    fn()
    sys.setprofile(None)
    return total, per


def with_plan(on: bool, fn):
    def run():
        plan.ENABLED = on
        try:
            return fn()
        finally:
            plan.ENABLED = True

    return run


def plan_lines(name: str, n: int = 360, repeat: int = 400) -> dict[str, float]:
    """Time (s per run) of the generated plan's lines of ``name`` at ``n`` positions,
    grouped: the joints' formulas, the factorisation, the rest."""
    r = ks.analyze(case(name, n).model, kinematics_only=True)
    system = r.system
    lines, env = plan.written(system)
    at = next(k for k, line in enumerate(lines) if line.startswith("def run("))
    end = next((k for k, line in enumerate(lines) if k > at and line.startswith("def ")), None)
    inverses, lines = lines[:at], lines[at:end]  # the blocks' inverses' functions, untimed
    body: list[str] = []  # the top-level statements (an if with its else is one)
    for line in lines[1:]:
        if body and (line.startswith("        ") or line.startswith("    else:")):
            body[-1] += "\n" + line
        else:
            body.append(line)
    timed_src = [*inverses, lines[0], "    _T = _clock()"]
    for k, line in enumerate(body):
        timed_src += [line, f"    _t = _clock(); ACC[{k}] += _t - _T; _T = _t"]
    env["ACC"], env["_clock"] = [0.0] * len(body), time.perf_counter
    exec(compile("\n".join(timed_src) + "\n", "<timed plan>", "exec"), env)
    pe = link_poses(system, r.q)
    psi_d, psi_dd = np.ones((n, 1)), np.zeros((n, 1))
    size, k = system.layout.size + 1, [len(p.cols) for p in system.plans]

    def args():  # the arrays planned_derivatives makes for the plan to write into
        out = np.zeros((size, n)), np.empty((system.n_q, n)), np.empty((system.n_q, n))
        cnd = [np.empty(n) if g in plan.conditioned(system) else None for g in range(len(k))]
        return (pe, psi_d, psi_dd, *out, [np.zeros((m, m, n)) for m in k], cnd)

    for _ in range(20):
        env["run"](*args())
    env["ACC"][:] = [0.0] * len(body)
    for _ in range(repeat):
        env["run"](*args())
    out = {"joints' formulas": 0.0, "factorisation": 0.0, "rest": 0.0}
    for line, t in zip(body, env["ACC"]):
        kind = (
            "joints' formulas"
            if ".jacobian(" in line
            or ".acceleration_rhs(" in line
            or line.lstrip().startswith("e")
            or line.lstrip().startswith(("buf[", "rows["))
            else "factorisation"
            if "invert(" in line or "INVERSE" in line
            else "rest"
        )
        out[kind] += t / repeat
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer rounds")
    ap.add_argument("--lines", action="store_true", help="the plan's time by kind of line")
    args = ap.parse_args(argv)
    rounds, sample = (5, 0.01) if args.quick else (15, 0.03)
    if args.lines:
        for name in ("slider_crank", "slotting_machine"):
            parts = plan_lines(name)
            total = sum(parts.values())
            shares = ", ".join(f"{k} {v * 1e3:.3f} ms ({v / total:.0%})" for k, v in parts.items())
            print(f"{name}, the plan at 360 positions: {total * 1e3:.3f} ms: {shares}")
    print(
        "| mechanism | row | positions | calls without the plan | calls with it "
        "| time with / without (median of rounds) | calls per stage, with the plan |"
    )
    print("|---|---|---|---|---|---|---|")
    for name in ("slider_crank", "slotting_machine"):
        for level in ("kinematics", "frictionless"):
            for n in (10, 360):
                c = case(name, n)
                names = list(c.closed(c.grid()[:3], level))
                fn = c.generic(names, **LEVEL_KW[level])
                off, _ = calls(with_plan(False, fn))
                on, per = calls(with_plan(True, fn))
                both = [with_plan(False, fn), with_plan(True, fn)]
                general, planned = interleaved(both, rounds, sample)
                ratio = median([b / a for a, b in zip(general, planned)])
                stages = ", ".join(f"{k} {v}" for k, v in per.items() if v)
                print(f"| {name} | {level} | {n} | {off} | {on} | {ratio:.3f} | {stages} |")


if __name__ == "__main__":
    main()
