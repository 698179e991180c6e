"""The variants of a batch and where they come from: the mechanism files as read
(:class:`Source`, :func:`sources_of`), one variant (:class:`Task`), what a worker
analyses (:class:`Chunk`) and how many variants make a chunk (:func:`auto_chunk`)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

from ..base.document import read_text
from ..base.expressions import evaluate_parameters
from ..base.memory import BYTES_PER_POSITION
from ..errors import KinetostaticsError
from .sweeps import check_parameters

__all__ = [
    "template_of",
    "Source",
    "Task",
    "Chunk",
    "BatchError",
    "sources_of",
    "auto_chunk",
    "variant_parameters",
    "MEMORY_BUDGET",
    "BYTES_PER_POSITION",
]

# Memory bound of one chunk: a variant costs about BYTES_PER_POSITION per
# position while it is analysed (base.memory).
MEMORY_BUDGET = 256 * 2**20
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
    # the row quantities someone reads (an optimisation's names): the rows then hold
    # what those need (:func:`~.variants.row_needs`); None: the whole row
    needs: tuple[str, ...] | None = None


@lru_cache(maxsize=16)
def template_of(file: str, text: str):
    from .variants import Template

    return Template.loads(text, file)


def auto_chunk(n_todo: int, positions: int, workers: int) -> int:
    """Variants per chunk: at most MEMORY_BUDGET of work per chunk and
    MAX_CHUNK variants, and at least four chunks per worker so the load
    balances and progress shows.

    >>> auto_chunk(10_000, 72, 2), auto_chunk(10, 72, 2), auto_chunk(10**6, 3600, 2)
    (125, 2, 9)
    """
    cap = max(1, min(MAX_CHUNK, MEMORY_BUDGET // (max(positions, 1) * BYTES_PER_POSITION)))
    return max(1, min(cap, math.ceil(n_todo / (4 * max(workers, 1)))))


# -- parameters of a variant -----------------------------------------------------------
def variant_parameters(template, overrides: Mapping[str, float]) -> dict[str, float]:
    """All the file's parameters evaluated for a variant (file units); only the
    overrides when the values cannot be evaluated (the row then says why)."""

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
