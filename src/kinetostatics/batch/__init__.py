"""Layer 9, batch: many variants of one file (:mod:`.variants`, a sweep or a table in
:mod:`.sweeps`, within :mod:`.limits`), run in chunks (:mod:`.runner`; the variants and
their files in :mod:`.sources`, the executors in :mod:`.executors`) with resumable output
(:mod:`.table`), and the best rows (:mod:`.best`)."""

from .executors import analyze_chunk
from .runner import BatchSummary, run_batch
from .sources import (
    BYTES_PER_POSITION,
    MEMORY_BUDGET,
    BatchError,
    Chunk,
    Source,
    Task,
    auto_chunk,
    sources_of,
    template_of,
)
from .table import read_summary

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
