"""``kinetostatics batch`` (variants of a file, or a folder of files → one summary
table) and ``kinetostatics best`` (the top rows of a summary table).

Imports neither scipy nor matplotlib at import time (``run`` stays light).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["register"]

SWEEP_HELP = """\
Sweeps (docs/batch.md): a `sweep:` section in FILE, or --sweep SWEEP.yaml, or the
options below. --set NAME=A,B,C (a list), NAME=FROM:TO:NUM (NUM values), several
--set = a grid; --random N --seed S samples each --set NAME=LO:HI uniformly
(NAME=A,B,C: a choice); --table CSV: one variant per row. Command-line options
replace the file's own sweep: section and combine with --sweep by cartesian product.
A FOLDER runs each *.yaml as written, one row each."""


def register(sub) -> None:
    p = sub.add_parser(
        "batch",
        help="analyse many variants (a sweep, a CSV table, a folder): summary.csv",
        description="Analyse the variants of FILE (or every *.yaml in a FOLDER) and write "
        "DIR/summary.csv: a row per variant with its parameters, status and "
        "reason, stroke, time ratio, peak and RMS driving effort with and without "
        "friction, efficiency, self-locking, peak reactions, peak output "
        "velocity/acceleration, worst pressure angle, flywheel inertia. A rerun "
        "resumes an interrupted batch.",
        epilog=SWEEP_HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("file", help="mechanism YAML file, or a folder of them")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--sweep", help="sweep YAML file (blocks grid/zip/random/table)")
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUES",
        help="sweep a parameter: A,B,C or FROM:TO:NUM (LO:HI with --random)",
    )
    p.add_argument(
        "--table",
        help="CSV of variants: a header of parameter names, optional variant column, one row each",
    )
    p.add_argument("--random", type=int, metavar="N", help="N random samples of the --set ranges")
    p.add_argument("--seed", type=int, help="random seed (default 0)")
    analysis_options(p)
    fw = p.add_mutually_exclusive_group()
    fw.add_argument(
        "--flywheel",
        action="store_true",
        default=None,
        help="add the flywheel inertia (default: when the file has flywheel:)",
    )
    fw.add_argument(
        "--no-flywheel",
        dest="flywheel",
        action="store_false",
        help="skip the flywheel even if the file has flywheel: (faster: sizing "
        "it analyses the variants one by one)",
    )
    p.add_argument(
        "--results",
        action="store_true",
        help="also write DIR/variants/<id>/results.csv and summary.json",
    )
    ex = p.add_mutually_exclusive_group()
    ex.add_argument("--workers", type=int, help="worker processes (default: the number of cores)")
    ex.add_argument("--serial", action="store_true", help="run in this process")
    ex.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a Dask scheduler, e.g. tcp://host:8786 (pip install 'kinetostatics[dask]')",
    )
    p.add_argument(
        "--chunk",
        type=int,
        help="variants per chunk (default: memory-bounded, 4 chunks per worker at least)",
    )
    p.add_argument(
        "--progress",
        action="store_true",
        default=None,
        help="show the progress bar even when stderr is not a terminal",
    )
    p.add_argument(
        "--overwrite", action="store_true", help="start afresh in an output folder of another batch"
    )
    _best_options(p, required=False)
    p.set_defaults(func=_batch, keeps_memory=True)

    q = sub.add_parser(
        "best",
        help="the best rows of a batch's summary.csv",
        description="Print the top rows of a batch summary table: the "
        "variants with status ok meeting every --where, sorted by "
        "the objective.",
    )
    q.add_argument("file", help="summary.csv of a batch (or its output folder)")
    _best_options(q, required=True)
    q.set_defaults(func=_best)


def analysis_options(p) -> None:
    """``--positions`` and ``--no-friction``: how each variant is analysed (batch, optimize)."""
    p.add_argument("--positions", type=int, help="positions per cycle (default: the file's)")
    p.add_argument(
        "--no-friction",
        dest="friction",
        action="store_false",
        default=None,
        help="skip the friction solutions",
    )


def _best_options(p, required: bool) -> None:
    p.add_argument(
        "--best",
        required=required,
        metavar="'min|max COLUMN'",
        help="objective, e.g. 'min motor.torque_friction_peak'",
    )
    p.add_argument(
        "--where",
        action="append",
        default=[],
        metavar="'COLUMN OP NUMBER'",
        help="constraint (several = all), e.g. 'rod_ram.pressure_angle_max <= 10'",
    )
    p.add_argument("--top", type=int, default=5, help="rows to print (default 5)")


def _variants(args, sources):
    """The tasks of the command line: a sweep of one file, or each file as written."""
    from ..batch import BatchError, Task, sweeps

    cli = sweeps.from_options(args.set, args.table, args.random, args.seed)
    blocks = []
    if args.sweep:
        path = Path(args.sweep)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as exc:
            raise BatchError(f"--sweep {args.sweep}: {exc.strerror}") from None
        blocks = sweeps.load_sweep(text, str(path))
        base = path.parent
    elif not cli and len(sources) == 1:
        blocks = sweeps.load_sweep(sources[0].text, sources[0].file, key="sweep") or []
        base = Path(sources[0].file).parent
    else:
        base = Path(".")
    if len(sources) > 1:
        if blocks or cli:
            raise BatchError(
                f"{args.file}: a folder batch runs each file as written; sweep one file at a time"
            )
        return None
    variants = sweeps.expand([*blocks, *cli], base)
    if not variants:
        return None  # the file as written
    return [Task(vid, 0, values) for vid, values in variants]


def _ranges() -> tuple[tuple[str, int, int], ...]:
    from ..base.limits import MAX_POSITIONS
    from ..batch.limits import MAX_VARIANTS

    return (
        ("positions", 1, MAX_POSITIONS),
        ("chunk", 1, MAX_VARIANTS),
        ("workers", 1, MAX_WORKERS),
        ("random", 1, MAX_VARIANTS),
        ("seed", 0, 2**63 - 1),
        ("top", 1, MAX_VARIANTS),
    )


def _check_ranges(args, error) -> None:
    """Each whole-number option of ``args`` within its range (:func:`_ranges`), else
    ``error`` naming it."""
    for option, lo, hi in _ranges():
        v = getattr(args, option, None)
        if v is not None and not lo <= v <= hi:
            raise error(f"--{option} {v}: must be from {lo} to {hi}")


# More worker processes than this are refused: each holds a copy of the
# interpreter and numpy (about 60 MB) and two chunks in flight.
MAX_WORKERS = 1024


def _batch(args) -> int:
    from ..batch import BatchError, run_batch, sources_of, template_of

    if args.where and not args.best:
        raise BatchError("--where needs --best")
    _check_ranges(args, BatchError)
    sources = sources_of(args.file)
    if len(sources) == 1:
        template_of(sources[0].file, sources[0].text)  # a broken file stops here
    tasks = _variants(args, sources)
    executor = "serial" if args.serial else (args.scheduler or "processes")
    try:
        s = run_batch(
            sources,
            tasks,
            args.out,
            chunk=args.chunk,
            executor=executor,
            workers=args.workers,
            positions=args.positions,
            friction=args.friction,
            flywheel=args.flywheel,
            results=args.results,
            progress=args.progress,
            overwrite=args.overwrite,
        )
    except KeyboardInterrupt:
        print(
            f"kinetostatics: interrupted; the finished rows are in {Path(args.out) / 'summary.csv'}"
            "; run the same command again to resume",
            file=sys.stderr,
        )
        return 130
    line = (
        f"{s.total} variants -> {s.summary_csv}: {s.computed} computed in {s.seconds:.1f} s "
        f"({s.rate:.1f} variants/s, chunks of {s.chunk}, {s.workers} workers)"
    )
    if s.reused:
        line += f", {s.reused} from the previous run"
    if s.alone:
        line += f"; {s.alone} analysed one by one (outside the vectorised analysis)"
    print(
        line
        + f"; {s.failed} failed"
        + (f", {s.errors} errors (a rerun retries them)" if s.errors else "")
    )
    if args.best:
        from ..batch.best import best

        print(best(s.summary_csv, args.best, args.where, args.top))
    return 0


def _best(args) -> int:
    from ..batch.best import BestError, best

    _check_ranges(args, BestError)
    path = Path(args.file)
    if path.is_dir():
        path = path / "summary.csv"
    if not path.is_file():
        raise BestError(f"{args.file}: no such summary table")
    print(best(path, args.best, args.where, args.top))
    return 0
