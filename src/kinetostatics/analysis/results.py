"""The result of an analysis: named arrays over the positions, and their export.

Column names and units are those of ``results.csv`` (docs/conventions.md).  Angles are
in rad inside the arrays ``q``, ``qd``, ``qdd``; the named columns follow the
CSV (``angle``, ``travel`` and ``<link>.theta`` in degrees).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..base.files import json_text
from ..base.tables import write_columns
from ..errors import did_you_mean
from ..structure.system import System
from .checks import result_checks
from .columns import build_columns, element_warnings, joint_warnings
from .frames import html_repr, members, select, short_repr, to_pandas, to_xarray
from .summary import summarize

if TYPE_CHECKING:  # the optional table packages, for the return types only
    import pandas
    import xarray

    from .summary import CycleRecords

__all__ = ["Result", "build_columns", "joint_warnings", "element_warnings"]


@dataclass(frozen=True, repr=False)
class Result:
    """Named arrays over the positions, with the raw arrays for advanced use.

    :func:`analyze` makes it: ``result["rod.omega"]`` is a column, ``result.units`` the
    units, ``result.checks`` the self-checks (computed on first use).

    Parameters
    ----------
    system : System
        The compiled mechanism.
    t, coordinate : numpy.ndarray
        Time (s) and driver coordinate (rad or m) of each position, ``(n_pos,)``.
    q, qd, qdd, lam : numpy.ndarray
        Poses, velocities, accelerations ``(n_pos, n_q)``; multipliers ``(n_pos, n_lam)``.
    columns, units : mapping of str to numpy.ndarray, dict of str to str
        The named columns in CSV order, and their units.
    events, singular : tuple, optional
        The load switches and the singular positions met.
    indeterminate, full_cycle : bool, optional
        Some reactions are statically indeterminate; the positions span a cycle.
    extremes : dict, optional
        The travel extremes of the output members.
    lam_friction : numpy.ndarray, optional
        ``lam`` of the consistent friction solution (None without it).

    Examples
    --------
    >>> import kinetostatics as ks
    >>> result = ks.analyze(ks.load("mechanisms/slider_crank.yaml"))  # doctest: +SKIP
    >>> result.units["motor.torque"], result.checks.ok  # doctest: +SKIP
    ('N*m', True)
    """

    system: System
    t: np.ndarray
    coordinate: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    lam: np.ndarray
    columns: Mapping[str, np.ndarray]
    units: dict[str, str]
    events: tuple = ()
    singular: tuple = ()
    indeterminate: bool = False
    full_cycle: bool = True
    extremes: dict = field(default_factory=dict)
    lam_friction: np.ndarray | None = None

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f"no column '{name}'{did_you_mean(name, self.columns)}") from None

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:

        return short_repr(self)

    def _repr_html_(self) -> str:

        return html_repr(self)

    def members(self) -> dict[str, list[str]]:
        """Group the column names by member (link, joint, driver, load…).

        Returns
        -------
        dict of str to list of str
            ``{member: [names]}``; a name is ``member.quantity``, split at the first dot.

        Examples
        --------
        >>> result.members()["motor"][0]  # doctest: +SKIP
        'motor.torque'
        """
        return members(self)

    def select(self, member: str) -> dict[str, np.ndarray]:
        """Return one member's columns by quantity.

        Parameters
        ----------
        member : str
            A link, joint, driver, load… (a key of :meth:`members`).

        Returns
        -------
        dict of str to numpy.ndarray
            ``{quantity: column}``: ``select("rod")["B.vx"]`` is ``result["rod.B.vx"]``.

        Raises
        ------
        KeyError
            No column belongs to ``member``.

        Examples
        --------
        >>> result.select("rod")["B.vx"] is result["rod.B.vx"]  # doctest: +SKIP
        True
        """
        return select(self, member)

    def to_pandas(self, multiindex: bool = False) -> pandas.DataFrame:
        """Return the columns as a pandas DataFrame (``pip install 'kinetostatics[pandas]'``).

        Parameters
        ----------
        multiindex : bool, default False
            Split each name at its first dot: ``rod.omega`` becomes ``("rod", "omega")``.

        Returns
        -------
        pandas.DataFrame
            One row per position; the units in ``df.attrs["units"]``.

        Raises
        ------
        MissingPackageError
            pandas is not installed (the message gives the line that installs it).

        Examples
        --------
        >>> result.to_pandas(multiindex=True)["rod"]["omega"].max()  # doctest: +SKIP
        """
        return to_pandas(self, multiindex)

    def to_xarray(self) -> xarray.Dataset:
        """Return the columns as an xarray Dataset over the dimension ``position``.

        Returns
        -------
        xarray.Dataset
            One variable per column, its unit as attribute (needs the xarray extra).

        Raises
        ------
        MissingPackageError
            xarray is not installed (the message gives the line that installs it).

        Examples
        --------
        >>> result.to_xarray()["motor.torque"].attrs["units"]  # doctest: +SKIP
        'N*m'
        """
        return to_xarray(self)

    @cached_property
    def checks(self):
        """Self-checks (:class:`~kinetostatics.analysis.checks.Checks`): constraint and
        power-balance residuals, sketch distance, group condition, friction status, each against its
        tolerance; ``checks.ok``, ``checks.failed()``.  Computed on first use."""

        return result_checks(self)

    @property
    def names(self) -> list[str]:
        return list(self.columns)

    def to_csv(self, path: str | Path) -> None:
        """Write the columns as CSV: a ``# units:`` line, the header, a row per position.

        Parameters
        ----------
        path : str or pathlib.Path
            The file to write.

        Examples
        --------
        >>> result.to_csv("results.csv")  # doctest: +SKIP
        """
        write_columns(path, self.columns, self.units)

    def to_dict(self) -> dict[str, Any]:
        """Return the columns and units as JSON-safe lists and dicts.

        Returns
        -------
        dict of str to Any
            ``{"columns": {name: [float or None, ...]}, "units": {name: unit}}``.

        Examples
        --------
        >>> result.to_dict()["units"]["motor.torque"]  # doctest: +SKIP
        'N*m'
        """
        return {
            "columns": {
                n: [None if not np.isfinite(v) else float(v) for v in a]
                for n, a in self.columns.items()
            },
            "units": dict(self.units),
        }

    def summary(self, cycle: CycleRecords | None = None) -> dict[str, Any]:
        """The summary of the result (summary.json's keys), formatted; nothing is solved.

        Parameters
        ----------
        cycle : Cycle, optional
            The cycle's records (:func:`~kinetostatics.dynamics.stages.cycle_stage`):
            the driving efforts' means and RMS, the output strokes, the self-locked
            zones, the flywheel and the drive, as ``kinetostatics run`` writes them.
            Without it, what the rows hold: the extremes of every column, the reaction
            peaks, the events, the singular positions, the self-checks and the driving
            efforts' peaks.

        Returns
        -------
        dict
            JSON-safe (:func:`~kinetostatics.analysis.summary.summarize`).

        Examples
        --------
        >>> from kinetostatics.dynamics.stages import cycle_stage
        >>> rows_only = result.summary()  # doctest: +SKIP
        >>> as_run_writes_it = result.summary(cycle_stage(result))  # doctest: +SKIP
        """
        return summarize(self, cycle)

    def to_json(
        self,
        path: str | Path,
        summary: dict[str, Any] | None = None,
        *,
        cycle: CycleRecords | None = None,
    ) -> None:
        """Write the summary as JSON.

        Parameters
        ----------
        path : str or Path
            The file.
        summary : dict, optional
            The summary already computed; default :meth:`summary` of ``cycle``.
        cycle : Cycle, optional
            The cycle's records, as for :meth:`summary`.

        Examples
        --------
        >>> result.to_json("summary.json")  # doctest: +SKIP
        """
        data = self.summary(cycle) if summary is None else summary
        Path(path).write_text(json_text(data, ensure_ascii=False), encoding="utf-8")
