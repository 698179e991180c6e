"""Writing a file whole or not at all."""

from __future__ import annotations

import json
import math
import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import OutputError, output_error

__all__ = ["make_folder", "write_file", "write_outputs", "write_whole", "json_text", "NON_FINITE"]

# the key that lists, in a JSON mapping written by json_text, the values that were not
# finite numbers and are written as null: {"path.to[2].value": "Infinity" | "-Infinity" | "NaN"}
NON_FINITE = "non_finite"


def write_whole(path: Path, write: Callable[[Path], None]) -> None:
    """Write ``path`` by ``write(temporary path)`` and ``os.replace``: never a half-written
    file, and no temporary file left when the write fails (a full disk, a read-only
    folder); an ``OSError`` names the file meant, not its temporary."""
    tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            tmp.unlink()
        except OSError:
            pass
        if isinstance(exc, OSError) and exc.filename == str(tmp):
            exc.filename = str(path)
        raise


def make_folder(out: Path, what: str) -> None:
    """Make the output folder ``out`` (``what`` names it in messages, e.g. ``--out DIR``);
    a path that is a file, or an ``OSError`` (read-only, full disk), is one
    :class:`~kinetostatics.errors.OutputError` line."""

    if out.exists() and not out.is_dir():
        raise OutputError(f"{what}: is a file, not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise output_error(exc, what) from None


def write_file(path: Path, what: str, write: Callable[[Path], None]) -> None:
    """Write the file ``path`` whole (:func:`write_whole`); a ``path`` that is a folder
    (``--out .``) or an ``OSError`` (a missing or read-only folder, a full disk) is
    one :class:`~kinetostatics.errors.OutputError` line starting with ``what`` (e.g.
    ``--out FILE``).  A writer gets a temporary name: it must state its format (for
    example ``savefig(..., format="png")``), not guess it from the name."""

    path = Path(path)
    if path.is_dir() or path.name in ("", ".", ".."):
        raise OutputError(f"{what}: is a folder, not a file")
    try:
        write_whole(path, write)
    except OSError as exc:
        raise output_error(exc, what) from None


def write_outputs(out: Path, what: str, writers) -> None:
    """Make the folder ``out`` (:func:`make_folder`) and write each ``(path, write)``
    whole (:func:`write_file`): every command writes its files through here or
    :func:`write_file`, so that none is left half-written or under a temporary name,
    and a failure is one line naming the path."""
    make_folder(Path(out), what)
    for path, write in writers:
        write_file(path, what, write)


def json_text(data: Any, indent: int | None = 2, *, whole: bool = False, **options: Any) -> str:
    """``data`` as strict JSON (RFC 8259: no ``Infinity`` or ``NaN``, which most JSON
    readers refuse): every JSON file the package writes is made here.  A value that is
    not a finite number is written as ``null``, and a mapping at the top gains the key
    :data:`NON_FINITE` naming each such value's path and what it was
    (``{"singular[2].condition": "Infinity"}``), so that a null is never mistaken for a
    missing value.  NumPy scalars and arrays are written as Python numbers and lists.
    ``whole``: a NumPy float array is named once for all its non-finite entries
    (``{"y": "NaN at 99 of 360"}``) and written through one ``tolist()`` (the editor's
    documents, large and made many times a second).
    ``options``: more keywords of :func:`json.dumps` (``ensure_ascii``, ``sort_keys``).

    >>> json_text({"a": [1.0, float("inf")]}, indent=None)
    '{"a": [1.0, null], "non_finite": {"a[1]": "Infinity"}}'
    """
    found: dict[str, str] = {}
    clean = _finite(data, "", found, whole)
    if found and isinstance(clean, dict):
        clean[NON_FINITE] = found
    return json.dumps(clean, indent=indent, allow_nan=False, **options)


def _finite(value: Any, path: str, found: dict[str, str], whole: bool = False) -> Any:
    """``value`` with its non-finite numbers replaced by None (their paths in ``found``;
    with ``whole``, a float array's once: :func:`json_text`)."""
    if isinstance(value, Mapping):
        return {
            k: _finite(v, f"{path}.{k}" if path else str(k), found, whole) for k, v in value.items()
        }
    if whole and isinstance(value, np.ndarray) and value.dtype.kind in "fc":
        a = np.asarray(value, float)
        if not np.all(np.isfinite(a)):
            found[path] = _non_finite(a)
            return np.where(np.isfinite(a), a, None).tolist()
        return a.tolist()
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_finite(v, f"{path}[{i}]", found, whole) for i, v in enumerate(value)]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        x = float(value)
        if math.isfinite(x):
            return x
        found[path] = "NaN" if math.isnan(x) else ("Infinity" if x > 0 else "-Infinity")
        return None
    return value


def _non_finite(a: np.ndarray) -> str:
    """What a float array holds that is not a finite number: ``"NaN at 99 of 360"``."""
    kinds = [
        w
        for w, m in (("NaN", np.isnan(a)), ("Infinity", a == np.inf), ("-Infinity", a == -np.inf))
        if m.any()
    ]
    return f"{'/'.join(kinds)} at {int((~np.isfinite(a)).sum())} of {a.size}"
