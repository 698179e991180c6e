"""Layer 9, batch: many variants of one file (:mod:`.variants`, a sweep or a table in
:mod:`.sweeps`), run in chunks with resumable output (:mod:`.runner`), and the best rows
(:mod:`.best`)."""

from .runner import (
    BYTES_PER_POSITION,
    MEMORY_BUDGET,
    BatchError,
    BatchSummary,
    Chunk,
    Source,
    Task,
    analyze_chunk,
    auto_chunk,
    read_summary,
    run_batch,
    sources_of,
    template_of,
)

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
