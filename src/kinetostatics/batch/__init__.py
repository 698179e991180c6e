"""Layer 9, batch: many variants of one file (:mod:`.variants`, a sweep or a table in
:mod:`.sweeps`, within :mod:`.limits`), run in chunks (:mod:`.runner`; the variants and
their files in :mod:`.sources`, the executors in :mod:`.executors`) with resumable output
(:mod:`.table`), the best rows (:mod:`.best`), and the optimisation of a file's parameters
over the rows (:mod:`.optimize`, its expressions in :mod:`.objectives`, its files in
:mod:`.optimize_files`)."""

from .executors import analyze_chunk
from .objectives import OptimizeError
from .optimize import Optimum, optimize
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
    "optimize",
    "Optimum",
    "OptimizeError",
    "auto_chunk",
    "MEMORY_BUDGET",
    "BYTES_PER_POSITION",
]
