"""Writing a file whole or not at all."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

__all__ = ["make_folder", "write_whole"]


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
