"""``==`` of models and of their records holding arrays (base/arrays.same_fields): a file
loaded twice gives equal models, links, joints and loads; a model of another number, another
file or another type is unequal.  The generated ``__eq__`` compared the arrays inside a tuple
and NumPy refused the truth of the result (``ks.load(p) == ks.load(p)`` raised ValueError)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base.arrays import same_fields
from tests.helpers import MECHANISMS, variant


def _records(obj):
    """Every dataclass record reachable from ``obj`` (tuples, lists and mappings walked)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        yield obj
        for f in dataclasses.fields(obj):
            yield from _records(getattr(obj, f.name))
    elif isinstance(obj, (tuple, list)):
        for x in obj:
            yield from _records(x)
    elif isinstance(obj, dict):
        for x in obj.values():
            yield from _records(x)


@pytest.mark.parametrize("path", MECHANISMS, ids=lambda p: p.stem)
def test_a_file_loaded_twice_gives_equal_models(path):
    a, b = ks.load(path), ks.load(path)
    assert a == b and not a != b
    pairs = list(zip(_records(a), _records(b)))
    assert len(pairs) > 10
    for x, y in pairs:  # every record of the tree, arrays or not
        assert x == y, type(x).__name__


def test_another_number_another_file_another_type_are_unequal():
    base = ks.load(MECHANISMS[0].parent / "slotting_machine.yaml")
    moved = variant("slotting_machine", c=(r"  c: 125 ", "  c: 126 "))  # S3 on the bar
    assert base != moved and not base == moved
    bar = [x is y or x == y for x, y in zip(base.links, moved.links)]
    assert bar.count(False) == 1  # the guide bar alone: its points about its CoM moved
    assert base != ks.load(MECHANISMS[0].parent / "slider_crank.yaml")
    assert base != "slotting_machine" and base.links[0] != 1


def test_arrays_compare_by_shape_and_value():
    @dataclasses.dataclass(frozen=True)
    class R:
        a: np.ndarray
        b: tuple = ()
        c: dict = dataclasses.field(default_factory=dict)
        note: str = dataclasses.field(default="", compare=False)

        __eq__ = same_fields

    x = R(np.array([1.0, 2.0]), (np.zeros(2),), {"p": np.ones(2)}, note="one")
    assert x == R(np.array([1.0, 2.0]), (np.zeros(2),), {"p": np.ones(2)}, note="two")
    assert x != R(np.array([1.0, 2.5]), (np.zeros(2),), {"p": np.ones(2)})
    assert x != R(np.array([[1.0, 2.0]]), (np.zeros(2),), {"p": np.ones(2)})  # shape
    assert x != R(np.array([1.0, 2.0]), (np.zeros(3),), {"p": np.ones(2)})
    assert x != R(np.array([1.0, 2.0]), (np.zeros(2),), {"q": np.ones(2)})
    assert x != R(np.array([1.0, 2.0]), [np.zeros(2)], {"p": np.ones(2)})  # tuple vs list
