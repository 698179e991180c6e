"""Small array helpers shared across the pipeline (internal)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

__all__ = [
    "sorted_distinct",
    "max_abs_last",
    "entries_first",
    "entries_last",
    "entry_major_zeros",
    "runs",
    "as_run",
    "same_fields",
]


def sorted_distinct(values) -> np.ndarray:
    """The distinct values of a 1-D array, sorted: ``np.unique(values)`` without its
    import of ``numpy.ma`` (~7 ms at the first call, on every ``kinetostatics run``)."""
    v = np.sort(np.asarray(values, dtype=float).ravel())
    return v[np.append(True, v[1:] != v[:-1])] if v.size else v


def max_abs_last(a: np.ndarray) -> np.ndarray:
    """The largest |entry| along the last axis, ``(...)`` (NaN where one is NaN), as
    ``np.max(np.abs(a), axis=-1)`` gives it: NumPy reduces a short last axis one row at a
    time (~40 ns per entry); along a copy with that axis first it runs ~10–20× faster."""
    a = np.abs(a)
    m = a.shape[-1] if a.ndim else 0
    if a.ndim < 2 or m == 0:
        return np.max(a, axis=-1)
    return np.ascontiguousarray(a.reshape(-1, m).T).max(axis=0).reshape(a.shape[:-1])


def entries_first(a: np.ndarray, d: int = 2) -> np.ndarray:
    """``a (..., e1 … ed)`` as a view ``(e1 … ed, ...)``: its last ``d`` axes (a matrix's
    entries) first, the positions after them (``np.moveaxis`` without its Python calls)."""
    n = a.ndim
    return a.transpose(tuple(range(n - d, n)) + tuple(range(n - d)))


def entries_last(a: np.ndarray, d: int = 2) -> np.ndarray:
    """The inverse of :func:`entries_first`: ``(e1 … ed, ...)`` as a view ``(..., e1 … ed)``."""
    n = a.ndim
    return a.transpose(tuple(range(d, n)) + tuple(range(d)))


def entry_major_zeros(shape: tuple[int, ...], d: int = 2) -> np.ndarray:
    """Zeros of ``shape (..., e1 … ed)`` stored entry-major (a view of ``(e1 … ed, ...)``):
    each entry one contiguous run over the positions, as Φ_q's group blocks are stored,
    so that writing an entry and gathering the entries into the blocks run along memory."""
    return entries_last(np.zeros(shape[len(shape) - d :] + shape[: len(shape) - d]), d)


def runs(mask) -> list[tuple[int, int]]:
    """The runs of consecutive ``True`` entries of a 1-D boolean ``mask``: ``[(first,
    last)]``, both indices included."""
    edges = np.diff(np.concatenate(([0], np.asarray(mask, dtype=np.int8), [0])))
    first, last = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return list(zip(first.tolist(), last.tolist()))


def as_run(index) -> slice | np.ndarray:
    """The integer ``index`` as a slice where it is a run of consecutive integers in order
    (a view of what it indexes, not a gather), else as an array."""
    index = np.asarray(index).reshape(-1)
    if index.size and index[-1] - index[0] == index.size - 1 and np.all(np.diff(index) == 1):
        return slice(int(index[0]), int(index[-1]) + 1)
    return index


def same_fields(self, other) -> bool:
    """``==`` of a dataclass record that holds arrays (its ``__eq__``): the same type and
    every compared field equal — an array by its shape and values, a tuple, list or
    mapping item by item.  The generated ``__eq__`` compared two arrays element-wise
    inside a tuple, and NumPy refused the truth of the result (``ks.load(p) ==
    ks.load(p)`` raised ValueError)."""
    if self is other:
        return True
    if type(self) is not type(other):
        return NotImplemented
    return all(
        _same(getattr(self, f.name), getattr(other, f.name))
        for f in dataclasses.fields(self)
        if f.compare
    )


def _same(a, b) -> bool:
    if a is b:  # as a tuple's comparison: the same object is equal, NaN included
        return True
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return (
            isinstance(a, np.ndarray)
            and isinstance(b, np.ndarray)
            and a.shape == b.shape
            and bool(np.array_equal(a, b))
        )
    if isinstance(a, (tuple, list)) and isinstance(b, (tuple, list)):
        return type(a) is type(b) and len(a) == len(b) and all(map(_same, a, b))
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    return bool(a == b)
