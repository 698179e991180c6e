"""The limits of a mechanism file: sizes of the text and of its parts, and the bounds
on its numbers (docs/errors.md lists them, with the messages they give)."""

from __future__ import annotations

__all__ = [
    "MAX_FILE_BYTES",
    "MAX_NODES",
    "MAX_DEPTH",
    "MAX_LINKS",
    "MAX_POSITIONS",
    "MAX_TURNS",
    "MAX_TRAVEL",
    "SPEED_RANGE",
    "MAX_LAW_ACCELERATION",
    "MAGNITUDE",
    "OWN_LIMITS",
]

MAX_FILE_BYTES = 1_000_000
MAX_NODES = 100_000
MAX_DEPTH = 100
MAX_LINKS = 1000
"""Links of a file, the ground included.  What bounds it is the analysis: memory grows
with links × positions (about 1 KiB per moving link and position, measured on chains of
dyads, :data:`~kinetostatics.base.memory.BYTES_PER_LINK_POSITION`), checked against the
memory available when a run starts; a 1,001-link chain of dyads at 360 positions used
0.4 GB and 2.4 s of CPU (tests/benchmarks/bench_loading.py ``--sizes``), and parts of the
analysis grow faster than the number of links beyond that (docs/accuracy.md)."""
MAX_POSITIONS = 10_000_000
MAX_TURNS = 100  # analysis.sweep of a revolute driver, in turns
MAX_TRAVEL = 1000  # a prismatic driver's sweep (and at - start): x the largest link
SPEED_RANGE = (1e-9, 1e9)  # |speed| of a motion driver, rad/s or m/s
MAX_LAW_ACCELERATION = 1e18  # |second derivative| of a motion law, rad/s^2 or m/s^2
MAGNITUDE = {  # SI: |value| <= upper, and a value that is not 0 has |value| >= lower
    "length": (1e-30, 1e9),  # m
    "mass": (1e-30, 1e12),  # kg
    "inertia": (1e-30, 1e30),  # kg*m^2 (mass limit x length limit^2)
    "force": (1e-30, 1e24),  # N (mass limit x gravity limit)
    "torque": (1e-30, 1e33),  # N*m (force limit x length limit)
    "acceleration": (1e-30, 1e12),  # m/s^2: gravity
    "time": (1e-30, 1e9),  # s
    "speed": (1e-30, 1e9),  # rad/s or m/s (a motion driver: SPEED_RANGE)
    "angle": (0.0, 1e6),  # rad
    None: (1e-30, 1e18),  # dimensionless: friction coefficients, directions, ratios
}
"""Bounds on every number of a file, by quantity kind, in SI.  The products the
analysis forms from them (m*omega^2*L, J*omega^2, m*g*L, F*L, power F*v; with a
driver speed of at most 1e9 and a law's acceleration of at most 1e18 in SI) stay
below 1e60, and their squares (norms) below 1e120: far from overflow (1.8e308).  A
non-zero value below the lower bound (1e-300 kg) is refused as well: it only
arises by mistake, and its products underflow."""
OWN_LIMITS = {
    "analysis.sweep": "MAX_TURNS (revolute driver; start + sweep within ±MAX_TURNS turns of "
    "0), MAX_TRAVEL (prismatic driver)",
    "analysis.at[]": "within ±MAX_TURNS turns of 0 (revolute driver), MAX_TRAVEL from "
    "analysis.start (prismatic driver)",
    "drivers.*.motion.speed": "SPEED_RANGE",
    "drivers.*.motion.coefficients[]": "finite in SI; the law's SPEED_RANGE, "
    "MAX_LAW_ACCELERATION, MAGNITUDE of its coordinate, "
    "MAX_TURNS or MAX_TRAVEL of its path",
    "links.*.number": "a whole number from 1 to 99 (io/bodies.py MAX_NUMBER)",
}
"""The numbers of a file that are bounded by a limit of their own instead of (or besides)
:data:`MAGNITUDE`: key pattern (names as ``*``, indices as ``[]``) -> the limit.  Every other
number is read through :meth:`~kinetostatics.base.spec.Entry.number` and bounded by
:data:`MAGNITUDE` (``tests/io/test_hostile_keys.py`` walks the loader to check it)."""
