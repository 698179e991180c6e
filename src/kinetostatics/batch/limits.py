"""The limits of a batch: at most :data:`MAX_VARIANTS` variants, and no more than the
memory available (:func:`available_memory`) holds at :data:`BYTES_PER_VARIANT` each
(:func:`check_size`, which refuses a sweep with a :class:`SweepError`)."""

from __future__ import annotations

from ..base.memory import available_memory, gigabytes
from ..errors import Location, ModelError

__all__ = [
    "SweepError",
    "MAX_VARIANTS",
    "BYTES_PER_VARIANT",
    "available_memory",
    "gigabytes",
    "check_size",
]

MAX_VARIANTS = 10_000_000
# What one variant costs while a batch holds it: its id and values, its task, and
# its row of the summary table as text (measured with tracemalloc on the slotting
# machine with friction, 3 swept parameters, 36 columns: 5.2 KiB; the rest is
# headroom for the fingerprint and the chunk lists).  A sweep whose variants would
# need more than the memory available is refused before any is made.
BYTES_PER_VARIANT = 8 * 2**10


class SweepError(ModelError):
    """A sweep that cannot be expanded; one ``(Location, message)`` problem."""

    def __init__(self, where: Location, message: str):
        super().__init__([(where, message)])


def check_size(n: int, where: Location, what: str = "the sweep") -> None:
    """Refuse ``n`` variants before making them: more than :data:`MAX_VARIANTS`,
    or more than the memory available holds at :data:`BYTES_PER_VARIANT` each."""
    if n > MAX_VARIANTS:
        raise SweepError(where, f"{what} has {n} variants, more than the limit of {MAX_VARIANTS}")
    need, free = n * BYTES_PER_VARIANT, available_memory()
    if need > free:
        raise SweepError(
            where,
            f"{what} has {n} variants: about {gigabytes(need)} of memory "
            f"to hold them and their rows, more than the {gigabytes(free)} "
            "available; split it into several batches (one --out each)",
        )
