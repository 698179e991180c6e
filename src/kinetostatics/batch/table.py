"""The table of a batch on disk: ``summary.csv`` (rows appended as chunks finish,
:func:`read_summary`), ``batch.json`` (the batch's fingerprint, for a resume) and
``batch.lock`` (one batch per output folder)."""

from __future__ import annotations

import csv
import errno
import hashlib
import io
import json
import math
import os
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..base.files import json_text, write_whole
from ..base.tables import write_table
from ..errors import output_error
from .sources import BatchError, Source, Task

__all__ = ["read_summary", "column_unit", "SUMMARY", "STATE", "LOCK"]

SUMMARY = "summary.csv"
STATE = "batch.json"
LOCK = "batch.lock"
FIXED = ("status", "reason")


# -- the table on disk -----------------------------------------------------------------
_FLOATS = frozenset((float, np.float64))


def _cell(v: Any) -> str:
    """A CSV cell: numbers at full precision, NaN empty, booleans True/False.

    >>> [_cell(x) for x in (np.float64(0.1), np.nan, np.True_, np.int64(3), "a–b", None)]
    ['0.1', '', 'True', '3', 'a–b', '']
    """
    if type(v) in _FLOATS:  # most cells: one test
        return "" if v != v else repr(float(v))
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
        self.param_set: set[str] = set()
        self.known: set[str] = {"variant", *FIXED}  # every column so far
        self.rows: dict[str, dict[str, str]] = {}

    @property
    def columns(self) -> list[str]:
        return ["variant", *self.params, *FIXED, *self.metrics]

    def _learn(self, row: Mapping[str, str], params: Iterable[str]) -> bool:
        """Take the columns ``row`` and ``params`` bring; whether there were new ones."""
        new = False
        for k in params:
            if k not in self.param_set:
                self.params.append(k)
                self.param_set.add(k)
                self.known.add(k)
                new = True
        for k in row:
            if k not in self.known:
                self.metrics.append(k)
                self.known.add(k)
                new = True
        return new

    def resume(self) -> None:
        header, rows = read_summary(self.path)
        if "status" in header:
            k = header.index("status")
            self.params = [h for h in header[1:k]]
            self.param_set = set(self.params)
            self.known |= self.param_set
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
    _replace(path, json_text(state, indent=1), _Table._write)


def _start_table(
    table: _Table, state_path: Path, state: dict, fingerprint: str, overwrite: bool, where: str
) -> dict:
    """The state of the batch: that of ``batch.json`` when the folder holds the rows
    of the same batch (they are read back into ``table``), else ``state`` with the
    table started afresh.  ``batch.json`` is written before any row: a kill stays
    resumable."""
    table_path = table.path
    try:
        if table_path.exists() and not overwrite:
            old = _read_state(state_path)
            if old.get("fingerprint") != fingerprint:
                raise BatchError(
                    f"{state_path.parent}: holds another batch (other files, sweep or options"
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
    return state


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
                try:
                    os.ftruncate(fd, 0)
                    os.write(
                        fd,
                        (
                            f"pid {os.getpid()} on {_host()} since "
                            f"{time.strftime('%Y-%m-%d %H:%M:%S')}\n"
                        ).encode(),
                    )
                except BaseException:  # a full disk, Ctrl-C: no lock file left behind
                    self.release()
                    raise
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


def _fingerprint(sources: Sequence[Source], tasks: Sequence[Task], options: Mapping) -> str:
    h = hashlib.sha256()
    h.update(json_text([[s.file, s.text] for s in sources], indent=None).encode())
    overrides = [[t.vid, t.source, sorted(t.overrides.items())] for t in tasks]
    h.update(json_text(overrides, indent=None).encode())
    h.update(json_text(options, indent=None, sort_keys=True).encode())
    return h.hexdigest()
