"""A result as tables: members and their columns, pandas and xarray, the short text.

**The naming rule.**  A column name is ``member.quantity``, split at the *first* dot:
``rocker.y`` is the quantity ``y`` of the link ``rocker``; ``rocker.B.vx`` the quantity
``B.vx`` (point ``B``) of the same link; ``A.Fx`` a reaction of joint ``A``;
``motor.torque`` the effort of driver ``motor``; ``power.input``, ``friction.status``,
``shaking.Fx`` and ``<links>.cond`` belong to the members ``power``, ``friction``,
``shaking`` and the group ``<links>``.  A column without a dot (``time``, ``angle`` or
``stroke``, ``travel``) is its own member, with the empty quantity ``""``.

pandas and xarray are optional (``pip install 'kinetostatics[pandas]'``,
``'kinetostatics[xarray]'``) and imported only here, when a table is asked for.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..base.optional import require
from ..errors import did_you_mean

__all__ = ["split", "members", "select", "to_pandas", "to_xarray", "short_repr", "html_repr"]

COORDINATES = ("time", "angle", "stroke", "travel")  # the position coordinates


def split(name: str) -> tuple[str, str]:
    """``(member, quantity)`` of a column name: split at the first dot (module docstring)."""
    member, _, quantity = name.partition(".")
    return member, quantity


def members(result) -> dict[str, list[str]]:
    """``{member: [its column names]}``, members and columns in CSV order."""
    out: dict[str, list[str]] = {}
    for name in result.columns:
        out.setdefault(split(name)[0], []).append(name)
    return out


def select(result, member: str) -> dict[str, np.ndarray]:
    """``{quantity: array}`` of the columns of ``member`` (a link, joint, driver, load,
    group, or ``power``…), in CSV order; a member with no column raises ``KeyError``
    naming the members."""
    groups = members(result)
    if member not in groups:
        raise KeyError(
            f"no member '{member}'{did_you_mean(member, groups)}; "
            f"the members are: {', '.join(groups)}"
        )
    return {split(name)[1]: result[name] for name in groups[member]}


def to_pandas(result, multiindex: bool = False):
    """A :class:`pandas.DataFrame`, one row per position (index ``position``), one
    column per result column in CSV order; ``df.attrs["units"]`` maps each column name
    to its unit.  ``multiindex=True``: the columns are ``(member, quantity)`` pairs
    (``("rocker", "y")``, ``("time", "")``), the units keyed by those pairs."""
    pd = require("pandas", "pandas", "Result.to_pandas()")
    names = list(result.columns)
    data = {name: result[name] for name in names}
    df = pd.DataFrame(data, index=pd.RangeIndex(len(result), name="position"))
    units = {name: result.units[name] for name in names}
    if multiindex:
        df.columns = pd.MultiIndex.from_tuples(
            [split(n) for n in names], names=["member", "quantity"]
        )
        units = {split(n): u for n, u in units.items()}
    df.attrs["units"] = units
    df.attrs["mechanism"] = result.system.model.name
    return df


def to_xarray(result):
    """An :class:`xarray.Dataset` with one dimension ``position``; ``time``, the driver
    coordinate (``angle`` in deg or ``stroke`` in m) and ``travel`` are coordinates along
    it (the driver coordinate indexed, so ``ds.sel(angle=90)`` works when no angle
    repeats), every other column a variable; each has its unit in ``attrs["units"]``."""
    xr = require("xarray", "xarray", "Result.to_xarray()")
    coords: dict[str, Any] = {"position": np.arange(len(result))}
    data: dict[str, Any] = {}
    for name in result.columns:
        entry = ("position", result[name], {"units": result.units[name]})
        (coords if name in COORDINATES else data)[name] = entry
    ds = xr.Dataset(data, coords=coords, attrs={"mechanism": result.system.model.name})
    driver = "angle" if "angle" in ds.coords else "stroke"
    values = ds[driver].values
    if len(np.unique(values)) == len(values):
        ds = ds.set_xindex(driver)
    return ds


def _checks_text(result) -> str:
    try:
        checks = result.checks
    except Exception as exc:  # a repr must not fail
        return f"checks not available ({type(exc).__name__})"
    if checks.ok:
        return "checks ok"
    return "checks FAILED: " + ", ".join(c.name for c in checks.failed())


def short_repr(result) -> str:
    """``<Result 'slider_crank': 360 positions, 106 columns, 12 members; checks ok>``."""
    n_members = len(members(result))
    return (
        f"<Result {result.system.model.name!r}: {len(result)} positions, "
        f"{len(result.columns)} columns, {n_members} members; {_checks_text(result)}>"
    )


def html_repr(result, rows: int = 5, columns: int = 12) -> str:
    """The notebook view: the short text, the members, and the first ``rows`` rows of
    the first ``columns`` columns as a small HTML table."""
    import html  # here, not at the top: html.entities costs every command's start ~2 ms

    names = list(result.columns)[:columns]
    head = "".join(
        f"<th>{html.escape(n)}<br><small>{html.escape(result.units[n])}</small></th>" for n in names
    )
    body = "".join(
        "<tr>" + "".join(f"<td>{float(result[n][k]):.6g}</td>" for n in names) + "</tr>"
        for k in range(min(rows, len(result)))
    )
    more = len(result.columns) - len(names)
    groups = members(result)
    return (
        f"<div><p>{html.escape(short_repr(result))}</p>"
        f"<p><small>members: {html.escape(', '.join(groups))}</small></p>"
        f"<table><tr>{head}</tr>{body}</table>"
        f"<p><small>first {min(rows, len(result))} rows"
        + (f"; {more} more columns" if more else "")
        + "</small></p></div>"
    )
