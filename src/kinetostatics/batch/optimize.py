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
from typing import Any

import numpy as np

from ..base.document import read_text
from ..base.limits import MAX_POSITIONS
from ..errors import did_you_mean
from .executors import _open_executor, analyze_chunk
from .objectives import FAILED, INFEASIBLE, Constraint, Expression, OptimizeError
from .optimize_files import designs_on_disk, write_outputs
from .sources import Chunk, Source, auto_chunk, template_of, variant_parameters

__all__ = ["optimize", "Optimum", "OptimizeError", "INFEASIBLE", "FAILED", "parse_vary"]

# |LO|, |HI| of a --vary at most half the largest float: the search's designs are
# midpoint + u·span, and both stay finite
MAX_BOUND = float(np.finfo(float).max) / 2
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


def parse_vary(items: Sequence[str] | Mapping[str, Sequence[float]]) -> dict[str, tuple]:
    """``["NAME=LO:HI", …]`` or ``{NAME: (LO, HI)}`` → ``{NAME: (LO, HI)}``."""
    out: dict[str, tuple[float, float]] = {}
    pairs = items.items() if isinstance(items, Mapping) else [_split_vary(t) for t in items]
    for name, bounds in pairs:
        try:
            lo, hi = (float(b) for b in bounds)
        except (TypeError, ValueError):
            raise OptimizeError(f"--vary {name}: expected LO:HI, got {bounds!r}") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise OptimizeError(f"--vary {name}={lo:g}:{hi:g}: needs finite LO < HI")
        if max(abs(lo), abs(hi)) > MAX_BOUND:
            # the search works on the midpoint and the span, which must stay finite
            raise OptimizeError(
                f"--vary {name}={lo:g}:{hi:g}: bounds beyond ±{MAX_BOUND:.4g} (half the "
                "largest float) would give designs that are not finite numbers"
            )
        if name in out:
            raise OptimizeError(f"--vary {name}: named twice; give each parameter once")
        out[name] = (lo, hi)
    if not out:
        raise OptimizeError("nothing to vary: give --vary NAME=LO:HI")
    return out


def _split_vary(text: str) -> tuple[str, tuple[str, ...]]:
    name, eq, rest = text.partition("=")
    bounds = tuple(rest.split(":"))
    if not eq or not name.strip() or len(bounds) != 2:
        raise OptimizeError(f"--vary {text!r}: expected NAME=LO:HI")
    return name.strip(), bounds


@dataclass
class Optimum:
    """The result of :func:`optimize`.  ``parameters``: the best design (the varied ones,
    file units); ``objective``, ``constraints`` (name → value of each side's margin) and
    ``row`` (its batch row) at it; ``feasible``; ``designs``: every evaluated design
    (``{"evaluation", "stage", <parameters>, "status", "reason", "objective",
    "violation", "score"}``); ``history``: the best score after each generation and then
    after each local step; ``on_bound``: ``{name: "lower" | "upper"}`` for each
    parameter of the best design on a bound of its ``vary`` (within 1e-6 of HI − LO:
    the optimum may lie beyond it); ``files``: what was written."""

    parameters: dict[str, float]
    objective: float
    feasible: bool
    row: dict[str, Any]
    designs: list[dict[str, Any]]
    history: list[tuple[str, int, float]]
    message: str
    on_bound: dict[str, str] = field(default_factory=dict)
    files: dict[str, Path] = field(default_factory=dict)

    def __repr__(self) -> str:
        what = ", ".join(f"{k}={v:.10g}" for k, v in self.parameters.items())
        return (
            f"Optimum({what}; objective {self.objective:.10g}, "
            f"{'feasible' if self.feasible else 'infeasible'}, {len(self.designs)} designs)"
        )


class _Problem:
    """The designs evaluated so far and their scores (one batch per population)."""

    def __init__(self, source, names, objective, constraints, options, executor, workers):
        self.source, self.names = source, list(names)
        self.objective, self.constraints = objective, constraints
        self.options, self.executor, self.workers = options, executor, workers
        self.designs: list[dict[str, Any]] = []
        self.cache: dict[tuple[float, ...], dict[str, Any]] = {}
        # the designs this run has asked for (a resumed run replays the search: the
        # designs read back are in the cache, and enter here as the search reaches them)
        self.visited: dict[tuple[float, ...], dict[str, Any]] = {}
        self.sink = None  # called with the new records of each evaluation (designs.csv)
        self.positions = 1  # of a design's analysis: the chunks in this process fit memory
        self.stage = "initial"
        self.bar = None
        self.pool = None
        self.checked = False
        self.error: OptimizeError | None = None

    def rows(self, overrides: list[dict[str, float]]) -> list[dict[str, Any]]:
        """The batch rows of the designs: one chunk (serial), or chunks on the executor."""

        def chunk(ovs):
            ids = tuple(str(k) for k in range(len(ovs)))
            return Chunk(self.source, ids, tuple(ovs), **self.options)

        if self.executor == "serial" or len(overrides) < 2:
            # a large population in parts, each within a batch chunk's memory bound
            size = auto_chunk(4 * len(overrides), self.positions, 1)
            parts = [overrides[k : k + size] for k in range(0, len(overrides), size)]
            return [r for p in parts for r in analyze_chunk(chunk(p))]
        if self.pool is None:
            self.pool = _open_executor(self.executor, self.workers)
        ex, slots, _ = self.pool
        size = max(1, math.ceil(len(overrides) / slots))
        parts = [overrides[k : k + size] for k in range(0, len(overrides), size)]
        try:
            futures = [ex.submit(analyze_chunk, chunk(p)) for p in parts]
            return [r for f in futures for r in f.result()]
        except Exception as exc:  # noqa: BLE001 - a lost scheduler, a killed worker
            raise OptimizeError(_executor_failed(self.executor, exc)) from None

    def close(self) -> None:
        if self.pool is not None:
            self.pool[2]()

    def evaluate(self, xs: np.ndarray) -> list[dict[str, Any]]:
        """The records of the designs ``xs`` ``(S, n)``, from the cache or analysed."""
        keys = [tuple(float(v) for v in x) for x in xs]
        for k in keys:
            if not all(map(math.isfinite, k)):  # guarded by MAX_BOUND; never analysed
                raise OptimizeError(
                    "optimize: a design that is not finite ("
                    + ", ".join(f"{n}={v!r}" for n, v in zip(self.names, k))
                    + "); narrow the --vary bounds"
                )
        todo = list(dict.fromkeys(k for k in keys if k not in self.cache))
        if todo:
            rows = self.rows([dict(zip(self.names, k)) for k in todo])
            new = []
            for k, row in zip(todo, rows):
                self.cache[k] = self._record(k, row)
                new.append(self.cache[k])
            if self.sink is not None:
                self.sink(new)
        for k in keys:
            self.visited.setdefault(k, self.cache[k])
        return [self.cache[k] for k in keys]

    def load(self, records: Sequence[dict[str, Any]]) -> None:
        """Designs read back from an interrupted run's ``designs.csv``: evaluated, not
        visited yet (their batch rows are not kept; the best design's is computed again)."""
        for rec in records:
            key = tuple(float(rec[n]) for n in self.names)
            self.designs.append(rec)
            self.cache[key] = rec
            if rec["status"] == "ok":
                self.checked = True  # its names were checked when it was evaluated

    def _record(self, key: tuple[float, ...], row: dict[str, Any]) -> dict[str, Any]:

        template = template_of(self.source.file, self.source.text)
        env = {**variant_parameters(template, dict(zip(self.names, key))), **row}
        rec: dict[str, Any] = {"evaluation": len(self.designs) + 1, "stage": self.stage}
        rec.update(zip(self.names, key))
        rec.update(status=row.get("status", "failed"), reason=row.get("reason", ""))
        if rec["status"] == "ok" and not self.checked:  # names checked on the first row
            known = [k for k in env if k not in ("status", "reason")]
            self.objective.check_names(known, "--minimize")
            for c in self.constraints:
                c.check_names(known)
            self.checked = True
        f = self.objective.value(env) if rec["status"] == "ok" else math.nan
        margins = [c.margin(env) for c in self.constraints] if rec["status"] == "ok" else []
        violation = float(sum(max(0.0, -m) if not math.isnan(m) else math.inf for m in margins))
        rec["objective"] = f
        for c, m in zip(self.constraints, margins):
            rec[c.text] = m
        rec["violation"] = violation if rec["status"] == "ok" else math.nan
        if rec["status"] != "ok":
            score = FAILED
        elif math.isnan(f) or math.isinf(violation):
            rec["status"], rec["reason"] = "infeasible", rec["reason"] or "no value"
            score = FAILED / 10
        elif violation > 0.0:
            rec["status"] = "infeasible"
            score = INFEASIBLE * (1.0 + violation)
        else:
            score = f
        rec["score"], rec["margins"], rec["row"] = score, margins, row
        self.designs.append(rec)
        return rec

    def best(self) -> dict[str, Any] | None:
        return min(self.visited.values(), key=lambda r: r["score"], default=None)

    def row_of(self, rec: dict[str, Any]) -> dict[str, Any]:
        """The batch row of a design (analysed again for one read back from disk)."""
        if rec.get("row") is None:
            rec["row"] = self.rows([{n: float(rec[n]) for n in self.names}])[0]
        return rec["row"]


def _source(model_or_path) -> Source:
    """The mechanism file as a batch :class:`~.sources.Source`: a path, or a model read
    from a file (its ``source``)."""
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


def optimize(
    model_or_path,
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
    """Minimise ``minimize`` over the parameters ``vary`` (``{NAME: (LO, HI)}`` in the
    file's units, or ``["NAME=LO:HI", …]``) subject to ``subject_to`` (``"EXPR <= EXPR"``
    or ``>=``); expressions over the batch row's quantities and the file's parameters
    (docs/optimisation.md).  Differential evolution (``seed``, ``maxiter`` generations of
    ``popsize`` × (number of parameters) designs, ``tol``), then a local refinement
    (``polish``: Nelder–Mead, or COBYLA with constraints, at most ``local_maxiter``
    steps).  ``positions``, ``friction``: as for a batch (a ``flywheel:`` of the file is
    sized only when an expression names ``flywheel.…``); ``executor``: ``"serial"``
    (default: each population as one vectorised batch in this process), ``"processes"``
    (a pool of ``workers`` processes), a Dask scheduler address (``"tcp://host:8786"``)
    or a ``concurrent.futures.Executor``, as :func:`~kinetostatics.batch.run_batch`'s:
    each population is cut into one chunk per worker; the result is the same on every
    executor (the local steps run in this process).  ``out``: a folder for
    ``best.yaml``, ``designs.csv`` and ``convergence.png``; ``designs.csv`` is appended
    to as the designs are evaluated, and the same search run again into the same folder
    after an interrupt reuses them (``overwrite``: start afresh in a folder that holds
    another search).  Raises :class:`OptimizeError` for a bad name, expression or
    option and for an objective that has no value at any design, never for a bad
    design."""
    from scipy.optimize import differential_evolution

    _check_ranges(popsize=popsize, maxiter=maxiter, seed=seed)
    if positions is not None:
        _check_ranges(positions=positions)
    source = _source(model_or_path)
    template = template_of(source.file, source.text)
    bounds = parse_vary(vary)
    known = template.parameters
    for name in bounds:
        if name not in known:
            raise OptimizeError(
                f"--vary {name}: the file has no parameter '{name}'"
                f"{' (it has no parameters: section)' if not known else ''}"
                f"{_did_you_mean(name, known)}"
            )
    objective = Expression(minimize)
    constraints = [Constraint.parse(c) for c in subject_to]
    named = [*objective.names.values(), *(n for c in constraints for n in c.names)]
    # the file's flywheel: is sized (variant by variant, slower) only when asked for
    flywheel = None if any(n.startswith("flywheel.") for n in named) else False
    options = {"positions": positions, "friction": friction, "flywheel": flywheel}
    names = list(bounds)
    lo = np.array([bounds[n][0] for n in names])
    hi = np.array([bounds[n][1] for n in names])
    problem = _Problem(source, names, objective, constraints, options, executor, workers)
    problem.positions = positions or template.base.analysis.positions
    history: list[tuple[str, int, float]] = []
    search = {
        "vary": {n: list(bounds[n]) for n in names},
        "minimize": minimize,
        "subject_to": list(subject_to),
        "seed": seed,
        "maxiter": maxiter,
        "popsize": popsize,
        "tol": tol,
        "polish": polish,
        "local_maxiter": local_maxiter,
        "positions": positions,
        "friction": friction,
    }
    with designs_on_disk(out, source, search, names, constraints, overwrite) as disk:
        if disk is not None:
            problem.load(disk.records)
            problem.sink = disk.add
        try:
            message = _run(
                differential_evolution,
                problem,
                known,
                names,
                lo,
                hi,
                history,
                executor,
                workers,
                maxiter=maxiter,
                popsize=popsize,
                tol=tol,
                seed=seed,
                polish=polish,
                local_maxiter=local_maxiter,
                progress=progress,
            )
        except OptimizeError:  # a mistake (an unknown name), found at the first designs
            if disk is not None and not disk.records:  # a fresh search: nothing to resume
                disk.discard()
            raise
        best = problem.best()
        analysed = [r for r in problem.visited.values() if r["status"] != "failed"]
        if all(math.isnan(r["objective"]) for r in analysed):  # a mistake, not a search
            if disk is not None:  # to resume: nothing left
                disk.discard()
            if not analysed:
                vary = " ".join(f"{n}={bounds[n][0]:g}:{bounds[n][1]:g}" for n in names)
                raise OptimizeError(
                    f"--vary {vary}: none of the {len(problem.visited)} designs within these "
                    f"bounds could be analysed (e.g. {best['reason'] or 'failed'})"
                )
            raise OptimizeError(
                f"--minimize {minimize!r}: could not be evaluated at any of the "
                f"{len(analysed)} designs analysed (no finite value: an overflow, a function "
                "outside its domain, or a quantity these designs lack)"
            )
        result = Optimum(
            parameters={n: float(best[n]) for n in names},
            objective=float(best["objective"]),
            feasible=best["status"] == "ok",
            row=dict(problem.row_of(best)),
            designs=problem.designs,
            history=history,
            message=message,
            on_bound=_on_bound(best, names, lo, hi),
        )
        if out is not None:
            result.files = write_outputs(result, source, template, names, constraints, Path(out))
    return result


def _run(
    differential_evolution,
    problem,
    known,
    names,
    lo,
    hi,
    history,
    executor,
    workers,
    *,
    maxiter,
    popsize,
    tol,
    seed,
    polish,
    local_maxiter,
    progress,
) -> str:
    """The search, then the local refinement; their messages."""
    bar = _bar(progress, maxiter + 1 + (local_maxiter if polish else 0))
    try:
        if executor != "serial":  # a scheduler that cannot be reached stops here
            problem.pool = _open_executor(executor, workers)

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

        x0 = np.array([known[n] for n in names], dtype=float)
        try:
            de = _search(
                differential_evolution, population, lo, hi, maxiter, popsize, tol, seed, x0
            )
        except RuntimeError:
            if problem.error is not None:
                raise problem.error from None
            raise
        message = f"differential evolution: {de.message}"

        best = problem.best()
        if polish and best is not None and best["score"] < FAILED:
            problem.stage = "local"
            message += "; " + _local(problem, best, names, lo, hi, local_maxiter, history, bar)
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


def _search(differential_evolution, population, lo, hi, maxiter, popsize, tol, seed, x0):
    """Differential evolution, a generation per call of ``population``; the file's own
    design in the first population when it lies within the bounds."""
    return differential_evolution(
        population,
        list(zip(lo, hi)),
        maxiter=maxiter,
        popsize=popsize,
        tol=tol,
        rng=np.random.default_rng(seed),
        polish=False,
        updating="deferred",
        vectorized=True,
        x0=x0 if np.all((x0 >= lo) & (x0 <= hi)) else None,
    )


def _executor_failed(executor: Any, exc: BaseException) -> str:
    """One line for an executor that failed while evaluating a population."""
    what = (
        f"--scheduler {executor}"
        if isinstance(executor, str) and executor not in ("processes", "serial")
        else "the executor"
    )
    text = str(exc).splitlines()[0] if str(exc) else ""
    return f"{what}: failed ({type(exc).__name__}{': ' + text if text else ''})"


def _did_you_mean(name: str, known) -> str:

    return did_you_mean(name, list(known))


def _local(problem, best, names, lo, hi, maxiter, history, bar) -> str:
    """Refine ``best`` by Nelder–Mead (no constraints) or COBYLA (constraints, and the
    bounds as constraints too), within the bounds; returns the method's message."""
    from scipy.optimize import minimize

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
