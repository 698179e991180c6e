"""``kinetostatics sensitivity``: local sensitivities of a file's quantities to toleranced
parameters and, with ``--samples``, a Monte Carlo of the tolerances, both on the batch's
path (docs/sensitivity.md).  Writes DIR/sensitivity.json, sensitivity.md, the tornado
charts and histograms, and samples.csv.

Imports neither scipy nor matplotlib at import time (``run`` stays light).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from .batch import analysis_options

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "sensitivity",
        help="sensitivities d(quantity)/d(parameter) and a Monte Carlo of tolerances",
        description="The derivatives of quantities of FILE's batch row (slide.stroke, "
        "motor.torque_peak, … or expressions of them and the parameters) with respect to "
        "toleranced parameters, by central differences on the batch's vectorised path, with "
        "their error estimates and a tornado chart; with --samples, a Monte Carlo of the "
        "tolerances: percentiles, histograms and the share of designs outside --limit "
        "(docs/sensitivity.md). Writes DIR/sensitivity.json, sensitivity.md, tornado-*.png "
        "and .svg, histogram-*.png and samples.csv.",
    )
    p.add_argument("file", help="mechanism YAML file with a parameters: section")
    p.add_argument(
        "--vary",
        action="append",
        required=True,
        metavar="NAME=±TOL",
        help="a toleranced parameter: ±TOL in the file's units or ±TOL%% of its value; "
        "repeat for each",
    )
    p.add_argument(
        "--of",
        action="append",
        metavar="Q",
        help="a quantity (a batch row's, or an expression); repeat for each (default: the "
        "strokes, time ratios, peak and RMS efforts, pressure and transmission angles)",
    )
    p.add_argument("--samples", type=int, metavar="N", help="Monte Carlo designs (default: none)")
    p.add_argument(
        "--dist",
        choices=("normal", "uniform"),
        default="normal",
        help="normal: ±TOL is 3 standard deviations (default); uniform: ±TOL is the range",
    )
    p.add_argument(
        "--limit",
        action="append",
        default=[],
        metavar="'Q <= X'",
        help="a limit; the share of the designs outside it is reported; repeat for each",
    )
    p.add_argument("--seed", type=int, default=0, help="random seed of the samples (default 0)")
    p.add_argument("--out", required=True, help="output folder")
    _run_options(p)
    p.set_defaults(func=_sensitivity, keeps_memory=True)


def _run_options(p) -> None:
    """How the designs are analysed and where: as ``batch``'s options."""
    analysis_options(p)
    ex = p.add_mutually_exclusive_group()
    ex.add_argument("--workers", type=int, help="worker processes (default: the number of cores)")
    ex.add_argument("--serial", action="store_true", help="run in this process")
    ex.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a Dask scheduler, e.g. tcp://host:8786 (pip install 'kinetostatics[dask]')",
    )
    p.add_argument("--chunk", type=int, help="samples per chunk (default: as batch)")
    p.add_argument(
        "--progress",
        action="store_true",
        default=None,
        help="show the progress bar even when stderr is not a terminal",
    )
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="start afresh in an output folder holding the samples of another analysis",
    )


def _options(args):
    from ..base.limits import MAX_POSITIONS
    from ..batch.runner import BatchOptions
    from ..batch.sensitivity import SensitivityError
    from .batch import MAX_WORKERS

    for name, lo, hi in (("workers", 1, MAX_WORKERS), ("chunk", 1, 10_000_000)):
        v = getattr(args, name)
        if v is not None and not lo <= v <= hi:
            raise SensitivityError(f"--{name} {v}: must be from {lo} to {hi}")
    if args.positions is not None and not 1 <= args.positions <= MAX_POSITIONS:
        raise SensitivityError(f"--positions {args.positions}: must be from 1 to {MAX_POSITIONS}")
    return BatchOptions(
        chunk=args.chunk,
        executor="serial" if args.serial else (args.scheduler or "processes"),
        workers=args.workers,
        positions=args.positions,
        friction=args.friction,
        progress=args.progress,
        overwrite=args.overwrite,
    )


def _sensitivity(args) -> int:
    from ..batch.sensitivity import SensitivityError, derivatives, study
    from ..batch.tolerance import check_options, parse_limits, run_samples

    if args.limit and args.samples is None:
        raise SensitivityError("--limit needs --samples (the share of designs outside it)")
    opts = _options(args)
    check_options(2 if args.samples is None else args.samples, args.dist, args.seed)
    st = study(args.file, args.vary, args.of, opts)
    parse_limits(args.limit, [k for k in st.nominal if k not in ("status", "reason")])
    out = Path(args.out)
    try:
        sens = derivatives(st, out)
        mc = None
        if args.samples is not None:
            linear = {q: sens.linear_sd(q, args.dist) for q in sens.quantities}
            mc = run_samples(st, args.samples, args.dist, args.seed, args.limit, out, linear)
    except KeyboardInterrupt:
        print(
            f"kinetostatics: interrupted; the finished samples are in {out / 'samples'}; "
            "run the same command again to resume",
            file=sys.stderr,
        )
        return 130
    files = _write(out, sens, mc, args.limit)
    _report(sens, mc, args.dist)
    for path in files:
        print(f"wrote {path}")
    return 0


def _safe(name: str) -> str:
    return re.sub(r"[^\w.-]+", "_", name)


def _write(out: Path, sens, mc, limits) -> list[Path]:
    """sensitivity.json, sensitivity.md, the pictures and samples.csv, each whole."""
    from ..base.files import json_text, write_outputs
    from ..outputs.plotting.tornado import histogram_figure, tornado_figure
    from ..outputs.sensitivity import sensitivity_markdown

    writers, pictures = [], []
    for q in sens.quantities:
        name = f"tornado-{_safe(q)}"
        fig = tornado_figure(sens, q)
        for fmt in ("png", "svg"):
            writers.append((out / f"{name}.{fmt}", _saver(fig, fmt)))
        pictures.append((f"tornado chart of {q}", f"{name}.png"))
        if mc is not None:
            hist = histogram_figure(mc, q, limits=_limits_on(q, limits))
            writers.append((out / f"histogram-{_safe(q)}.png", _saver(hist, "png")))
            pictures.append((f"histogram of {q}", f"histogram-{_safe(q)}.png"))
    data = {
        "file": sens.file,
        "tolerances": [
            {"parameter": t.name, "nominal": t.nominal, "tolerance": t.half, "written": t.text}
            for t in sens.tolerances
        ],
        "sensitivity": sens.to_dict(mc.dist if mc is not None else None),
        "monte_carlo": mc.to_dict() if mc is not None else None,
    }
    writers.append((out / "sensitivity.json", _text(json_text(data))))
    writers.append((out / "sensitivity.md", _text(sensitivity_markdown(sens, mc, pictures))))
    if mc is not None:
        writers.append((out / "samples.csv", lambda tmp: _samples_csv(tmp, mc, sens.units)))
    write_outputs(out, f"--out {out}", writers)
    return [path for path, _ in writers]


def _saver(fig, fmt: str):
    return lambda tmp: fig.savefig(tmp, format=fmt)


def _text(text: str):
    return lambda tmp: Path(tmp).write_text(text, encoding="utf-8")


def _limits_on(q: str, limits) -> list[tuple[float, str]]:
    """The limits ``Q <= X`` / ``Q >= X`` on quantity ``q`` with a number X, to draw."""
    from ..batch.objectives import Constraint

    out = []
    for text in limits:
        c = Constraint.parse(text)
        if c.left.text == q and not c.right.names:
            out.append((c.right.value({}), c.op))
    return out


def _samples_csv(path, mc, units) -> None:
    """One row per design: its parameters, status, reason and quantities."""
    from ..base.tables import write_table

    names = ["sample", *(t.name for t in mc.tolerances), "status", "reason", *mc.quantities]
    unit_row = ["", *("file" for _ in mc.tolerances), "", "", *units]
    rows = (
        [k + 1, *(repr(float(v)) for v in mc.parameters[k]), mc.status[k], mc.reasons_by_sample[k]]
        + ["" if v != v else repr(float(v)) for v in mc.values[k]]
        for k in range(mc.samples)
    )
    with open(path, "w", encoding="utf-8", newline="") as f:
        write_table(f, names, unit_row, rows)


def _report(sens, mc, dist: str) -> None:
    """The results in short on stdout; a warning on stderr for each derivative whose
    error estimate is large (not smooth at the nominal design) and each failed design."""
    for k, q in enumerate(sens.quantities):
        unit = "" if sens.units[k] in ("", "1") else f" {sens.units[k]}"
        print(f"{q} = {sens.nominal[k]:.8g}{unit}")
        for d in sens.of(q):
            print(
                f"  d/d{d.parameter} = {d.value:.8g} ± {d.error:.2g}   "
                f"at p ∓ t: {d.low:.8g} … {d.high:.8g}"
            )
            if d.flagged:
                print(
                    f"kinetostatics: warning: d({q})/d({d.parameter}) = {d.value:.6g} has an "
                    f"error estimate of {d.error:.2g}: {q} is not smooth at the nominal design "
                    "(a peak changing rows, a failed design); read it as a rough slope",
                    file=sys.stderr,
                )
        if mc is not None:
            sp = next(s for s in mc.spreads if s.quantity == q)
            print(
                f"  Monte Carlo: mean {sp.mean:.8g}, sd {sp.sd:.4g} (linearised {sp.linear_sd:.4g})"
            )
    for vid, reason in sens.failed:
        print(f"kinetostatics: warning: design {vid} failed: {reason}", file=sys.stderr)
    if mc is not None:
        print(
            f"Monte Carlo: {mc.samples} designs ({dist}, seed {mc.seed}), {mc.failed} failed"
            + "".join(f"; {lim.text}: {100 * lim.share:.4g} % outside" for lim in mc.limits)
        )
        if mc.failed:
            print(
                f"kinetostatics: warning: {mc.failed} of {mc.samples} designs could not be "
                f"analysed (e.g. {mc.reasons[0][0]})",
                file=sys.stderr,
            )
