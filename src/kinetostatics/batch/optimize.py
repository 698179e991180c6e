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
last (:data:`FAILED`).  Nothing raises for a bad variant.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..base.document import read_text
from .objectives import FAILED, INFEASIBLE, Constraint, Expression, OptimizeError
from .sources import Chunk, Source, template_of

__all__ = ["optimize", "Optimum", "OptimizeError", "INFEASIBLE", "FAILED", "parse_vary"]


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
    after each local step; ``files``: what was written."""

    parameters: dict[str, float]
    objective: float
    feasible: bool
    row: dict[str, Any]
    designs: list[dict[str, Any]]
    history: list[tuple[str, int, float]]
    message: str
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
        self.stage = "initial"
        self.bar = None
        self.pool = None
        self.checked = False
        self.error: OptimizeError | None = None

    def rows(self, overrides: list[dict[str, float]]) -> list[dict[str, Any]]:
        """The batch rows of the designs: one chunk (serial), or chunks on the executor."""
        from .executors import _open_executor, analyze_chunk

        def chunk(ovs):
            ids = tuple(str(len(self.designs) + k) for k in range(len(ovs)))
            return Chunk(self.source, ids, tuple(ovs), **self.options)

        if self.executor == "serial" or len(overrides) < 2:
            return analyze_chunk(chunk(overrides))
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
        todo = list(dict.fromkeys(k for k in keys if k not in self.cache))
        if todo:
            rows = self.rows([dict(zip(self.names, k)) for k in todo])
            for k, row in zip(todo, rows):
                self.cache[k] = self._record(k, row)
        return [self.cache[k] for k in keys]

    def _record(self, key: tuple[float, ...], row: dict[str, Any]) -> dict[str, Any]:
        from .sources import variant_parameters

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
        violation = sum(max(0.0, -m) if not math.isnan(m) else math.inf for m in margins)
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
        return min(self.designs, key=lambda r: r["score"], default=None)


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
    ``best.yaml``, ``designs.csv`` and ``convergence.png``.  Raises
    :class:`OptimizeError` for a bad name or expression, never for a bad design."""
    from scipy.optimize import differential_evolution

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
    history: list[tuple[str, int, float]] = []
    bar = _bar(progress, maxiter + 1 + (local_maxiter if polish else 0))
    try:
        if executor != "serial":  # a scheduler that cannot be reached stops here
            from .executors import _open_executor

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
    best = problem.best()
    result = Optimum(
        parameters={n: float(best[n]) for n in names},
        objective=float(best["objective"]),
        feasible=best["status"] == "ok",
        row=dict(best["row"]),
        designs=problem.designs,
        history=history,
        message=message,
    )
    if out is not None:
        from .optimize_files import write_outputs

        result.files = write_outputs(result, source, template, names, constraints, Path(out))
    return result


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
    from ..errors import did_you_mean

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
