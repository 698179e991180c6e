"""``kinetostatics optimize``: vary a file's parameters to minimise an expression over the
batch's summary quantities, subject to constraints (docs/optimisation.md).

Imports neither scipy nor matplotlib at import time (``run`` stays light).
"""

from __future__ import annotations

import sys
from pathlib import Path

from .batch import analysis_options

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "optimize",
        help="optimise parameters: differential evolution over the batch's quantities",
        description="Vary the parameters of FILE within bounds to minimise EXPR, an "
        "expression over a variant's batch quantities (stroke, time_ratio, torque_rms, "
        "reaction_peak, shaking.force_peak, ...) and the file's parameters, subject to "
        "'EXPR <= EXPR' / 'EXPR >= EXPR' constraints (docs/optimisation.md). Writes "
        "DIR/best.yaml, DIR/designs.csv and DIR/convergence.png.",
    )
    p.add_argument("file", help="mechanism YAML file with a parameters: section")
    p.add_argument(
        "--vary",
        action="append",
        required=True,
        metavar="NAME=LO:HI",
        help="a parameter to vary and its bounds (file units); repeat for each",
    )
    p.add_argument("--minimize", required=True, metavar="EXPR", help="the objective")
    p.add_argument(
        "--subject-to",
        action="append",
        default=[],
        metavar="EXPR",
        help="a constraint 'EXPR <= EXPR' or 'EXPR >= EXPR'; repeat for each",
    )
    p.add_argument("--out", help="output folder (default: print only)")
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="start afresh in an --out folder that holds the designs of another search",
    )
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--maxiter", type=int, default=60, help="generations, 0 to 100000 (60)")
    p.add_argument(
        "--popsize", type=int, default=12, help="population per parameter, 1 to 1000 (12)"
    )
    p.add_argument("--no-polish", dest="polish", action="store_false", help="no local step")
    analysis_options(p)
    ex = p.add_mutually_exclusive_group()
    ex.add_argument(
        "--workers",
        type=int,
        help="evaluate each population on N processes (default: this process only)",
    )
    ex.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="evaluate each population on a Dask cluster, e.g. tcp://host:8786 "
        "(pip install 'kinetostatics[dask]')",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_optimize, keeps_memory=True)


def _optimize(args) -> int:
    from ..batch.optimize import OptimizeError, optimize
    from .batch import MAX_WORKERS

    if args.workers is not None and not 1 <= args.workers <= MAX_WORKERS:
        raise OptimizeError(f"--workers {args.workers}: must be from 1 to {MAX_WORKERS}")
    if args.scheduler:
        executor = args.scheduler
    elif args.workers and args.workers > 1:
        executor = "processes"
    else:
        executor = "serial"
    try:
        result = optimize(
            args.file,
            args.vary,
            args.minimize,
            args.subject_to,
            seed=args.seed,
            maxiter=args.maxiter,
            popsize=args.popsize,
            polish=args.polish,
            positions=args.positions,
            friction=args.friction,
            executor=executor,
            workers=args.workers,
            out=args.out,
            overwrite=args.overwrite,
            progress=not args.quiet,
        )
    except KeyboardInterrupt:
        where = (
            f"the designs evaluated are in {Path(args.out) / 'designs.csv'}; run the same "
            "command again to resume"
            if args.out
            else "no --out, so nothing was written"
        )
        print(f"kinetostatics: interrupted; {where}", file=sys.stderr)
        return 130
    state = "feasible" if result.feasible else "INFEASIBLE (no design met every constraint)"
    print(f"best design ({state}), {len(result.designs)} designs evaluated:")
    for name, value in result.parameters.items():
        side = result.on_bound.get(name)
        print(f"  {name} = {value:.10g}" + (f" (on its {side} bound)" if side else ""))
    print(f"  {args.minimize} = {result.objective:.10g}")
    print(result.message)
    if result.on_bound:
        print(
            f"on a bound: {', '.join(result.on_bound)} (the optimum may lie beyond it; "
            "widen --vary to see)"
        )
    for key, path in result.files.items():
        print(f"{key}: {path}")
    return 0
