"""The designs of an optimisation (:mod:`.optimize`) evaluated so far, and their scores.

:class:`_Problem` evaluates a population of designs by the batch's own path (one chunk in
this process, or chunks on an executor), keeps each design's record (its batch row, the
objective, the constraints' margins, the violation and the score of Deb's rules) and
knows the best design visited.  A design's row holds what the expressions need
(``options["needs"]``, :func:`~.variants.row_needs`: no friction solution when none
names a quantity with friction, no strokes, no located zones); the best design's whole
row is analysed again at the end (:meth:`_Problem.row_of`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .executors import _open_executor, analyze_chunk
from .objectives import FAILED, INFEASIBLE, OptimizeError
from .sources import Chunk, auto_chunk, template_of, variant_parameters

__all__: list[str] = []


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
        self.alone = 0  # designs analysed one by one (outside the vectorised analysis)

    def rows(self, overrides: list[dict[str, float]]) -> list[dict[str, Any]]:
        """The batch rows of the designs, with what the expressions need."""
        return self._rows(overrides, self.options)

    def _rows(self, overrides: list[dict[str, float]], options) -> list[dict[str, Any]]:
        """The batch rows of the designs analysed with ``options``: one chunk (serial), or
        chunks on the executor."""

        def chunk(ovs):
            ids = tuple(str(k) for k in range(len(ovs)))
            return Chunk(self.source, ids, tuple(ovs), **options)

        def counted(rows):
            self.alone += getattr(rows, "alone", 0) if len(rows) > 1 else 0
            return rows

        if self.executor == "serial" or len(overrides) < 2:
            # a large population in parts, each within a batch chunk's memory bound
            size = auto_chunk(4 * len(overrides), self.positions, 1)
            parts = [overrides[k : k + size] for k in range(0, len(overrides), size)]
            return [r for p in parts for r in counted(analyze_chunk(chunk(p)))]
        if self.pool is None:
            self.pool = _open_executor(self.executor, self.workers)
        ex, slots, _ = self.pool
        size = max(1, math.ceil(len(overrides) / slots))
        parts = [overrides[k : k + size] for k in range(0, len(overrides), size)]
        try:
            futures = [ex.submit(analyze_chunk, chunk(p)) for p in parts]
            return [r for f in futures for r in counted(f.result())]
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
            self._check_names([k for k in env if k not in ("status", "reason")], key)
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

    def _check_names(self, known: list[str], key: tuple[float, ...]) -> None:
        """OptimizeError for a name that is neither a quantity of the row nor a parameter;
        a row of what is named has fewer quantities, so the nearest name is looked for
        among the whole row's (the design analysed again, on this error only)."""

        def check(names: list[str]) -> None:
            self.objective.check_names(names, "--minimize")
            for c in self.constraints:
                c.check_names(names)

        try:
            check(known)
        except OptimizeError:
            if self.options.get("needs") is None:
                raise
            design = [dict(zip(self.names, key))]
            whole = self._rows(design, {**self.options, "needs": None})[0]
            check([*known, *(k for k in whole if k not in known)])
            raise

    def best(self) -> dict[str, Any] | None:
        return min(self.visited.values(), key=lambda r: r["score"], default=None)

    def row_of(self, rec: dict[str, Any]) -> dict[str, Any]:
        """The whole batch row of a design, every quantity: analysed again (alone) when
        the search's rows held only what the expressions need, or it was read back from
        disk."""
        if rec.get("row") is None or self.options.get("needs") is not None:
            design = [{n: float(rec[n]) for n in self.names}]
            rec["row"] = self._rows(design, {**self.options, "needs": None})[0]
        return rec["row"]


def _executor_failed(executor: Any, exc: BaseException) -> str:
    """One line for an executor that failed while evaluating a population."""
    what = (
        f"--scheduler {executor}"
        if isinstance(executor, str) and executor not in ("processes", "serial")
        else "the executor"
    )
    text = str(exc).splitlines()[0] if str(exc) else ""
    return f"{what}: failed ({type(exc).__name__}{': ' + text if text else ''})"
