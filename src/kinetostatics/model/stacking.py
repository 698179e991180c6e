"""Stack variants of one topology into one model with a leading variant axis.

Every number that differs between the variants becomes an array of shape
``(V, 1) + shape`` — variants first, then one axis that broadcasts over the
positions — so the stage functions, which broadcast over leading axes, run
all variants at once on arrays ``(V, N, ...)``.  Numbers equal in every
variant stay as they are.  Anything else that differs (names, kinds, the
number of points) is a different topology: :func:`stack` refuses it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from operator import attrgetter, itemgetter
from typing import Any

import numpy as np

from . import Model

__all__ = ["stack", "subset", "signature", "is_stacked", "TopologyMismatch"]


class TopologyMismatch(ValueError):
    """The variants differ in more than numbers."""


_NUMBER_TYPES = (int, float, np.floating, np.integer)


def _is_number(x: Any) -> bool:
    return isinstance(x, _NUMBER_TYPES) and not isinstance(x, bool)


def _all_numbers(types: set[type]) -> bool:
    """Whether values of these types are all numbers (:func:`_is_number`)."""
    return all(issubclass(t, _NUMBER_TYPES) and not issubclass(t, bool) for t in types)


def _stack(values: Sequence[Any], path: str) -> Any:
    # The checks run over the variants in C (map, zip, list.count): a chunk stacks ~125
    # models of a few hundred values each.
    first = values[0]
    types = set(map(type, values))
    if isinstance(first, np.ndarray) and first.dtype.kind == "f":
        if not all(issubclass(t, np.ndarray) for t in types) or (
            len(set(map(np.shape, values))) != 1
        ):
            raise TopologyMismatch(f"{path}: shapes differ")
        arr = np.stack(values)
        return first if np.array_equal(arr, np.broadcast_to(first, arr.shape)) else arr[:, None]
    if _is_number(first):
        if not _all_numbers(types):
            raise TopologyMismatch(f"{path}: not all numbers")
        if values.count(first) == len(values):  # all equal (or one NaN object repeated)
            return first
        arr = np.array(values, dtype=float)
        if np.all(arr == arr[0]):
            return first
        if isinstance(first, (int, np.integer)) and not isinstance(first, float):
            raise TopologyMismatch(f"{path}: counts differ")
        return arr[:, None]
    if dataclasses.is_dataclass(first) and not isinstance(first, type):
        if len(types) != 1:
            raise TopologyMismatch(f"{path}: kinds differ")
        changes = {}
        for f in dataclasses.fields(first):
            if not f.compare:  # locations: the first variant's
                continue
            items = list(map(attrgetter(f.name), values))
            stacked = _stack(items, f"{path}.{f.name}")
            if stacked is not items[0]:
                changes[f.name] = stacked
        return dataclasses.replace(first, **changes) if changes else first
    if isinstance(first, (tuple, list)):
        if not all(issubclass(t, type(first)) for t in types) or len(set(map(len, values))) != 1:
            raise TopologyMismatch(f"{path}: lengths differ")
        items = [_stack(list(column), f"{path}[{k}]") for k, column in enumerate(zip(*values))]
        if all(a is b for a, b in zip(items, first)):
            return first
        return type(first)(items)
    if isinstance(first, dict) or hasattr(first, "keys"):
        keys = list(first.keys())
        if any(list(v.keys()) != keys for v in values):
            raise TopologyMismatch(f"{path}: keys differ")
        items = {k: _stack(list(map(itemgetter(k), values)), f"{path}.{k}") for k in first}
        if all(items[k] is first[k] for k in first):
            return first
        return type(first)(items) if isinstance(first, dict) else items
    if values.count(first) == len(values):
        return first
    raise TopologyMismatch(f"{path}: {first!r} differs")


def stack(models: Sequence[Model]) -> Model:
    """One model whose differing numbers carry a leading variant axis ``(V, 1, ...)``."""
    if not models:
        raise ValueError("no models to stack")
    if len(models) == 1:
        return models[0]
    parameters = models[0].parameters
    out = _stack([dataclasses.replace(m, parameters={}) for m in models], "model")
    return dataclasses.replace(out, parameters=parameters)


def subset(stacked: Model, models: Sequence[Model], members: Sequence[int]) -> Model:
    """``stack([models[v] for v in members])`` from ``stacked = stack(models)`` without
    stacking again: the variant axis of every stacked value taken at ``members`` (at least
    two).  A value :func:`stack` kept as the first model's (the same object) is that
    model's; one stacked stays stacked even where the members agree — the same numbers
    per variant, so the same results."""
    members = np.asarray(members)
    first = models[0]

    def take(s: Any, f: Any) -> Any:
        if s is f:
            return s
        if isinstance(s, np.ndarray):
            return s[members]
        if dataclasses.is_dataclass(s) and not isinstance(s, type):
            changes = {}
            for fd in dataclasses.fields(s):
                if fd.compare:
                    a, b = getattr(s, fd.name), getattr(f, fd.name)
                    if (t := take(a, b)) is not a:
                        changes[fd.name] = t
            return dataclasses.replace(s, **changes) if changes else s
        if isinstance(s, (tuple, list)):
            return type(s)(take(a, b) for a, b in zip(s, f))
        if isinstance(s, dict):
            return {k: take(s[k], f[k]) for k in s}
        return s  # pragma: no cover - stack keeps anything else as the first model's

    out = take(
        dataclasses.replace(stacked, parameters={}), dataclasses.replace(first, parameters={})
    )
    return dataclasses.replace(out, parameters=models[int(members[0])].parameters)


def is_stacked(x: Any) -> bool:
    """Whether a model value carries the variant axis (numbers (V, 1), vectors (V, 1, 2))."""
    if dataclasses.is_dataclass(x):
        return any(is_stacked(getattr(x, f.name)) for f in dataclasses.fields(x) if f.compare)
    if isinstance(x, (tuple, list)):
        return any(is_stacked(v) for v in x)
    return np.ndim(x) > 1


def signature(model: Model) -> tuple:
    """What must agree for models to stack: every name, kind and count."""

    def sig(x):
        if isinstance(x, np.ndarray):
            return ("array", x.shape)
        if _is_number(x):
            return ("int", int(x)) if isinstance(x, (int, np.integer)) else "num"
        if dataclasses.is_dataclass(x) and not isinstance(x, type):
            return (type(x).__name__,) + tuple(
                sig(getattr(x, f.name)) for f in dataclasses.fields(x) if f.compare
            )
        if isinstance(x, (tuple, list)):
            return tuple(sig(v) for v in x)
        if isinstance(x, dict) or hasattr(x, "keys"):
            return tuple((k, sig(x[k])) for k in x)
        return x

    return sig(
        dataclasses.replace(
            model,
            parameters={},
            analysis=dataclasses.replace(model.analysis, positions=model.analysis.positions),
        )
    )
