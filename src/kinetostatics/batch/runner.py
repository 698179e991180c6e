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

import csv
import errno
import hashlib
import io
import json
import math
import os
import sys
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import (
    FIRST_COMPLETED,
    BrokenExecutor,
    CancelledError,
    Executor,
    Future,
    wait,
)
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from ..base.files import make_folder, write_whole
from ..base.spec import read_text
from ..base.tables import write_table
from ..errors import KinetostaticsError, OutputError, output_error

__all__ = [
    "template_of",
    "Source",
    "Task",
    "Chunk",
    "BatchSummary",
    "BatchError",
    "run_batch",
    "analyze_chunk",
    "sources_of",
    "read_summary",
    "auto_chunk",
    "MEMORY_BUDGET",
    "BYTES_PER_POSITION",
]

SUMMARY = "summary.csv"
STATE = "batch.json"
LOCK = "batch.lock"
# A chunk whose worker process died (killed, out of memory) is submitted again
# to a fresh pool, at most this many times in all, before its rows are errors.
ATTEMPTS = 3
FIXED = ("status", "reason")
# Memory bound of one chunk: a variant costs about BYTES_PER_POSITION per
# position while it is analysed (result columns, q, q', q'', reactions).
MEMORY_BUDGET = 256 * 2**20
BYTES_PER_POSITION = 8 * 2**10
# Larger chunks gain nothing: the vectorised analysis of the slotting machine
# at 72 positions runs fastest per variant around 125 variants a chunk (one
# process: 370 variants/s at 125, 312 at 250, 283 at 1,000, 241 at 2,000).
MAX_CHUNK = 125


class BatchError(KinetostaticsError, ValueError):
    """A batch that cannot start (an output folder of another batch, a bad option)."""


@dataclass(frozen=True)
class Source:
    """A mechanism file as read when the batch started."""

    file: str
    text: str
    problem: KinetostaticsError | None = None  # why the file could not be read


@dataclass(frozen=True)
class Task:
    """One variant: its id, its source (index into the sources) and overrides."""

    vid: str
    source: int
    overrides: Mapping[str, float]


@dataclass(frozen=True)
class Chunk:
    """What a worker analyses: variants of one file, and the analysis options."""

    source: Source
    ids: tuple[str, ...]
    overrides: tuple[Mapping[str, float], ...]
    positions: int | None = None
    friction: bool | None = None
    flywheel: bool | None = None
    results_dir: str | None = None


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

    @property
    def summary_csv(self) -> Path:
        return self.out_dir / SUMMARY

    @property
    def rate(self) -> float:
        """Variants computed per second of this run."""
        return self.computed / self.seconds if self.seconds > 0 else math.nan


# -- the worker ------------------------------------------------------------------------
@lru_cache(maxsize=16)
def template_of(file: str, text: str):
    from .variants import Template

    return Template.loads(text, file)


def analyze_chunk(chunk: Chunk) -> list[dict[str, Any]]:
    """The rows of a chunk, in order (the function every executor runs).
    With ``results_dir`` it also writes ``<results_dir>/<id>/results.csv`` and
    ``summary.json`` of each variant that succeeded (a second, single analysis)."""
    from . import variants

    try:
        template = template_of(chunk.source.file, chunk.source.text)
    except KinetostaticsError as exc:
        return [variants.failure_row(exc) for _ in chunk.ids]
    rows = variants.analyze_variants(
        template,
        chunk.overrides,
        positions=chunk.positions,
        friction=chunk.friction,
        flywheel=chunk.flywheel,
    )
    if chunk.results_dir:
        from ..analysis.pipeline import analyze

        for vid, ov, row in zip(chunk.ids, chunk.overrides, rows):
            if row["status"] == "ok":
                result = analyze(
                    template.model(ov, positions=chunk.positions), friction=chunk.friction
                )
                folder = Path(chunk.results_dir) / vid
                folder.mkdir(parents=True, exist_ok=True)
                result.to_csv(folder / "results.csv")
                result.to_json(folder / "summary.json")
    return rows


def _error_row(exc: BaseException) -> dict[str, Any]:
    text = str(exc).splitlines()[0] if str(exc) else ""
    return {
        "status": "error",
        "reason": f"{type(exc).__name__}: {text}".rstrip(": "),
        "full_cycle": False,
    }


# -- executors -------------------------------------------------------------------------
def _die_with_parent(parent: int) -> None:
    """Pool initializer: a worker dies with the batch that started it, even when
    the batch is killed (SIGKILL runs no clean-up).  On Linux the kernel sends
    SIGKILL at the parent's death (``prctl(PR_SET_PDEATHSIG)``); everywhere a
    daemon thread checks once a second that the parent is still there."""
    import threading

    if sys.platform.startswith("linux"):
        try:
            import ctypes
            import signal

            ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):  # pragma: no cover - no libc prctl
            pass
    if os.getppid() != parent:  # the parent died before prctl
        os._exit(1)

    def watch() -> None:
        while True:
            time.sleep(1.0)
            if os.getppid() != parent:
                os._exit(1)

    threading.Thread(target=watch, name="kinetostatics-parent-watch", daemon=True).start()


class _Serial(Executor):
    """Runs each call when it is submitted, in this process."""

    def submit(self, fn, /, *args, **kwargs) -> Future:
        f: Future = Future()
        try:
            f.set_result(fn(*args, **kwargs))
        except Exception as exc:  # noqa: BLE001 - reported as the chunk's rows
            f.set_exception(exc)
        return f


def _open_executor(executor: Any, workers: int | None) -> tuple[Executor, int, Callable[[], None]]:
    """(executor, number of parallel slots, close)."""
    if executor == "serial":
        return _Serial(), 1, lambda: None
    if executor in (None, "processes"):
        from concurrent.futures import ProcessPoolExecutor

        n = workers or os.cpu_count() or 1
        ex = ProcessPoolExecutor(
            max_workers=n, initializer=_die_with_parent, initargs=(os.getpid(),)
        )
        return ex, n, lambda: ex.shutdown(wait=False, cancel_futures=True)
    if isinstance(executor, Executor):
        return executor, workers or os.cpu_count() or 1, lambda: None
    if isinstance(executor, str):
        try:
            from distributed import Client
        except ImportError:
            raise BatchError(
                f"--scheduler {executor}: Dask is not installed (pip install 'kinetostatics[dask]')"
            ) from None
        try:
            client = Client(executor, timeout=10)
        except (OSError, TimeoutError) as exc:
            raise BatchError(f"--scheduler {executor}: cannot connect ({exc})") from None
        n = workers or max(1, sum(client.nthreads().values()))
        ex = client.get_executor()

        def close() -> None:
            ex.shutdown(wait=False)
            client.close()

        return ex, n, close
    raise BatchError(
        f"executor {executor!r}: use 'processes', 'serial', a Dask scheduler "
        "address or a concurrent.futures.Executor"
    )


def auto_chunk(n_todo: int, positions: int, workers: int) -> int:
    """Variants per chunk: at most MEMORY_BUDGET of work per chunk and
    MAX_CHUNK variants, and at least four chunks per worker so the load
    balances and progress shows.

    >>> auto_chunk(10_000, 72, 2), auto_chunk(10, 72, 2), auto_chunk(10**6, 3600, 2)
    (125, 2, 9)
    """
    cap = max(1, min(MAX_CHUNK, MEMORY_BUDGET // (max(positions, 1) * BYTES_PER_POSITION)))
    return max(1, min(cap, math.ceil(n_todo / (4 * max(workers, 1)))))


# -- the table on disk -----------------------------------------------------------------
def _cell(v: Any) -> str:
    """A CSV cell: numbers at full precision, NaN empty, booleans True/False.

    >>> [_cell(x) for x in (np.float64(0.1), np.nan, np.True_, np.int64(3), "a–b", None)]
    ['0.1', '', 'True', '3', 'a–b', '']
    """
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "True" if v else "False"
    if isinstance(v, str):
        return v
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    x = float(v)
    return "" if math.isnan(x) else repr(x)


def column_unit(name: str, params: Iterable[str] = ()) -> str:
    """The unit of a summary column: ``file`` for a parameter (the file's units),
    :data:`variants.ROW_UNITS` for a metric, N·m / N for a driver effort."""
    from .variants import ROW_UNITS

    if name in params:
        return "file"
    if name == "full_cycle":
        return "bool"
    quantity = name.rsplit(".", 1)[-1]
    if quantity in ROW_UNITS:
        return ROW_UNITS[quantity]
    if quantity.startswith("torque"):
        return "N*m"
    if quantity.startswith("force"):
        return "N"
    return ""


def read_summary(path: str | Path) -> tuple[list[str], list[dict[str, str]]]:
    """(header, rows as text) of a summary table; a row cut short by a kill or a
    full disk is left out.  Every row is written with its line end, the row's
    sentinel: rows are only ever appended, so only the last line can be cut, and
    it was cut exactly when its line end is missing (even if the cut fell inside
    its last cell, where the cells still count right).  A row with another
    number of cells than the header is left out too."""
    lines = Path(path).read_text(encoding="utf-8").splitlines(keepends=True)
    if lines and not lines[-1].endswith("\n"):
        lines.pop()  # its end never reached the disk
    lines = [line for line in lines if not line.startswith("#")]
    reader = csv.reader(lines)
    header = next(reader, [])
    rows = [dict(zip(header, cells)) for cells in reader if len(cells) == len(header)]
    return header, rows


class _Table:
    """``summary.csv``: rows appended as chunks finish, the header grown (and
    the file rewritten) when a row brings a new column."""

    def __init__(self, path: Path, order: Mapping[str, int]):
        self.path, self.order = path, order
        self.params: list[str] = []
        self.metrics: list[str] = []
        self.rows: dict[str, dict[str, str]] = {}

    @property
    def columns(self) -> list[str]:
        return ["variant", *self.params, *FIXED, *self.metrics]

    def _learn(self, row: Mapping[str, str], params: Iterable[str]) -> bool:
        new = False
        for k in params:
            if k not in self.params:
                self.params.append(k)
                new = True
        for k in row:
            if k not in self.params and k not in FIXED and k != "variant" and k not in self.metrics:
                self.metrics.append(k)
                new = True
        return new

    def resume(self) -> None:
        header, rows = read_summary(self.path)
        if "status" in header:
            k = header.index("status")
            self.params = [h for h in header[1:k]]
        for row in rows:
            if row.get("variant") in self.order and row.get("status") != "error":
                self._learn(row, ())
                self.rows[row["variant"]] = row
        self.rewrite()

    def _text(self, rows: Iterable[Mapping[str, str]], header: bool) -> str:
        buf = io.StringIO()
        columns = self.columns
        units = [column_unit(c, self.params) for c in columns] if header else []
        cells = ([row.get(c, "") for c in columns] for row in rows)
        write_table(buf, columns, units, cells, header=header, lineterminator="\n")
        return buf.getvalue()

    @staticmethod
    def _write(path: Path, text: str, mode: str) -> None:
        with open(path, mode, encoding="utf-8", newline="") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())

    def add(self, rows: Sequence[tuple[dict[str, str], Iterable[str]]]) -> None:
        grown = False
        for row, params in rows:
            grown |= self._learn(row, params)
            self.rows[row["variant"]] = row
        if grown or not self.path.exists():
            self.rewrite()
        else:
            self._write(self.path, self._text([r for r, _ in rows], header=False), "a")

    def rewrite(self) -> None:
        ordered = sorted(self.rows.values(), key=lambda r: self.order.get(r["variant"], 0))
        _replace(self.path, self._text(ordered, header=True), self._write)


def _replace(path: Path, text: str, write: Callable[[Path, str, str], None]) -> None:
    """Write ``text`` to ``path`` whole or not at all
    (:func:`~kinetostatics.base.files.write_whole`)."""
    write_whole(path, lambda tmp: write(tmp, text, "w"))


def _write_state(path: Path, state: Mapping) -> None:
    _replace(path, json.dumps(state, indent=1), _Table._write)


def _read_state(path: Path) -> dict:
    try:
        state = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return state if isinstance(state, dict) else {}


# -- one batch per output folder -------------------------------------------------------
class _Lock:
    """``DIR/batch.lock``: one batch writes to a folder at a time.  The lock is an
    advisory ``flock`` on that file, which the system releases when its process
    dies however it dies, so the lock of a killed batch is simply taken over; the
    file names the holder (pid, host, start time) for the message to the second."""

    def __init__(self, folder: Path):
        self.path = folder / LOCK
        self.fd: int | None = None

    def acquire(self) -> None:
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX
            fcntl = None
        for _ in range(10):
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
            try:
                if fcntl is not None:
                    try:
                        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                    except OSError as exc:  # a file system without flock (some NFS)
                        if exc.errno not in (errno.ENOLCK, errno.EOPNOTSUPP, errno.EINVAL):
                            raise
                        if not self._stale(fd):
                            raise BlockingIOError from None
                elif not self._stale(fd):  # pragma: no cover
                    raise BlockingIOError
            except BlockingIOError:
                holder = os.read(fd, 200).decode("utf-8", "replace").strip()
                os.close(fd)
                raise BatchError(
                    f"{self.path.parent}: another batch is writing to this "
                    f"folder ({holder or 'batch.lock is held'}); wait for it "
                    "to finish, or use another --out"
                ) from None
            except BaseException:
                os.close(fd)
                raise
            try:  # the file may have been removed meanwhile
                same = os.stat(self.path).st_ino == os.fstat(fd).st_ino
            except FileNotFoundError:
                same = False
            if same:
                self.fd = fd
                os.ftruncate(fd, 0)
                os.write(
                    fd,
                    (
                        f"pid {os.getpid()} on {_host()} since "
                        f"{time.strftime('%Y-%m-%d %H:%M:%S')}\n"
                    ).encode(),
                )
                return
            os.close(fd)
        raise BatchError(f"{self.path}: cannot take the lock")  # pragma: no cover

    def _stale(self, fd: int) -> bool:  # pragma: no cover - without flock
        words = os.read(fd, 200).decode("utf-8", "replace").split()
        os.lseek(fd, 0, os.SEEK_SET)
        try:
            os.kill(int(words[1]), 0)
        except (IndexError, ValueError, ProcessLookupError):
            return True
        except PermissionError:
            return False
        return False

    def release(self) -> None:
        if self.fd is None:
            return
        try:
            self.path.unlink()
        except OSError:
            pass
        os.close(self.fd)  # releases the flock
        self.fd = None


def _host() -> str:
    import socket

    return socket.gethostname()


# -- parameters of a variant -----------------------------------------------------------
def variant_parameters(template, overrides: Mapping[str, float]) -> dict[str, float]:
    """All the file's parameters evaluated for a variant (file units); only the
    overrides when the values cannot be evaluated (the row then says why)."""
    from ..base.expressions import evaluate_parameters

    if not overrides:
        return template.parameters
    section = template.tree.get("parameters")
    items = [(k, overrides[k] if k in overrides else e.node.value) for k, e in section.items()]
    try:
        return evaluate_parameters(items)
    except (KinetostaticsError, ValueError, ArithmeticError):
        return dict(overrides)


# -- sources ---------------------------------------------------------------------------
def sources_of(path: str | Path) -> list[Source]:
    """The mechanism file, or every ``*.yaml``/``*.yml`` of a folder (sorted)."""
    p = Path(path)
    if p.is_dir():
        files = sorted([*p.glob("*.yaml"), *p.glob("*.yml")])
        if not files:
            raise BatchError(f"{path}: no *.yaml files in this folder")
    elif p.is_file():
        return [Source(str(p), read_text(p))]
    else:
        raise BatchError(f"{path}: no such file or folder")
    out = []
    for f in files:  # in a folder, an unreadable file is a row with its reason
        try:
            out.append(Source(str(f), read_text(f)))
        except KinetostaticsError as exc:
            out.append(Source(str(f), "", exc))
    return out


def _fingerprint(sources: Sequence[Source], tasks: Sequence[Task], options: Mapping) -> str:
    h = hashlib.sha256()
    h.update(json.dumps([[s.file, s.text] for s in sources]).encode())
    h.update(json.dumps([[t.vid, t.source, sorted(t.overrides.items())] for t in tasks]).encode())
    h.update(json.dumps(options, sort_keys=True).encode())
    return h.hexdigest()


# -- progress --------------------------------------------------------------------------
class _Progress:
    """A one-line progress bar on stderr: done/total, variants/s, ETA, failures."""

    def __init__(self, total: int, done: int, enabled: bool, stream=None):
        self.total, self.start_done, self.done = total, done, done
        self.enabled, self.stream = enabled, stream or sys.stderr
        self.t0 = self.last = time.perf_counter()
        self.failed = 0

    def update(self, n: int, failed: int) -> None:
        self.done += n
        self.failed += failed
        now = time.perf_counter()
        if self.enabled and (now - self.last > 0.2 or self.done == self.total):
            self.last = now
            rate = (self.done - self.start_done) / max(now - self.t0, 1e-9)
            eta = (self.total - self.done) / rate if rate > 0 else math.inf
            frac = self.done / self.total if self.total else 1.0
            bar = "#" * int(30 * frac)
            eta_s = time.strftime("%H:%M:%S", time.gmtime(eta)) if math.isfinite(eta) else "?"
            self.stream.write(
                f"\rbatch [{bar:<30}] {self.done}/{self.total} {100 * frac:3.0f}% "
                f"{rate:7.1f} variants/s ETA {eta_s} failed {self.failed} "
            )
            self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()


# -- the batch -------------------------------------------------------------------------
def run_batch(
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
    if isinstance(sources, (str, Path)):
        sources = sources_of(sources)
    sources = list(sources)
    if tasks is None:
        tasks = _one_per_file(sources)
    tasks = list(tasks)
    _check_memory(len(tasks), None, 1)
    out = Path(out_dir)
    options = {"positions": positions, "friction": friction, "flywheel": flywheel}
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
        if flywheel and not isinstance(tpl, BaseException) and tpl.base.flywheel is None:
            raise BatchError(
                f"{source.file}: --flywheel needs a flywheel: {{delta: ...}} "
                "section in the file (docs/dynamics.md)"
            )
    n_pos = positions or max(
        (tpl.base.analysis.positions for tpl in templates if not isinstance(tpl, BaseException)),
        default=None,
    )
    _check_memory(
        0,
        n_pos,
        (workers or os.cpu_count() or 1) if executor in (None, "processes") else 1,
        bool(positions),
    )
    where = f"--out {out_dir}"
    make_folder(out, where)
    lock = _Lock(out)
    try:
        lock.acquire()
    except OSError as exc:
        raise output_error(exc, where) from None
    try:
        return _run_locked(
            sources,
            tasks,
            out,
            where,
            templates,
            state,
            fingerprint,
            order,
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
            t_start=t_start,
        )
    finally:
        lock.release()


def _check_memory(n_tasks: int, positions: int | None, workers: int, option: bool = True) -> None:
    """Refuse, before any allocation, a batch whose table or one variant's analysis
    would not fit in the memory available (``sweeps.available_memory``)."""
    from .sweeps import BYTES_PER_VARIANT, available_memory, gigabytes

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
    sources,
    tasks,
    out: Path,
    where: str,
    templates,
    state,
    fingerprint,
    order,
    *,
    chunk,
    executor,
    workers,
    positions,
    friction,
    flywheel,
    results,
    progress,
    overwrite,
    on_chunk,
    t_start,
) -> BatchSummary:
    """The batch, with ``out`` locked: resume or start the table, run the chunks."""
    state_path, table_path = out / STATE, out / SUMMARY
    table = _Table(table_path, order)
    try:
        if table_path.exists() and not overwrite:
            old = _read_state(state_path)
            if old.get("fingerprint") != fingerprint:
                raise BatchError(
                    f"{out}: holds another batch (other files, sweep or options"
                    f"{'' if old else '; batch.json is missing or unreadable'}); "
                    "use another --out, or --overwrite to start afresh"
                )
            state = old
            table.resume()
        elif table_path.exists():
            table_path.unlink()
        _write_state(state_path, state)  # before any row: a kill stays resumable
        if not table_path.exists():
            table.rewrite()
    except OSError as exc:
        raise output_error(exc, where) from None
    reused = len(table.rows)

    todo = [t for t in tasks if t.vid not in table.rows]
    broken = [t for t in todo if isinstance(templates[t.source], BaseException)]
    todo = [t for t in todo if not isinstance(templates[t.source], BaseException)]

    def record(task_rows: Sequence[tuple[Task, Mapping[str, Any]]]) -> int:
        cells = []
        for task, row in task_rows:
            tpl = templates[task.source]
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

    from .variants import failure_row

    bar = _Progress(len(tasks), reused, sys.stderr.isatty() if progress is None else progress)
    if broken:
        bar.update(len(broken), record([(t, failure_row(templates[t.source])) for t in broken]))
    ex, slots, close = _open_executor(executor, workers)
    n_pos = positions or max(
        (tpl.base.analysis.positions for tpl in templates if not isinstance(tpl, BaseException)),
        default=1,
    )
    size = chunk or auto_chunk(len(todo), n_pos, slots)
    results_dir = str(out / "variants") if results else None
    pending: dict[Future, tuple[list[Task], int]] = {}
    retry: list[tuple[list[Task], int]] = []
    it = iter(_chunks(todo, size))
    t_run = time.perf_counter()
    failure: BaseException | None = None
    try:
        while True:
            while len(pending) < 2 * slots and (
                (
                    nxt := retry.pop()
                    if retry
                    else ((p, 1) if (p := next(it, None)) is not None else None)
                )
                is not None
            ):
                part, attempt = nxt
                job = Chunk(
                    sources[part[0].source],
                    tuple(t.vid for t in part),
                    tuple(dict(t.overrides) for t in part),
                    positions,
                    friction,
                    flywheel,
                    results_dir,
                )
                try:
                    pending[ex.submit(analyze_chunk, job)] = (part, attempt)
                except BrokenExecutor:
                    retry.append((part, attempt))
                    ex, close = _reopen(executor, workers, ex, close)
                except Exception as exc:  # noqa: BLE001 - the executor itself failed
                    for f in [
                        f
                        for f in pending
                        if f.done() and not f.cancelled() and f.exception() is None
                    ]:
                        part, _ = pending.pop(f)  # keep the rows already computed
                        if len(rows := f.result()) == len(part):
                            bar.update(len(part), record(list(zip(part, rows))))
                    raise _executor_error(executor, exc, out) from None
            if not pending:
                break
            try:
                done, _ = wait(list(pending), return_when=FIRST_COMPLETED)
            except Exception as exc:  # noqa: BLE001
                raise _executor_error(executor, exc, out) from None
            lost = False
            for f in done:
                part, attempt = pending.pop(f)
                try:
                    rows = f.result()
                    if len(rows) != len(part):
                        raise RuntimeError(f"{len(rows)} rows for {len(part)} variants")
                except CancelledError as exc:  # not by us: the executor gave up (a lost
                    raise _executor_error(executor, exc, out) from None  # scheduler)
                except BrokenExecutor as exc:  # its worker died: again, in a fresh pool
                    lost = True
                    if attempt < ATTEMPTS and executor in (None, "processes"):
                        retry.append((part, attempt + 1))
                        continue
                    rows = [_error_row(exc) for _ in part]
                except Exception as exc:  # noqa: BLE001 - a chunk's crash is its rows' error
                    rows = [_error_row(exc) for _ in part]
                bar.update(len(part), record(list(zip(part, rows))))
                if on_chunk is not None:
                    on_chunk(len(table.rows))
            if lost and executor in (None, "processes"):
                for f, job in list(pending.items()):  # the others in the broken pool
                    if f.done() and isinstance(f.exception(), BrokenExecutor):
                        pending.pop(f)
                        retry.append(job)
                ex, close = _reopen(executor, workers, ex, close)
    except BaseException as exc:
        failure = exc
        raise
    finally:
        try:
            close()
        except Exception:  # noqa: BLE001 - e.g. a Dask client already lost
            pass
        bar.close()
        seconds = time.perf_counter() - t_run
        computed = len(table.rows) - reused  # rows written now (an interrupt may fall anywhere)
        state["computed"] = state.get("computed", 0) + computed
        state["runs"] = [
            *state.get("runs", []),
            {
                "computed": computed,
                "reused": reused,
                "seconds": round(seconds, 3),
                "chunk": size,
                "workers": slots,
                "executor": executor
                if isinstance(executor, (str, type(None)))
                else type(executor).__name__,
            },
        ]
        try:
            table.rewrite()
            _write_state(state_path, state)
        except OSError as exc:
            # the appended rows stay on disk, each whole or recognisably cut; the
            # first failure is the one reported
            if failure is None:
                raise output_error(exc, where) from None
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
        slots,
    )


def _reopen(executor, workers, ex, close):
    """A fresh process pool in place of a broken one (a worker was killed)."""
    close()
    ex, _, close = _open_executor(executor, workers)
    return ex, close


def _executor_error(executor: Any, exc: BaseException, out: Path) -> OutputError:
    """One line for an executor that failed as a whole (a lost Dask scheduler)."""
    what = (
        f"--scheduler {executor}"
        if isinstance(executor, str) and executor not in ("processes", "serial")
        else "the executor"
    )
    text = str(exc).splitlines()[0] if str(exc) else ""
    return OutputError(
        f"{what}: failed ({type(exc).__name__}{': ' + text if text else ''}); "
        f"the finished rows are in {out / SUMMARY}; run the same command "
        "again to resume"
    )


def _one_per_file(sources: Sequence[Source]) -> list[Task]:
    seen: set[str] = set()
    tasks = []
    for k, s in enumerate(sources):
        vid = Path(s.file).stem
        if vid in seen:
            vid = Path(s.file).name
        seen.add(vid)
        tasks.append(Task(vid, k, {}))
    return tasks


def _templates(sources: Sequence[Source]) -> list[Any]:
    """Each source's Template, or the error that stops it loading."""
    out = []
    for s in sources:
        if s.problem is not None:
            out.append(s.problem)
            continue
        try:
            out.append(template_of(s.file, s.text))
        except KinetostaticsError as exc:
            out.append(exc)
    return out


def _check_names(tasks: Sequence[Task], sources: Sequence[Source], templates: Sequence) -> None:
    """Fail fast, before any analysis, on a parameter a file does not declare."""
    from .sweeps import check_parameters

    for k, (source, tpl) in enumerate(zip(sources, templates)):
        if not isinstance(tpl, BaseException):
            check_parameters(
                [(t.vid, t.overrides) for t in tasks if t.source == k], tpl.parameters, source.file
            )


def _chunks(tasks: Sequence[Task], size: int) -> list[list[Task]]:
    """Consecutive runs of at most ``size`` tasks of one source."""
    out: list[list[Task]] = []
    for t in tasks:
        if out and len(out[-1]) < size and out[-1][0].source == t.source:
            out[-1].append(t)
        else:
            out.append([t])
    return out
