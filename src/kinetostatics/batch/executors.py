"""The executors of a batch (``concurrent.futures``): in this process
(``"serial"``), a pool of processes that die with the batch, or a Dask cluster
given by its scheduler address; and the function they all run, :func:`analyze_chunk`."""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable
from concurrent.futures import Executor, Future
from pathlib import Path
from typing import Any

from ..base import kernels
from ..errors import KinetostaticsError, OutputError
from .sources import BatchError, Chunk, template_of
from .table import SUMMARY

__all__ = ["analyze_chunk"]


# -- the worker ------------------------------------------------------------------------
class ChunkRows(list):
    """The rows of a chunk (a list), with ``parameters``: each variant's parameters as its
    model has them (file units), or None where the model was not built — what the table's
    parameter columns show, computed where the model is built; and ``alone``: how many of
    its variants were analysed one by one (the slow path, counted so that it shows)."""

    parameters: list[dict[str, float] | None]
    alone: int = 0


def analyze_chunk(chunk: Chunk) -> ChunkRows:
    """The rows of a chunk, in order (the function every executor runs).
    With ``results_dir`` it also writes ``<results_dir>/<id>/results.csv`` and
    ``summary.json`` of each variant that succeeded (a second, single analysis)."""
    from . import variants

    try:
        template = template_of(chunk.source.file, chunk.source.text)
    except KinetostaticsError as exc:
        return ChunkRows(variants.failure_row(exc) for _ in chunk.ids)
    found, parameters, alone = variants._analyze_variants(
        template,
        chunk.overrides,
        positions=chunk.positions,
        friction=chunk.friction,
        flywheel=chunk.flywheel,
        needs=chunk.needs,
    )
    rows = ChunkRows(found)
    rows.parameters, rows.alone = parameters, alone
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


# -- executors -------------------------------------------------------------------------
def _start_worker(parent: int, backend: str) -> None:
    """Pool initializer: the parent's backend (base/kernels.py), death with it, and
    Ctrl-C left to it: a terminal's SIGINT reaches the whole process group, and a worker
    waiting for its next chunk would print a traceback of its own; the parent stops
    (one line) and shuts the pool down."""
    import signal

    kernels.set_backend(backend)
    _die_with_parent(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


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


def _shut(ex) -> None:
    """Shut a process pool down: the calls not started cancelled, the ones running (their
    workers ignore Ctrl-C) finished and the pool's thread joined, so that Python 3.11's
    exit hook does not race that thread ("Exception ignored … Bad file descriptor" after
    the one line of an interrupt).  A second Ctrl-C stops the wait."""
    try:
        ex.shutdown(wait=True, cancel_futures=True)
    except KeyboardInterrupt:
        pass


def _open_executor(executor: Any, workers: int | None) -> tuple[Executor, int, Callable[[], None]]:
    """(executor, number of parallel slots, close)."""
    if executor == "serial":
        return _Serial(), 1, lambda: None
    if executor in (None, "processes"):
        from concurrent.futures import ProcessPoolExecutor

        n = workers or os.cpu_count() or 1
        ex = ProcessPoolExecutor(
            max_workers=n, initializer=_start_worker, initargs=(os.getpid(), kernels.backend())
        )
        return ex, n, lambda: _shut(ex)
    if isinstance(executor, Executor):
        return executor, workers or os.cpu_count() or 1, lambda: None
    if isinstance(executor, str):
        try:
            from distributed import Client
        except ImportError:
            raise BatchError(
                f"--scheduler {executor}: Dask is not installed (pip install 'kinetostatics[dask]')"
            ) from None
        restore = _quiet_dask()
        try:
            client = Client(executor, timeout=10)
        except (OSError, TimeoutError) as exc:
            restore()
            raise BatchError(f"--scheduler {executor}: cannot connect ({exc})") from None
        except BaseException:
            restore()
            raise
        try:
            n = workers or max(1, sum(client.nthreads().values()))
            ex = client.get_executor()
        except BaseException:
            client.close()
            restore()
            raise

        def close() -> None:
            try:
                ex.shutdown(wait=False)
                client.close()
            finally:
                restore()

        return ex, n, close
    raise BatchError(
        f"executor {executor!r}: use 'processes', 'serial', a Dask scheduler "
        "address or a concurrent.futures.Executor"
    )


# distributed logs through these (its client's reconnection, tornado's event loop)
_DASK_LOGGERS = ("distributed", "tornado", "asyncio")


def _quiet_dask() -> Callable[[], None]:
    """Silence distributed's loggers (and those it logs through) while we use a cluster;
    returns the function that restores them.  A lost scheduler is then the one line of
    :func:`_executor_error`, not distributed's tracebacks of its reconnection (36 lines
    before it).  The loggers are disabled, each as it was restored after."""
    import logging

    def ours(name: str) -> bool:
        return any(name == n or name.startswith(n + ".") for n in _DASK_LOGGERS)

    names = {*_DASK_LOGGERS, *(n for n in logging.root.manager.loggerDict if ours(n))}
    saved = {n: logging.getLogger(n).disabled for n in names}
    for n in names:
        logging.getLogger(n).disabled = True

    def restore() -> None:
        for n, was in saved.items():
            logging.getLogger(n).disabled = was

    return restore


class _Pool:
    """The executor of a batch (:func:`_open_executor`): ``ex``, its number of
    parallel ``slots`` and ``close``."""

    def __init__(self, executor: Any, workers: int | None):
        self.executor, self.workers = executor, workers
        self.ex, self.slots, self.close = _open_executor(executor, workers)

    @property
    def processes(self) -> bool:
        """A process pool of ours: a chunk whose worker died goes again to a fresh pool."""
        return self.executor in (None, "processes")

    def reopen(self) -> None:
        """A fresh process pool in place of a broken one (a worker was killed)."""
        self.close()
        self.ex, _, self.close = _open_executor(self.executor, self.workers)


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
