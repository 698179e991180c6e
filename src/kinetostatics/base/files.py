"""Writing a file whole or not at all."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

__all__ = ["make_folder", "write_file", "write_outputs", "write_whole"]


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
    from ..errors import OutputError, output_error

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
    from ..errors import OutputError, output_error

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
