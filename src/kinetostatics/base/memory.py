"""The memory available now and what an analysis needs: a run, a simulation's table
or a batch is refused before it allocates more than is free (docs/errors.md)."""

from __future__ import annotations

import os

__all__ = [
    "BYTES_PER_LINK_POSITION",
    "BYTES_PER_POSITION",
    "available_memory",
    "gigabytes",
    "memory_shortfall",
]

# What one position costs while it is analysed (result columns, q, q', q'',
# reactions): measured with tracemalloc on the slotting machine with friction at
# 20,000 positions, 8.0 KiB (the slider-crank: 4.6 KiB).  A batch's chunks and a
# single run are bounded by it.
BYTES_PER_POSITION = 8 * 2**10
# A large linkage costs in proportion to its moving links: a chain of dyads at 360
# positions peaked at 0.99 KiB per moving link and position (tracemalloc, 401 links; the
# slotting machine's 8 KiB over its 6 moving links is 1.3 KiB).
BYTES_PER_LINK_POSITION = 3 * 2**9


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


def memory_shortfall(positions: int, what: str, links: int = 0) -> str | None:
    """None when ``positions`` rows fit in the memory available, else the sentence saying
    so (``what`` names the rows, e.g. ``"the run"``), for the caller's error.  A row costs
    :data:`BYTES_PER_POSITION`, or :data:`BYTES_PER_LINK_POSITION` per moving link when
    that is more (``links``: the moving links; 0 when not known)."""
    per = max(BYTES_PER_POSITION, links * BYTES_PER_LINK_POSITION)
    need, free = positions * per, available_memory()
    if need <= free:
        return None
    return (
        f"{what} at {positions} positions needs about {gigabytes(need)} of memory, "
        f"more than the {gigabytes(free)} available"
    )
