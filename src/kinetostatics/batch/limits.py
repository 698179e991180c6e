"""The limits of a batch: at most :data:`MAX_VARIANTS` variants, and no more than the
memory available (:func:`available_memory`) holds at :data:`BYTES_PER_VARIANT` each
(:func:`check_size`, which refuses a sweep with a :class:`SweepError`)."""

from __future__ import annotations

import os

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


def available_memory() -> int:
    """Bytes of memory available now: ``MemAvailable`` of ``/proc/meminfo`` (and at
    most what a cgroup limit leaves), else the free physical pages; 2**62 when
    the system does not say."""
    free = None
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    free = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError, IndexError):
        pass
    if free is None:
        try:
            free = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (ValueError, OSError, AttributeError):
            return 2**62
    try:
        with open("/sys/fs/cgroup/memory.max", encoding="ascii") as fh:
            limit = fh.read().strip()
        with open("/sys/fs/cgroup/memory.current", encoding="ascii") as fh:
            used = int(fh.read().strip())
        if limit != "max":
            free = min(free, max(int(limit) - used, 0))
    except (OSError, ValueError):
        pass
    return free


def gigabytes(n: float) -> str:
    """``n`` bytes as ``'1.2 GB'`` (GiB)."""
    return f"{n / 2**30:.1f} GB"


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
