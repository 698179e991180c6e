"""Checks of numbers passed to the Python API (``analyze(positions=...)``,
``simulate(until=...)``): a plain ``ValueError`` naming the argument, the
offending entry and its value (a call from Python is not a file: see
docs/errors.md).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["real_array", "real_number"]


def real_array(
    name: str, values, *, low: float | None = None, high: float | None = None, why: str = ""
) -> np.ndarray:
    """``values`` as a non-empty 1-D float array of finite real numbers in [low, high];
    ``why`` explains the bounds in the message."""
    try:
        arr = np.asarray(values)
    except Exception as exc:  # ragged lists and the like
        raise ValueError(f"{name} must be a 1-D sequence of numbers ({exc})") from None
    if arr.dtype.kind not in "biuf":
        kind = "complex numbers" if arr.dtype.kind == "c" else f"{arr.dtype} values"
        raise ValueError(f"{name} must be a 1-D sequence of real numbers, got {kind}")
    if arr.ndim != 1:
        raise ValueError(
            f"{name} must be a 1-D sequence of numbers, got an array of shape {arr.shape}"
        )
    if arr.size == 0:
        raise ValueError(f"{name} is empty: give at least one value")
    arr = arr.astype(float)
    bad = ~np.isfinite(arr)
    if low is not None:
        bad |= arr < low
    if high is not None:
        bad |= arr > high
    if bad.any():
        k = int(np.argmax(bad))
        raise ValueError(f"{name}[{k}] = {float(arr[k])!r}: " + _expected(low, high, why))
    return arr


def real_number(
    name: str,
    value,
    *,
    low: float | None = None,
    high: float | None = None,
    strict_low: bool = False,
    strict_high: bool = False,
    why: str = "",
) -> float:
    """``value`` as a finite real float in [low, high] (``strict_low``: > low,
    ``strict_high``: < high)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(
        value, (int, float, np.integer, np.floating)
    ):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    v = float(value)
    if (
        not math.isfinite(v)
        or (low is not None and (v < low or (strict_low and v == low)))
        or (high is not None and (v > high or (strict_high and v == high)))
    ):
        bounds = _expected(low, high, why)
        if strict_low and strict_high and low is not None and high is not None:
            bounds = bounds.replace(
                f"from {low:g} to {high:g}", f"greater than {low:g} and below {high:g}", 1
            )
        elif strict_low and low is not None and high is not None:
            bounds = bounds.replace(
                f"from {low:g} to {high:g}", f"greater than {low:g} and at most {high:g}", 1
            )
        elif strict_low:
            bounds = bounds.replace("of at least", "greater than", 1)
        raise ValueError(f"{name} = {v!r}: {bounds}")
    return v


def _expected(low, high, why: str) -> str:
    if low is not None and high is not None:
        text = f"expected a finite number from {low:g} to {high:g}"
    elif low is not None:
        text = f"expected a finite number of at least {low:g}"
    elif high is not None:
        text = f"expected a finite number of at most {high:g}"
    else:
        text = "expected a finite number"
    return text + (f" ({why})" if why else "")
