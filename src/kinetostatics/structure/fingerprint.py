"""A model's fingerprint: how :func:`~kinetostatics.structure.system.system_of` knows that
the model it compiled has not changed since.

A :class:`~kinetostatics.model.Model` is frozen, but its arrays are writable and its
mappings are dicts: a caller may change one in place (``link.points["A"][:] = …``), and
the compiled system must then be built again.  The model's pickle was the fingerprint: a
serialisation of every array on every ``analyze`` (~0.13–0.15 ms, 5–8 % of a kinematics
analysis at 360 positions).  Here the model is taken apart once, following each object's
pickle state (``__getstate__``, so what a piece leaves out of its pickle — a cam's last
poses, the model's compiled system — stays out here too), into

- every NumPy array reached, with a copy of its bytes, its shape and its dtype;
- every mutable container reached (a dict, a list, a set, the state of an object that is
  not a frozen dataclass), with the identities of its items;
- the model's own fields, by identity (a copy made with ``dataclasses.replace`` carries the
  cache along and is noticed by the field it changed).

Tuples, frozen dataclasses and atoms (numbers, strings, functions) cannot change their
items without ``object.__setattr__``, which the package uses for caches only, so their
items' identities are fixed once reached.  :meth:`Fingerprint.same` compares a few lists
at C speed: the arrays' bytes, the containers' items by identity.  Objects a fingerprint
cannot follow (an array of Python objects) make :func:`fingerprint` return None, and the
caller builds without a cache, as it did for a model that could not be pickled.
"""

from __future__ import annotations

import dataclasses
import enum
import operator
import types
from pathlib import PurePath

import numpy as np

__all__ = ["Fingerprint", "fingerprint"]

_ATOMS = (
    str,
    bytes,
    int,
    float,
    complex,
    bool,
    type(None),
    np.generic,
    np.dtype,
    enum.Enum,
    type,
    range,
    slice,
    PurePath,
    types.FunctionType,
    types.BuiltinFunctionType,
    types.MethodType,
    types.ModuleType,
)


class _Unfollowable(Exception):
    """An object whose contents a fingerprint cannot compare (an object array)."""


@dataclasses.dataclass(frozen=True, eq=False)
class Fingerprint:
    """The state of a model taken apart once (see the module's docstring)."""

    fields: tuple  # the model's pickle state: its field values, in order
    names: tuple[str, ...]  # their names
    arrays: tuple[np.ndarray, ...]
    contents: tuple[bytes, ...]  # each array's bytes when taken
    layouts: tuple  # each array's (shape, dtype)
    dicts: tuple  # (dict, its keys, its values)
    sequences: tuple  # (list, its items)
    sets: tuple  # (set, a frozen copy)
    objects: tuple  # (object, its state's keys, its state's values): not frozen

    def same(self, model) -> bool:
        """Whether ``model`` is the mechanism taken, to the bit: the same fields, the same
        array bytes, the same items in every container."""
        is_ = operator.is_
        state = model.__getstate__()
        if tuple(state) != self.names or not all(map(is_, state.values(), self.fields)):
            return False
        if [a.tobytes() for a in self.arrays] != list(self.contents):
            return False
        if [(a.shape, a.dtype) for a in self.arrays] != list(self.layouts):
            return False
        for d, keys, values in self.dicts:
            if len(d) != len(keys) or tuple(d) != keys or not all(map(is_, d.values(), values)):
                return False
        for seq, items in self.sequences:
            if len(seq) != len(items) or not all(map(is_, seq, items)):
                return False
        for s, frozen in self.sets:
            if s != frozen:
                return False
        for obj, keys, values in self.objects:
            st = obj.__getstate__()
            if (
                not isinstance(st, dict)
                or tuple(st) != keys
                or not all(map(is_, st.values(), values))
            ):
                return False
        return True


def fingerprint(model) -> Fingerprint | None:
    """The :class:`Fingerprint` of ``model``, or None if some object in it cannot be
    followed (the caller then keeps no cache)."""
    found: dict[str, list] = {k: [] for k in ("arrays", "dicts", "sequences", "sets", "objects")}
    seen: set[int] = set()
    state = model.__getstate__()
    try:
        for value in state.values():
            _walk(value, found, seen)
    except (_Unfollowable, RecursionError):
        return None
    arrays = tuple(found["arrays"])
    return Fingerprint(
        fields=tuple(state.values()),
        names=tuple(state),
        arrays=arrays,
        contents=tuple(a.tobytes() for a in arrays),
        layouts=tuple((a.shape, a.dtype) for a in arrays),
        dicts=tuple(found["dicts"]),
        sequences=tuple(found["sequences"]),
        sets=tuple(found["sets"]),
        objects=tuple(found["objects"]),
    )


def _walk(obj, found: dict[str, list], seen: set[int]) -> None:
    if isinstance(obj, _ATOMS) or id(obj) in seen:
        return
    seen.add(id(obj))
    if isinstance(obj, np.ndarray):
        if obj.dtype.hasobject:
            raise _Unfollowable(obj)
        found["arrays"].append(obj)
        return
    if isinstance(obj, (tuple, frozenset)):
        items = obj
    elif isinstance(obj, dict):
        found["dicts"].append((obj, tuple(obj), tuple(obj.values())))
        items = (*obj, *obj.values())
    elif isinstance(obj, list):
        found["sequences"].append((obj, tuple(obj)))
        items = obj
    elif isinstance(obj, set):
        found["sets"].append((obj, frozenset(obj)))
        items = obj
    else:
        try:
            state = obj.__getstate__() if hasattr(obj, "__getstate__") else None
        except TypeError as e:  # a C object that refuses
            raise _Unfollowable(obj) from e
        if isinstance(state, tuple) and len(state) == 2:  # (dict or None, slots)
            merged = {**(state[0] or {}), **(state[1] or {})}
        elif isinstance(state, dict):
            merged = state
        else:  # no state Python can see (a C object): its identity only
            return
        params = getattr(type(obj), "__dataclass_params__", None)
        if params is None or not params.frozen:  # its attributes may be set again
            if not isinstance(state, dict):  # slots of a mutable object: not followed
                raise _Unfollowable(obj)
            found["objects"].append((obj, tuple(merged), tuple(merged.values())))
        items = merged.values()
    for item in items:
        _walk(item, found, seen)
