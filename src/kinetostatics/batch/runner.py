"""Batches: many variants of one file (or every file of a folder) analysed in
chunks, one summary table.

:func:`run_batch` cuts the variants into memory-bounded chunks of one source
file, hands each chunk to :func:`analyze_chunk` (which calls
:func:`kinetostatics.batch.variants.analyze_variants`) through a
``concurrent.futures`` executor — processes by default, in-process
(``"serial"``), or a Dask cluster given by its scheduler address — and
appends each finished chunk's rows to ``DIR/summary.csv`` (flushed and
synced), so an interrupted batch leaves its finished rows on disk.  Rows are
appended in completion order; when the batch ends (or is interrupted) the file
is rewritten in variant order.  A rerun with the same files, sweep and options
(``DIR/batch.json`` holds their fingerprint) skips the variants already in the
table.  A variant that fails is a row with ``status = failed`` and its reason;
a chunk whose worker raised (a crash) gives rows with ``status = error``,
which a rerun computes again; a chunk whose worker process died is submitted
again to a fresh pool.  Workers die with the batch, even a killed one.  Only one
batch writes to an output folder at a time (``DIR/batch.lock``).  Nothing stops
the batch but an interrupt or an environment failure (a full disk, a folder
that cannot be written, a lost Dask scheduler: :class:`OutputError`, one line);
the rows on disk then stay valid and the same batch resumes.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import (
    FIRST_COMPLETED,
    BrokenExecutor,
    CancelledError,
    Future,
    wait,
)
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..base.files import make_folder
from ..errors import output_error
from .executors import _executor_error, _Pool, analyze_chunk
from .sources import (
    BYTES_PER_POSITION,
    BatchError,
    Chunk,
    Source,
    Task,
    _check_names,
    _chunks,
    _one_per_file,
    _templates,
    auto_chunk,
    sources_of,
    variant_parameters,
)
from .table import (
    STATE,
    SUMMARY,
    _cell,
    _fingerprint,
    _Lock,
    _start_table,
    _Table,
    _write_state,
)

__all__ = ["BatchOptions", "BatchSummary", "run_batch"]

# A chunk whose worker process died (killed, out of memory) is submitted again
# to a fresh pool, at most this many times in all, before its rows are errors.
ATTEMPTS = 3


@dataclass
class BatchSummary:
    """What a batch did: rows in the table, computed now, reused from before."""

    out_dir: Path
    total: int
    computed: int
    reused: int
    failed: int
    errors: int
    seconds: float
    chunk: int
    workers: int
    alone: int = 0  # variants computed one by one, outside the vectorised analysis

    @property
    def summary_csv(self) -> Path:
        return self.out_dir / SUMMARY

    @property
    def rate(self) -> float:
        """Variants computed per second of this run."""
        return self.computed / self.seconds if self.seconds > 0 else math.nan


def _error_row(exc: BaseException) -> dict[str, Any]:
    text = str(exc).splitlines()[0] if str(exc) else ""
    return {
        "status": "error",
        "reason": f"{type(exc).__name__}: {text}".rstrip(": "),
        "full_cycle": False,
    }


# -- progress --------------------------------------------------------------------------
class _Progress:
    """The progress bar on stderr (tqdm): done/total, variants/s, ETA, failures."""

    def __init__(self, total: int, done: int, enabled: bool, stream=None):
        from tqdm import tqdm

        self.failed = 0
        self.bar = tqdm(
            total=total,
            initial=done,
            desc="batch",
            unit=" variants",
            file=stream or sys.stderr,
            disable=not enabled,
            mininterval=0.2,
            dynamic_ncols=True,
        )

    def update(self, n: int, failed: int) -> None:
        self.failed += failed
        if failed:
            self.bar.set_postfix(failed=self.failed, refresh=False)
        self.bar.update(n)

    def close(self) -> None:
        self.bar.close()


# -- the batch -------------------------------------------------------------------------
@dataclass(frozen=True)
class BatchOptions:
    """How a batch runs: the keywords of :func:`run_batch` as one record.

    ``positions``, ``friction``, ``flywheel`` are the analysis's (part of the batch's
    fingerprint); the others say how it runs (``chunk``, ``executor``, ``workers``,
    ``progress``, ``on_chunk``), what it writes (``results``) and whether it may replace
    another batch (``overwrite``)."""

    chunk: int | None = None
    executor: Any = None
    workers: int | None = None
    positions: int | None = None
    friction: bool | None = None
    flywheel: bool | None = None
    results: bool = False
    progress: bool | None = None
    overwrite: bool = False
    on_chunk: Callable[[int], None] | None = None

    @property
    def analysis(self) -> dict[str, Any]:
        """The options that change the rows (``batch.json``'s ``options``)."""
        return {"positions": self.positions, "friction": self.friction, "flywheel": self.flywheel}


@dataclass(frozen=True)
class _Plan:
    """A batch's inputs, checked: the files, the variants and their templates (a
    template that could not be read is its error), each variant's place in the table
    (``order``), and the state ``batch.json`` starts from with its ``fingerprint``."""

    sources: list[Source]
    tasks: list[Task]
    templates: list
    order: dict[str, int]
    state: dict[str, Any]
    fingerprint: str


def run_batch(  # noqa: PLR0913  the public keywords (docs/batch.md, the CLI); they build BatchOptions
    sources: Sequence[Source] | str | Path,
    tasks: Sequence[Task] | None,
    out_dir: str | Path,
    *,
    chunk: int | None = None,
    executor: Any = None,
    workers: int | None = None,
    positions: int | None = None,
    friction: bool | None = None,
    flywheel: bool | None = None,
    results: bool = False,
    progress: bool | None = None,
    overwrite: bool = False,
    on_chunk: Callable[[int], None] | None = None,
) -> BatchSummary:
    """Analyse ``tasks`` (default: each source as written, id = file stem) and
    write ``out_dir/summary.csv`` (one row per task, in task order) and
    ``out_dir/batch.json``.

    Parameters
    ----------
    sources : the mechanism files (:func:`sources_of`), or a file/folder path.
    tasks : the variants; ``Task.source`` indexes ``sources``.
    chunk : variants per chunk (default :func:`auto_chunk`).
    executor : ``"processes"`` (default; ``workers`` processes, default the number
        of cores), ``"serial"`` (in this process), a Dask scheduler address
        (``"tcp://host:8786"``), or any ``concurrent.futures.Executor``.
    positions, friction, flywheel : as :func:`variants.analyze_variants`.
    results : also write ``out_dir/variants/<id>/results.csv`` and ``summary.json``.
    progress : the progress bar on stderr (default: when stderr is a terminal).
    overwrite : start afresh in a folder that holds another batch.
    on_chunk : called with the number of rows done after each chunk (a test
        hook: raising there interrupts the batch like Ctrl-C).

    Rows already in ``summary.csv`` from an interrupted run of the same batch
    are kept and not computed again.  Raises :class:`BatchError` if ``out_dir``
    holds a different batch (unless ``overwrite``), if another batch is writing
    to it, or if the variants or one variant's positions would not fit in the
    memory available; :class:`OutputError` if ``out_dir`` cannot be written
    (a file, no permission, a full disk) or the executor fails as a whole.
    """
    t_start = time.perf_counter()
    opts = BatchOptions(
        chunk=chunk,
        executor=executor,
        workers=workers,
        positions=positions,
        friction=friction,
        flywheel=flywheel,
        results=results,
        progress=progress,
        overwrite=overwrite,
        on_chunk=on_chunk,
    )
    plan = _plan(sources, tasks, opts)
    out = Path(out_dir)
    where = f"--out {out_dir}"
    make_folder(out, where)
    lock = _Lock(out)
    try:
        lock.acquire()
    except OSError as exc:
        raise output_error(exc, where) from None
    try:
        return _run_locked(plan, out, where, opts, t_start)
    finally:
        lock.release()


def _plan(sources: Sequence[Source] | str | Path, tasks, opts: BatchOptions) -> _Plan:
    """The batch's inputs read and checked before anything is written: unique variant
    ids, known parameter names, a ``flywheel:`` where ``--flywheel`` asks for one, and the
    memory of the table and of one variant's analysis per worker."""
    if isinstance(sources, (str, Path)):
        sources = sources_of(sources)
    sources = list(sources)
    if tasks is None:
        tasks = _one_per_file(sources)
    tasks = list(tasks)
    _check_memory(len(tasks), None, 1)
    options = opts.analysis
    fingerprint = _fingerprint(sources, tasks, options)
    state = {
        "fingerprint": fingerprint,
        "variants": len(tasks),
        "sources": [s.file for s in sources],
        "options": options,
        "computed": 0,
        "runs": [],
    }
    order = {t.vid: k for k, t in enumerate(tasks)}
    if len(order) != len(tasks):
        raise BatchError("variant ids are not unique")
    templates = _templates(sources)
    _check_names(tasks, sources, templates)
    for source, tpl in zip(sources, templates):
        if opts.flywheel and not isinstance(tpl, BaseException) and tpl.base.flywheel is None:
            raise BatchError(
                f"{source.file}: --flywheel needs a flywheel: {{delta: ...}} "
                "section in the file (docs/dynamics.md)"
            )
    n_pos = _positions(opts, templates, None)
    workers = opts.workers or os.cpu_count() or 1
    _check_memory(
        0,
        n_pos,
        workers if opts.executor in (None, "processes") else 1,
        bool(opts.positions),
    )
    return _Plan(sources, tasks, templates, order, state, fingerprint)


def _check_memory(n_tasks: int, positions: int | None, workers: int, option: bool = True) -> None:
    """Refuse, before any allocation, a batch whose table or one variant's analysis
    would not fit in the memory available (``limits.available_memory``)."""
    from .limits import BYTES_PER_VARIANT, available_memory, gigabytes

    free = available_memory()
    need = n_tasks * BYTES_PER_VARIANT
    if need > free:
        raise BatchError(
            f"{n_tasks} variants: the table needs about {gigabytes(need)} of "
            f"memory, more than the {gigabytes(free)} available; split the sweep "
            "into several batches (one --out each)"
        )
    if positions and positions * BYTES_PER_POSITION * workers > free:
        raise BatchError(
            f"{'--positions' if option else 'analysis.positions'} {positions}: "
            f"one variant at {positions} positions needs about "
            f"{gigabytes(positions * BYTES_PER_POSITION)} of memory per worker "
            f"({workers} at once), more than the {gigabytes(free)} available"
        )


def _run_locked(
    plan: _Plan, out: Path, where: str, opts: BatchOptions, t_start: float
) -> BatchSummary:
    """The batch, with ``out`` locked: resume or start the table, run the chunks."""
    from .variants import failure_row

    tasks, templates = plan.tasks, plan.templates
    table = _Table(out / SUMMARY, plan.order)
    state = _start_table(table, out / STATE, plan.state, plan.fingerprint, opts.overwrite, where)
    reused = len(table.rows)

    todo = [t for t in tasks if t.vid not in table.rows]
    broken = [t for t in todo if isinstance(templates[t.source], BaseException)]
    todo = [t for t in todo if not isinstance(templates[t.source], BaseException)]
    bar = _Progress(
        len(tasks), reused, sys.stderr.isatty() if opts.progress is None else opts.progress
    )
    alone = [0]

    def record(part: Sequence[Task], rows: Sequence[Mapping[str, Any]]) -> None:
        """A chunk's rows into the table, and the progress bar on."""
        parameters = getattr(rows, "parameters", None)
        alone[0] += getattr(rows, "alone", 0)
        bar.update(len(part), _record(table, templates, where, list(zip(part, rows)), parameters))

    if broken:
        record(broken, [failure_row(templates[t.source]) for t in broken])
    pool = _Pool(opts.executor, opts.workers)
    size = opts.chunk or auto_chunk(len(todo), _positions(opts, templates, 1), pool.slots)
    job = _chunk_job(plan.sources, opts, str(out / "variants") if opts.results else None)

    def after_chunk() -> None:
        if opts.on_chunk is not None:
            opts.on_chunk(len(table.rows))

    log = _RunLog(out / STATE, state, reused, time.perf_counter(), size, where)
    failure: BaseException | None = None
    try:
        _drain(pool, _chunks(todo, size), job, record, out, after_chunk)
    except BaseException as exc:
        failure = exc
        raise
    finally:
        computed = _finish(pool, bar, table, log, alone[0], failure)
    statuses = [r.get("status") for r in table.rows.values()]
    return BatchSummary(
        out,
        len(tasks),
        computed,
        reused,
        statuses.count("failed"),
        statuses.count("error"),
        time.perf_counter() - t_start,
        size,
        pool.slots,
        alone[0],
    )


def _positions(opts: BatchOptions, templates, default: int | None) -> int | None:
    """The positions of one variant's analysis: ``opts.positions``, or the most any file
    asks for (``default`` if none could be read)."""
    return opts.positions or max(
        (tpl.base.analysis.positions for tpl in templates if not isinstance(tpl, BaseException)),
        default=default,
    )


def _chunk_job(sources: list[Source], opts: BatchOptions, results_dir: str | None):
    """The function making the :class:`~.sources.Chunk` of a part of the variants (all of
    one source file) that a worker analyses."""

    def job(part: list[Task]) -> Chunk:
        return Chunk(
            sources[part[0].source],
            tuple(t.vid for t in part),
            tuple(dict(t.overrides) for t in part),
            opts.positions,
            opts.friction,
            opts.flywheel,
            results_dir,
        )

    return job


def _drain(pool: _Pool, parts, job, record, out: Path, after_chunk) -> None:
    """Submit the chunks ``parts`` and record their rows until none is left or pending."""
    pending: dict[Future, tuple[list[Task], int]] = {}
    retry: list[tuple[list[Task], int]] = []
    it = iter(parts)
    while True:
        _submit(pool, pending, retry, it, job, record, out)
        if not pending:
            break
        _collect(pool, pending, retry, record, out, after_chunk)


def _record(table: _Table, templates, where: str, task_rows, parameters=None) -> int:
    """Append finished variants' rows, with their parameters, to the table; the
    number of rows that are not ``ok``.  ``parameters``: the variants' as their models have
    them (:class:`~kinetostatics.batch.executors.ChunkRows`), evaluated here where None."""
    cells = []
    for k, (task, row) in enumerate(task_rows):
        tpl = templates[task.source]
        params = parameters[k] if parameters is not None else None
        if params is None:
            params = (
                {} if isinstance(tpl, BaseException) else variant_parameters(tpl, task.overrides)
            )
        text = {
            "variant": task.vid,
            **{k: _cell(v) for k, v in params.items()},
            **{k: _cell(v) for k, v in row.items()},
        }
        cells.append((text, params))
    try:
        table.add(cells)
    except OSError as exc:  # a full disk: stop; the rows on disk stay valid
        raise output_error(exc, where) from None
    return sum(r.get("status") != "ok" for _, r in task_rows)


def _submit(pool: _Pool, pending, retry, parts, job, record, out: Path) -> None:
    """Submit chunks, those to retry first, until two per slot are pending."""
    while len(pending) < 2 * pool.slots and (
        (
            nxt := retry.pop()
            if retry
            else ((p, 1) if (p := next(parts, None)) is not None else None)
        )
        is not None
    ):
        part, attempt = nxt
        chunk = job(part)
        try:
            pending[pool.ex.submit(analyze_chunk, chunk)] = (part, attempt)
        except BrokenExecutor:
            retry.append((part, attempt))
            pool.reopen()
        except Exception as exc:  # noqa: BLE001 - the executor itself failed
            for f in [
                f for f in pending if f.done() and not f.cancelled() and f.exception() is None
            ]:
                part, _ = pending.pop(f)  # keep the rows already computed
                if len(rows := f.result()) == len(part):
                    record(part, rows)
            raise _executor_error(pool.executor, exc, out) from None


def _collect(pool: _Pool, pending, retry, record, out: Path, after_chunk) -> None:
    """Wait for chunks to finish and record their rows (a crash's rows are errors);
    a chunk whose worker died goes again, with the others of its pool, to a fresh pool."""
    try:
        done, _ = wait(list(pending), return_when=FIRST_COMPLETED)
    except Exception as exc:  # noqa: BLE001
        raise _executor_error(pool.executor, exc, out) from None
    lost = False
    for f in done:
        part, attempt = pending.pop(f)
        try:
            rows = f.result()
            if len(rows) != len(part):
                raise RuntimeError(f"{len(rows)} rows for {len(part)} variants")
        except CancelledError as exc:  # not by us: the executor gave up (a lost
            raise _executor_error(pool.executor, exc, out) from None  # scheduler)
        except BrokenExecutor as exc:  # its worker died: again, in a fresh pool
            lost = True
            if attempt < ATTEMPTS and pool.processes:
                retry.append((part, attempt + 1))
                continue
            rows = [_error_row(exc) for _ in part]
        except Exception as exc:  # noqa: BLE001 - a chunk's crash is its rows' error
            rows = [_error_row(exc) for _ in part]
        record(part, rows)
        after_chunk()
    if lost and pool.processes:
        for f, job in list(pending.items()):  # the others in the broken pool
            if f.done() and isinstance(f.exception(), BrokenExecutor):
                pending.pop(f)
                retry.append(job)
        pool.reopen()


@dataclass(frozen=True)
class _RunLog:
    """What ``batch.json`` records of a run: where it is, the state read at the start,
    the rows reused, when the chunks started, their size, and the ``--out`` for messages."""

    state_path: Path
    state: dict[str, Any]
    reused: int
    t_run: float
    size: int
    where: str


def _finish(pool: _Pool, bar, table: _Table, log: _RunLog, alone: int, failure) -> int:
    """Close the executor and the bar, add this run to ``batch.json`` and rewrite the
    table in variant order; the number of rows computed now."""
    state, reused = log.state, log.reused
    try:
        pool.close()
    except Exception:  # noqa: BLE001 - e.g. a Dask client already lost
        pass
    bar.close()
    seconds = time.perf_counter() - log.t_run
    computed = len(table.rows) - reused  # rows written now (an interrupt may fall anywhere)
    state["computed"] = state.get("computed", 0) + computed
    state["runs"] = [
        *state.get("runs", []),
        {
            "computed": computed,
            "alone": alone,
            "reused": reused,
            "seconds": round(seconds, 3),
            "chunk": log.size,
            "workers": pool.slots,
            "executor": pool.executor
            if isinstance(pool.executor, (str, type(None)))
            else type(pool.executor).__name__,
        },
    ]
    try:
        table.rewrite()
        _write_state(log.state_path, state)
    except OSError as exc:
        # the appended rows stay on disk, each whole or recognisably cut; the
        # first failure is the one reported
        if failure is None:
            raise output_error(exc, log.where) from None
    return computed
