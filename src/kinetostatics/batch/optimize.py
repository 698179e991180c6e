"""Optimisation of a mechanism file's parameters over the batch's summary quantities.

:func:`optimize` varies named ``parameters:`` of a file within bounds to minimise an
expression over a variant's batch row (:mod:`.objectives`), subject to ``<=``/``>=``
constraints.  Every design is evaluated by the batch's own path
(:func:`~kinetostatics.batch.executors.analyze_chunk`, hence
:func:`~kinetostatics.batch.variants.analyze_variants`: a whole population in one
vectorised analysis where it can, in chunks on an executor when asked), never by a second
evaluator.

The global search is :func:`scipy.optimize.differential_evolution` with a fixed seed, its
population evaluated generation by generation (``vectorized``, ``updating="deferred"``);
its best design is then refined locally by :func:`scipy.optimize.minimize`
(Nelder–Mead without constraints, COBYLA with them).

What counts as infeasible: a variant the batch reports as failed (it does not assemble
over the cycle, a group singular, invalid parameters), one whose objective has no finite
value (a self-locked machine's friction quantities are NaN), and one that breaks a
constraint or where a constraint has no value.  In the search a design is ranked by
(Deb's rules, as a penalty): a feasible design by its objective; an infeasible one behind
every feasible one, by its total violation (:data:`INFEASIBLE` + violation); a failed one
last (:data:`FAILED`).  Nothing raises for a bad variant; a search in which no design
could be analysed, or none gave the objective a value, raises :class:`OptimizeError`.

With ``out``, ``designs.csv`` is appended to as the designs are evaluated
(:func:`~.optimize_files.designs_on_disk`, the batch table's helpers); the same search
run again replays the seeded search and takes every design it meets from the file, so an
interrupted search resumes and ends as the uninterrupted one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..base.document import read_text
from ..base.limits import MAX_POSITIONS
from ..errors import did_you_mean
from .designs import _Problem
from .executors import _open_executor
from .objectives import FAILED, INFEASIBLE, Constraint, Expression, OptimizeError, parse_vary
from .optimize_files import designs_on_disk, write_outputs
from .sources import Source, template_of

if TYPE_CHECKING:
    from ..model import Model

__all__ = [
    "optimize",
    "SearchOptions",
    "Optimum",
    "OptimizeError",
    "INFEASIBLE",
    "FAILED",
    "parse_vary",
]

# The options' ranges (the command refuses others with one line): designs per
# generation = popsize × the number of varied parameters (at least 5, scipy's rule)
RANGES = {
    "popsize": (1, 1000),
    "maxiter": (0, 100_000),
    "seed": (0, 2**63 - 1),
    "positions": (1, MAX_POSITIONS),
}
# a best design this close to a bound (a fraction of HI − LO) is reported on it
ON_BOUND = 1e-6


@dataclass
class Optimum:
    """The result of :func:`optimize`.  ``parameters``: the best design (the varied ones,
    file units); ``objective``, ``constraints`` (name → value of each side's margin) and
    ``row`` (its batch row) at it; ``feasible``; ``designs``: every evaluated design
    (``{"evaluation", "stage", <parameters>, "status", "reason", "objective",
    "violation", "score"}``); ``history``: the best score after each generation and then
    after each local step; ``on_bound``: ``{name: "lower" | "upper"}`` for each
    parameter of the best design on a bound of its ``vary`` (within 1e-6 of HI − LO:
    the optimum may lie beyond it); ``files``: what was written; ``alone``: how many
    designs of the populations were analysed one by one, outside their population's
    vectorised analysis (another branch or topology, a singular position, a flywheel to
    size: the same rows, more slowly).  ``row`` holds every quantity of the batch row;
    a row in ``designs`` only those the expressions need."""

    parameters: dict[str, float]
    objective: float
    feasible: bool
    row: dict[str, Any]
    designs: list[dict[str, Any]]
    history: list[tuple[str, int, float]]
    message: str
    on_bound: dict[str, str] = field(default_factory=dict)
    files: dict[str, Path] = field(default_factory=dict)
    alone: int = 0

    def __repr__(self) -> str:
        what = ", ".join(f"{k}={v:.10g}" for k, v in self.parameters.items())
        return (
            f"Optimum({what}; objective {self.objective:.10g}, "
            f"{'feasible' if self.feasible else 'infeasible'}, {len(self.designs)} designs)"
        )


def _source(model_or_path) -> Source:
    """The mechanism file as a batch :class:`~.sources.Source`: a path, or a model read
    from a file (its ``source``)."""
    path: Path | None
    if isinstance(model_or_path, (str, Path)):
        path = Path(model_or_path)
    else:
        src = getattr(model_or_path, "source", None)
        path = Path(src) if src else None
        if path is None or not path.is_file():
            raise OptimizeError(
                "optimize: give the mechanism file's path (a model built from text has no "
                "file whose parameters could be varied)"
            )
    return Source(str(path), read_text(path))


@dataclass(frozen=True)
class SearchOptions:
    """How :func:`optimize` searches, evaluates and writes: its keywords as one record.

    The search: ``seed``, ``maxiter`` generations of ``popsize`` × (number of parameters)
    designs, ``tol``; the local refinement: ``polish``, at most ``local_maxiter`` steps.
    A design's analysis: ``positions``, ``friction`` (as for a batch), on ``executor``
    with ``workers``.  The files: ``out``, ``overwrite``; ``progress``: the bar."""

    seed: int = 0
    maxiter: int = 60
    popsize: int = 12
    tol: float = 1e-6
    polish: bool = True
    local_maxiter: int = 400
    positions: int | None = None
    friction: bool | None = None
    executor: Any = "serial"
    workers: int | None = None
    out: str | Path | None = None
    overwrite: bool = False
    progress: bool = True

    def check(self) -> None:
        """OptimizeError for a whole-number option outside its range (:data:`RANGES`)."""
        _check_ranges(popsize=self.popsize, maxiter=self.maxiter, seed=self.seed)
        if self.positions is not None:
            _check_ranges(positions=self.positions)

    @property
    def steps(self) -> int:
        """The progress bar's length: the generations, then the local steps."""
        return self.maxiter + 1 + (self.local_maxiter if self.polish else 0)


@dataclass(frozen=True)
class _Space:
    """The designs searched: the varied parameters ``names`` within ``lo`` … ``hi`` (file
    units), and ``x0`` the file's own design."""

    names: list[str]
    lo: np.ndarray
    hi: np.ndarray
    x0: np.ndarray


def optimize(  # noqa: PLR0913  the public keywords (docs/optimisation.md, the CLI); they build SearchOptions
    model_or_path: Model | str | Path,
    vary: Mapping[str, Sequence[float]] | Sequence[str],
    minimize: str,
    subject_to: Sequence[str] = (),
    *,
    seed: int = 0,
    maxiter: int = 60,
    popsize: int = 12,
    tol: float = 1e-6,
    polish: bool = True,
    local_maxiter: int = 400,
    positions: int | None = None,
    friction: bool | None = None,
    executor: Any = "serial",
    workers: int | None = None,
    out: str | Path | None = None,
    overwrite: bool = False,
    progress: bool = True,
) -> Optimum:
    """Minimise an expression over some of a mechanism file's parameters.

    A differential evolution, then a local refinement; expressions are over the batch
    row's quantities and the file's parameters (docs/optimisation.md).

    Parameters
    ----------
    model_or_path : Model or str or pathlib.Path
        The mechanism file, or a model read from one (its ``source``).
    vary : mapping of str to (float, float), or sequence of str
        The parameters to vary and their bounds in the file's units:
        ``{NAME: (LO, HI)}`` or ``["NAME=LO:HI", ...]``.
    minimize : str
        The objective, an expression (``"shaking.force_rms"``).
    subject_to : sequence of str, optional
        Constraints ``"EXPR <= EXPR"`` or ``"EXPR >= EXPR"``.
    seed, maxiter, popsize : int, optional
        The evolution's seed (default 0), generations (60) and designs per generation
        and varied parameter (12).
    tol : float, optional
        Its relative tolerance on the population's scores (default 1e-6).
    polish, local_maxiter : bool and int, optional
        Refine the best design locally (default True: Nelder–Mead, or COBYLA with
        constraints) in at most ``local_maxiter`` steps (400).
    positions, friction : int and bool, optional
        As for a batch (default: the file's).  A ``flywheel:`` is sized only when an
        expression names ``flywheel.…``.
    executor, workers : str or concurrent.futures.Executor, and int, optional
        ``"serial"`` (default: a population as one vectorised batch), ``"processes"``
        (a pool of ``workers``), a Dask scheduler address or an executor; each
        population is cut into one chunk per worker.  The result is the same on each.
    out : str or pathlib.Path, optional
        A folder for ``best.yaml``, ``designs.csv`` (appended to as designs are
        evaluated: the same search run again after an interrupt reuses them) and
        ``convergence.png``.
    overwrite, progress : bool, optional
        Start afresh in an ``out`` that holds another search (default False); show a
        progress bar (default True).

    Returns
    -------
    Optimum
        The best design (``parameters``, file units), its ``objective``,
        ``constraints``, ``row`` and ``feasible``; ``designs``, ``history``,
        ``on_bound`` (parameters on a bound) and the ``files`` written.

    Raises
    ------
    OptimizeError
        A bad name, expression or option, or an objective with no value at any design
        (never a bad design: that one scores as failed).

    Examples
    --------
    >>> import kinetostatics as ks
    >>> best = ks.optimize("mechanisms/fourbar_balancing.yaml", {"x1": (-0.3, 0.1)},
    ...                    "shaking.force_rms", maxiter=5, progress=False)  # doctest: +SKIP
    """
    opts = SearchOptions(
        seed=seed,
        maxiter=maxiter,
        popsize=popsize,
        tol=tol,
        polish=polish,
        local_maxiter=local_maxiter,
        positions=positions,
        friction=friction,
        executor=executor,
        workers=workers,
        out=out,
        overwrite=overwrite,
        progress=progress,
    )
    return _optimize(model_or_path, vary, minimize, subject_to, opts)


def _optimize(model_or_path, vary, minimize: str, subject_to, opts: SearchOptions) -> Optimum:
    """:func:`optimize` with its keywords in ``opts``: the search over the designs, written
    to ``opts.out`` as it goes, and the best design."""
    from scipy.optimize import differential_evolution

    opts.check()
    source = _source(model_or_path)
    template = template_of(source.file, source.text)
    bounds = parse_vary(vary)
    space = _space(bounds, template.parameters)
    objective = Expression(minimize)
    constraints = [Constraint.parse(c) for c in subject_to]
    named = [*objective.names.values(), *(n for c in constraints for n in c.names)]
    # the file's flywheel: is sized (variant by variant, slower) only when asked for
    flywheel = None if any(n.startswith("flywheel.") for n in named) else False
    options = {
        "positions": opts.positions,
        "friction": opts.friction,
        "flywheel": flywheel,
        "needs": tuple(dict.fromkeys(named)),  # a design's row: only what these read
    }
    names = space.names
    problem = _Problem(source, names, objective, constraints, options, opts.executor, opts.workers)
    problem.positions = opts.positions or template.base.analysis.positions
    history: list[tuple[str, int, float]] = []
    search = {
        "vary": {n: list(bounds[n]) for n in names},
        "minimize": minimize,
        "subject_to": list(subject_to),
        **{k: getattr(opts, k) for k in ("seed", "maxiter", "popsize", "tol", "polish")},
        **{k: getattr(opts, k) for k in ("local_maxiter", "positions", "friction")},
    }
    out = opts.out
    with designs_on_disk(out, source, search, names, constraints, opts.overwrite) as disk:
        if disk is not None:
            problem.load(disk.records)
            problem.sink = disk.add
        try:
            message = _run(differential_evolution, problem, space, opts, history)
        except OptimizeError:  # a mistake (an unknown name), found at the first designs
            if disk is not None and not disk.records:  # a fresh search: nothing to resume
                disk.discard()
            raise
        best = _checked_best(problem, bounds, minimize, disk)
        result = Optimum(
            parameters={n: float(best[n]) for n in names},
            objective=float(best["objective"]),
            feasible=best["status"] == "ok",
            row=dict(problem.row_of(best)),
            designs=problem.designs,
            history=history,
            message=message + _alone(problem.alone),
            on_bound=_on_bound(best, names, space.lo, space.hi),
            alone=problem.alone,
        )
        if out is not None:
            result.files = write_outputs(result, source, template, names, constraints, Path(out))
    return result


def _space(bounds: Mapping[str, tuple[float, float]], known: Mapping[str, float]) -> _Space:
    """The designs within ``bounds`` of the file's parameters ``known`` (an OptimizeError
    names a parameter the file does not have)."""
    for name in bounds:
        if name not in known:
            raise OptimizeError(
                f"--vary {name}: the file has no parameter '{name}'"
                f"{' (it has no parameters: section)' if not known else ''}"
                f"{_did_you_mean(name, known)}"
            )
    names = list(bounds)
    return _Space(
        names,
        np.array([bounds[n][0] for n in names]),
        np.array([bounds[n][1] for n in names]),
        np.array([known[n] for n in names], dtype=float),
    )


def _checked_best(problem, bounds, minimize: str, disk) -> dict[str, Any]:
    """The best design of the search, or an OptimizeError (and nothing left on ``disk``
    to resume) where no design could be analysed or the objective had no value at any."""
    best = problem.best()
    analysed = [r for r in problem.visited.values() if r["status"] != "failed"]
    if not all(math.isnan(r["objective"]) for r in analysed):
        return best
    # a mistake, not a search
    if disk is not None:  # to resume: nothing left
        disk.discard()
    if not analysed:
        vary = " ".join(f"{n}={lo:g}:{hi:g}" for n, (lo, hi) in bounds.items())
        raise OptimizeError(
            f"--vary {vary}: none of the {len(problem.visited)} designs within these "
            f"bounds could be analysed (e.g. {best['reason'] or 'failed'})"
        )
    raise OptimizeError(
        f"--minimize {minimize!r}: could not be evaluated at any of the "
        f"{len(analysed)} designs analysed (no finite value: an overflow, a function "
        "outside its domain, or a quantity these designs lack)"
    )


def _run(differential_evolution, problem, space: _Space, opts: SearchOptions, history) -> str:
    """The search, then the local refinement; their messages."""
    bar = _bar(opts.progress, opts.steps)
    try:
        if opts.executor != "serial":  # a scheduler that cannot be reached stops here
            problem.pool = _open_executor(opts.executor, opts.workers)

        def population(x: np.ndarray) -> np.ndarray:  # (n, S) -> (S,)
            try:
                recs = problem.evaluate(np.atleast_2d(x.T))
            except OptimizeError as exc:  # scipy would hide it in a RuntimeError
                problem.error = exc
                raise
            generation = sum(1 for s, _, _ in history if s == "search")
            history.append(("search", generation, problem.best()["score"]))
            problem.stage = f"generation {generation + 1}"
            bar.update(1)
            return np.array([r["score"] for r in recs])

        try:
            de = _search(differential_evolution, population, space, opts)
        except RuntimeError:
            if problem.error is not None:
                raise problem.error from None
            raise
        message = f"differential evolution: {de.message}"

        best = problem.best()
        if opts.polish and best is not None and best["score"] < FAILED:
            problem.stage = "local"
            message += "; " + _local(problem, best, space, opts.local_maxiter, history, bar)
    finally:
        bar.close()
        problem.close()
    return message


def _check_ranges(**values: int) -> None:
    """OptimizeError for an option outside its range (:data:`RANGES`)."""
    for name, value in values.items():
        lo, hi = RANGES[name]
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise OptimizeError(f"--{name} {value!r}: must be a whole number from {lo} to {hi}")
        if not lo <= value <= hi:
            raise OptimizeError(f"--{name} {value}: must be from {lo} to {hi}")


def _on_bound(best: Mapping[str, Any], names, lo, hi) -> dict[str, str]:
    """``{name: "lower" | "upper"}`` for each parameter of ``best`` within
    :data:`ON_BOUND` × (HI − LO) of a bound."""
    out = {}
    for n, a, b in zip(names, lo, hi):
        tol = ON_BOUND * (b - a)
        if best[n] - a <= tol:
            out[n] = "lower"
        elif b - best[n] <= tol:
            out[n] = "upper"
    return out


def _search(differential_evolution, population, space: _Space, opts: SearchOptions):
    """Differential evolution, a generation per call of ``population``; the file's own
    design in the first population when it lies within the bounds."""
    lo, hi, x0 = space.lo, space.hi, space.x0
    return differential_evolution(
        population,
        list(zip(lo, hi)),
        maxiter=opts.maxiter,
        popsize=opts.popsize,
        tol=opts.tol,
        rng=np.random.default_rng(opts.seed),
        polish=False,
        updating="deferred",
        vectorized=True,
        x0=x0 if np.all((x0 >= lo) & (x0 <= hi)) else None,
    )


def _alone(count: int) -> str:
    """The message's note of the designs analysed one by one (none: nothing)."""
    if not count:
        return ""
    what = "design" if count == 1 else "designs"
    return f"; {count} {what} analysed one by one (outside the population's vectorised analysis)"


def _did_you_mean(name: str, known) -> str:

    return did_you_mean(name, list(known))


def _local(problem, best, space: _Space, maxiter: int, history, bar) -> str:
    """Refine ``best`` by Nelder–Mead (no constraints) or COBYLA (constraints, and the
    bounds as constraints too), within the bounds; returns the method's message."""
    from scipy.optimize import minimize

    names, lo, hi = space.names, space.lo, space.hi
    span = hi - lo
    x0 = (np.array([best[n] for n in names]) - lo) / span  # in the unit box

    def rec(u):
        x = lo + np.clip(np.asarray(u, dtype=float), 0.0, 1.0) * span
        r = problem.evaluate(x[None, :])[0]
        history.append(("local", len(history), problem.best()["score"]))
        bar.update(1)
        return r

    if not problem.constraints:

        def f(u):
            return rec(u)["score"]

        res = minimize(
            f,
            x0,
            method="Nelder-Mead",
            bounds=[(0.0, 1.0)] * len(names),
            options={"maxiter": maxiter, "xatol": 1e-12, "fatol": 0.0, "adaptive": len(x0) > 2},
        )
        return f"Nelder-Mead: {res.message}"

    def objective(u):
        r = rec(u)
        return (
            r["objective"] if r["status"] != "failed" and not math.isnan(r["objective"]) else 1e30
        )

    def margin(k):
        def g(u):
            m = rec(u)["margins"]
            return m[k] if m and not math.isnan(m[k]) else -1e30

        return g

    cons = [{"type": "ineq", "fun": margin(k)} for k in range(len(problem.constraints))]
    for i in range(len(names)):  # the bounds, as COBYLA reads them in every scipy
        cons.append({"type": "ineq", "fun": lambda u, i=i: u[i]})
        cons.append({"type": "ineq", "fun": lambda u, i=i: 1.0 - u[i]})
    res = minimize(
        objective,
        x0,
        method="COBYLA",
        constraints=cons,
        options={"maxiter": maxiter, "rhobeg": 0.05, "tol": 1e-12},
    )
    return f"COBYLA: {res.message}"


def _bar(progress: bool, total: int):
    """The progress bar on stderr (tqdm): generations, then local steps."""
    from tqdm import tqdm

    return tqdm(total=total, disable=not progress, unit="step", desc="optimize", leave=False)
