"""The writer (``io.dump``): every shipped file written and read back is the same machine.

The invariant is the one a user relies on when saving a model built or edited in Python:
the file it writes analyses to the numbers of the model it came from (every column, to
round-off of the points written in the file's frame), and writing it again changes nothing.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.io import dump

ROOT = Path(__file__).resolve().parents[2]
MECHANISMS = sorted((ROOT / "mechanisms").glob("*.yaml"))


# written as values, not kept: the file is SI with its expressions evaluated (parameters,
# units, the parameters' texts); where each key was read and the source file name
NOT_WRITTEN = {
    "parameters",
    "parameter_texts",
    "units",
    "where",
    "source",
    "sketch_where",
    "_compiled",
    "ideal",
}


def _differences(a, b, path: str) -> list:
    """Every field of two models (recursively) that differs: numbers to 1e-14 relative
    (points are written in the file's frame, then read back relative to the centre of
    mass), everything else exactly.  A field the writer forgets shows here by its path."""
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        if type(a) is not type(b):
            return [(path, type(a).__name__, type(b).__name__)]
        return [
            d
            for f in dataclasses.fields(a)
            if f.name not in NOT_WRITTEN
            for d in _differences(getattr(a, f.name), getattr(b, f.name), f"{path}.{f.name}")
        ]
    if isinstance(a, Mapping):
        if not isinstance(b, Mapping) or set(a) != set(b):
            return [(path, a, b)]
        return [d for k in a for d in _differences(a[k], b[k], f"{path}[{k!r}]")]
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray) or _numbers(a):
        if a is None or b is None or np.shape(a) != np.shape(b):
            return [(path, a, b)]
        ok = np.allclose(np.asarray(a, float), np.asarray(b, float), rtol=1e-14, atol=1e-15)
        return [] if ok else [(path, a, b)]
    if isinstance(a, (list, tuple)):
        if not isinstance(b, (list, tuple)) or len(a) != len(b):
            return [(path, a, b)]
        return [d for k, (x, y) in enumerate(zip(a, b)) for d in _differences(x, y, f"{path}[{k}]")]
    return [] if a == b else [(path, a, b)]


def _numbers(x) -> bool:
    if isinstance(x, bool):
        return False
    if isinstance(x, (int, float)):
        return True
    return isinstance(x, (list, tuple)) and len(x) > 0 and all(_numbers(v) for v in x)


def _motion_driven(model) -> bool:
    return bool(model.drivers) and all(d.motion is not None for d in model.drivers)


@pytest.mark.parametrize("path", MECHANISMS, ids=[p.stem for p in MECHANISMS])
def test_a_written_file_reads_back_to_the_same_machine(path):
    model = ks.load(path)
    text = dump(model)
    again = ks.loads(text, "dumped.yaml")
    assert dump(again) == text  # a fixed point: nothing lost or added by a second pass
    assert _differences(model, again, path.stem) == []
    if not _motion_driven(model):
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the file's own warnings, alike on both
        try:
            first = ks.analyze(model)
        except ks.errors.KinetostaticsError:
            return  # a file that needs options to analyse: the fields above are the check
        second = ks.analyze(again)
    assert second.names == first.names
    for name in first.names:
        a, b = np.asarray(first[name], float), np.asarray(second[name], float)
        scale = max(float(np.nanmax(np.abs(a), initial=0.0)), 1e-300)
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        assert np.nanmax(np.abs(a - b), initial=0.0) <= 1e-12 * scale, name


def test_the_cutting_force_and_its_conditions_are_written():
    """The slotting machine's resistance on the ram, active while the tool moves down
    through the middle 90 % of its travel: its keys in SI, as io/loads.py reads them."""
    text = dump(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml"))
    loads = __import__("yaml").safe_load(text)["loads"]
    (spec,) = loads.values()
    assert spec["type"] == "resistance" and spec["link"] == "ram"
    kinds = [next(k for k in ("moving", "travel", "angle") if k in c) for c in spec["active"]]
    assert kinds == ["moving", "travel"]
    lo, hi = spec["active"][1]["travel"]
    assert lo == pytest.approx(0.005) and hi == pytest.approx(0.095)  # m: 0.05 H and 0.95 H


OTHER_FILES = sorted(
    p
    for folder in ("tests/hard", "tests/net/cases", "tests/drive", "tests/dynamics")
    for p in (ROOT / folder).glob("*.yaml")
)


@pytest.mark.parametrize("path", OTHER_FILES, ids=[p.stem for p in OTHER_FILES])
def test_the_test_files_read_back_field_for_field(path):
    """The hard cases, the net's reproducers and the dynamics and drive files: every field
    read back equal (a second dump may differ in a last digit: the reader normalises a
    unit axis again)."""
    model = ks.load(path)
    assert _differences(model, ks.loads(dump(model), "dumped.yaml"), path.stem) == []
