"""Local sensitivities d(quantity)/d(parameter) of a mechanism file, by central differences
on the batch's vectorised path (docs/sensitivity.md).

A quantity is an expression over a variant's batch row and the file's parameters, the
names of ``batch`` and ``optimize`` (``motor.torque_peak``, ``slide.stroke``,
``guide.time_ratio``, ``K``; :class:`~.objectives.Expression`).  A parameter is varied by
its tolerance ``±t`` (:func:`parse_tolerances`: ``a=±0.05`` in the file's units, ``b=±1%``
of its value).  :func:`sensitivity` analyses, as one batch (one chunk: one stacked analysis
unless ``options.chunk`` says otherwise), the nominal design and, for each parameter ``p``,
the variants ``p ± h``, ``p ± 2h`` and ``p ± t``, with the step

    h = ε^(1/3) · max(|p|, t),   ε = 2.2e-16 (so h ≈ 6.1e-6 · max(|p|, t)),

the step that balances the truncation error of a central difference (∝ h²) against the
rounding of the values (∝ ε/h).  The derivative is D(h) = (Q(p+h) − Q(p−h)) / 2h; its error
is estimated as |D(h) − D(2h)| / 3 (D(h) − D′ ≈ c·h², D(2h) − D′ ≈ 4c·h²: Richardson's
estimate of D(h)'s truncation) plus ε·max|Q|/h (the rounding of the values).  A quantity
that is not smooth at p (a peak whose row changes between p − 2h and p + 2h) shows as a
large estimate, and is flagged.  ``Q(p ± t)`` are the tornado chart's ends.

Every variant is a row of :func:`~.runner.run_batch` (processes, serial or Dask, as
:class:`~.runner.BatchOptions` says), read back from its table at full precision; a variant
that fails is reported with its reason, never dropped.  The Monte Carlo analysis is in
:mod:`.tolerance`.
"""

from __future__ import annotations

import math
import re
import tempfile
from collections.abc import Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..base.document import read_text
from ..errors import KinetostaticsError, did_you_mean
from .objectives import Expression, OptimizeError
from .runner import BatchOptions, _check_memory, run_batch
from .sources import Source, Task, template_of
from .table import SUMMARY, column_unit, read_summary
from .variants import analyze_variants

__all__ = [
    "SensitivityError",
    "Tolerance",
    "Derivative",
    "Sensitivity",
    "parse_tolerances",
    "sensitivity",
    "STEP_FACTOR",
    "DEFAULT_QUANTITIES",
]

EPS = float(np.finfo(float).eps)
STEP_FACTOR = EPS ** (1.0 / 3.0)  # h = STEP_FACTOR · max(|p|, t)
# the quantities asked for when none is named: each of these row quantities the nominal
# design has a value of
DEFAULT_QUANTITIES = (
    "stroke",
    "time_ratio",
    "torque_peak",
    "torque_rms",
    "force_peak",
    "force_rms",
    "torque_friction_peak",
    "force_friction_peak",
    "pressure_angle_max",
    "transmission_angle_min",
)
# a derivative whose estimated error is more than this share of it is flagged (when the
# error also moves the quantity by more than FLAG_SCALE of itself over max(|p|, t))
FLAG_SHARE = 1e-3
FLAG_SCALE = 1e-8
_TOLERANCE = re.compile(r"^\s*(?:±|\+-|\+/-)?\s*([^%\s]+)\s*(%?)\s*$")


class SensitivityError(KinetostaticsError, ValueError):
    """A sensitivity or tolerance analysis that cannot start: a bad --vary, --of, --limit
    or option, or a nominal design that cannot be analysed."""


@dataclass(frozen=True)
class Tolerance:
    """A parameter's tolerance: ``nominal`` ± ``half`` (file units); ``text`` as written
    (``±1%``: ``relative``, ``half`` = 1 % of |nominal|)."""

    name: str
    nominal: float
    half: float
    relative: bool
    text: str

    def sd(self, dist: str) -> float:
        """The standard deviation of the parameter's distribution: ``±t`` is 3σ of a
        normal (σ = t/3) or the whole range of a uniform (σ = t/√3)."""
        return self.half / 3.0 if dist == "normal" else self.half / math.sqrt(3.0)

    @property
    def step(self) -> float:
        """The difference step h = ε^(1/3) · max(|p|, t)."""
        return STEP_FACTOR * max(abs(self.nominal), self.half)


def parse_tolerances(
    items: Sequence[str] | Mapping[str, Any], parameters: Mapping[str, float]
) -> tuple[Tolerance, ...]:
    """``["a=±0.05", "b=±1%"]`` or ``{"a": 0.05, "b": "1%"}`` → the tolerances, each
    checked against the file's ``parameters`` (a SensitivityError names the bad one)."""
    if isinstance(items, Mapping):
        pairs = [(str(k), str(v), f"{k}={v}") for k, v in items.items()]
    else:
        pairs = []
        for text in items:
            name, eq, rest = str(text).partition("=")
            if not eq or not name.strip():
                raise SensitivityError(f"--vary {text!r}: expected NAME=±TOL or NAME=±TOL%")
            pairs.append((name.strip(), rest, str(text)))
    out: dict[str, Tolerance] = {}
    for name, tol, written in pairs:
        if name not in parameters:
            raise SensitivityError(
                f"--vary {written}: the file has no parameter '{name}'"
                + (" (it has no parameters: section)" if not parameters else "")
                + did_you_mean(name, list(parameters))
            )
        if name in out:
            raise SensitivityError(f"--vary {name}: named twice; give each parameter once")
        out[name] = _tolerance(name, tol, float(parameters[name]), written)
    if not out:
        raise SensitivityError("nothing to vary: give --vary NAME=±TOL")
    return tuple(out.values())


def _tolerance(name: str, tol: str, nominal: float, written: str) -> Tolerance:
    m = _TOLERANCE.match(tol)
    try:
        value = float(m.group(1)) if m else math.nan
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise SensitivityError(
            f"--vary {written}: the tolerance must be a positive number, ±TOL (file units) "
            "or ±TOL% (of the value)"
        )
    relative = bool(m and m.group(2))
    if relative:
        if nominal == 0:
            raise SensitivityError(
                f"--vary {written}: '{name}' is 0 in the file, so a tolerance in % of it is 0; "
                "give it in the file's units"
            )
        half = value / 100.0 * abs(nominal)
    else:
        half = value
    if not math.isfinite(nominal + half) or not math.isfinite(nominal - half):
        raise SensitivityError(f"--vary {written}: the ends are not finite numbers")
    return Tolerance(name, nominal, half, relative, tol.strip())


# -- the study: the file, its quantities and how its variants run --------------------
@dataclass(frozen=True)
class Study:
    """What every variant of a sensitivity or tolerance analysis shares: the file
    (``source``), the ``tolerances``, the ``quantities`` (expressions, in order), the
    batch ``options`` (the flywheel sized only when a quantity names ``flywheel.…``) and
    the ``nominal`` design's row (file parameters and quantities)."""

    source: Source
    tolerances: tuple[Tolerance, ...]
    quantities: tuple[Expression, ...]
    options: BatchOptions
    nominal: Mapping[str, Any]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(q.text for q in self.quantities)

    def unit(self, k: int) -> str:
        """The unit of quantity ``k``: its row quantity's, or ``file`` for a parameter, or
        empty for an expression of several."""
        names = list(self.quantities[k].names.values())
        if len(names) != 1 or names[0] != self.quantities[k].text:
            return ""
        return column_unit(names[0], self.nominal_parameters)

    @property
    def nominal_parameters(self) -> list[str]:
        return list(template_of(self.source.file, self.source.text).parameters)

    def values(self, row: Mapping[str, Any]) -> np.ndarray:
        """The quantities of a table row (NaN where the row is not ``ok`` or has no value)."""
        if row.get("status") != "ok":
            return np.full(len(self.quantities), np.nan)
        return np.array([q.value(row) for q in self.quantities])


def study(
    path: str | Path,
    vary: Sequence[str] | Mapping[str, Any],
    of: Sequence[str] | None,
    options: BatchOptions | None,
) -> Study:
    """The file read, the tolerances and quantities checked, the nominal design analysed
    (in this process: a SensitivityError when it fails, or names a quantity it lacks)."""
    source = Source(str(path), read_text(path))
    template = template_of(source.file, source.text)
    tolerances = parse_tolerances(vary, template.parameters)
    try:
        quantities = tuple(Expression(q) for q in of or ())
    except OptimizeError as exc:
        raise SensitivityError(f"--of {exc}") from None
    texts = [q.text for q in quantities]
    for q in texts:
        if texts.count(q) > 1:
            raise SensitivityError(f"--of {q!r}: named twice; give each quantity once")
    opts = options or BatchOptions()
    named = [n for q in quantities for n in q.names.values()]
    if opts.flywheel is None:  # sized (variant by variant, slower) only when asked for
        flywheel = None if any(n.startswith("flywheel.") for n in named) else False
        opts = replace(opts, flywheel=flywheel)
    if opts.positions:  # one design's analysis within the memory available, as a batch's
        _check_memory(0, opts.positions, 1)
    row = analyze_variants(
        template, [{}], positions=opts.positions, friction=opts.friction, flywheel=opts.flywheel
    )[0]
    if row["status"] != "ok":
        raise SensitivityError(f"{path}: the nominal design cannot be analysed: {row['reason']}")
    env = {**template.parameters, **row}
    if not quantities:
        quantities = tuple(
            Expression(k)
            for k, v in row.items()
            if k.rpartition(".")[2] in DEFAULT_QUANTITIES
            and isinstance(v, float)
            and math.isfinite(v)
        )
        if not quantities:
            raise SensitivityError(f"{path}: none of the default quantities; name them with --of")
    known = [k for k in env if k not in ("status", "reason")]
    for q in quantities:
        try:
            q.check_names(known, "--of")
        except OptimizeError as exc:
            raise SensitivityError(str(exc)) from None
    return Study(source, tolerances, quantities, opts, env)


@contextmanager
def _folder(out: str | Path | None):
    """``out``, or a temporary folder removed after."""
    if out is not None:
        yield Path(out)
        return
    with tempfile.TemporaryDirectory(prefix="kinetostatics-sensitivity-") as tmp:
        yield Path(tmp)


def batch_rows(
    st: Study, tasks: Sequence[Task], folder: Path, options: BatchOptions
) -> tuple[list[dict[str, str]], Any]:
    """The table rows of ``tasks`` (in their order) run by :func:`run_batch` into
    ``folder``, and its :class:`~.runner.BatchSummary`."""
    keywords = {f.name: getattr(options, f.name) for f in fields(options)}
    summary = run_batch([st.source], list(tasks), folder, **keywords)
    _, rows = read_summary(folder / SUMMARY)
    by_id = {r["variant"]: r for r in rows}
    return [by_id.get(t.vid, {"status": "error", "reason": "missing"}) for t in tasks], summary


# -- the derivatives -------------------------------------------------------------------
@dataclass(frozen=True)
class Derivative:
    """dQ/dp of one quantity and parameter, at the nominal design.

    ``value``: D(h), the central difference at the step ``step`` (the quantity's unit per
    file unit of the parameter); ``error``: its estimate (|D(h) − D(2h)|/3 + ε·max|Q|/h;
    NaN where a ±2h variant failed); ``flagged``: the estimate is more than
    :data:`FLAG_SHARE` of the value (not smooth at p, e.g. a peak changing rows);
    ``elasticity``: (p/Q)·dQ/dp; ``low``, ``high``: Q at p − t and p + t (a tornado
    chart's bar; NaN where that variant failed); ``linear``: D(h)·t, the linearised
    change over the tolerance."""

    quantity: str
    parameter: str
    value: float
    error: float
    step: float
    elasticity: float
    low: float
    high: float
    linear: float
    flagged: bool


@dataclass(frozen=True)
class Sensitivity:
    """The local sensitivities of a file's quantities to its toleranced parameters.

    ``nominal``: each quantity at the nominal design; ``units``: each quantity's;
    ``derivatives``: one per quantity and parameter (quantities outer); ``failed``:
    ``(variant, reason)`` of each variant that could not be analysed; ``variants``,
    ``seconds``: the batch's size and time; ``alone``: variants analysed one by one."""

    file: str
    tolerances: tuple[Tolerance, ...]
    quantities: tuple[str, ...]
    units: tuple[str, ...]
    nominal: tuple[float, ...]
    derivatives: tuple[Derivative, ...]
    failed: tuple[tuple[str, str], ...]
    variants: int
    seconds: float
    alone: int

    def of(self, quantity: str) -> tuple[Derivative, ...]:
        """The derivatives of one quantity, in the tolerances' order."""
        return tuple(d for d in self.derivatives if d.quantity == quantity)

    def linear_sd(self, quantity: str, dist: str) -> float:
        """The linearised standard deviation √Σ (dQ/dp_i · σ_i)² of a quantity under the
        tolerances read as ``dist`` (:meth:`Tolerance.sd`); NaN if a derivative is."""
        sds = {t.name: t.sd(dist) for t in self.tolerances}
        return math.sqrt(sum((d.value * sds[d.parameter]) ** 2 for d in self.of(quantity)))

    def to_dict(self, dist: str | None = None) -> dict[str, Any]:
        """sensitivity.json's ``sensitivity`` part (``linear_sd`` under ``dist``)."""
        out: dict[str, Any] = {
            "file": self.file,
            "step_rule": "h = eps^(1/3) * max(|p|, t), eps = 2.22e-16",
            "error_rule": "|D(h) - D(2h)| / 3 + eps * max|Q| / h",
            "variants": self.variants,
            "analysed_alone": self.alone,
            "seconds": round(self.seconds, 3),
            "quantities": {},
            "failed": [{"variant": v, "reason": r} for v, r in self.failed],
        }
        for q, unit, q0 in zip(self.quantities, self.units, self.nominal):
            entry: dict[str, Any] = {"unit": unit, "nominal": q0, "parameters": {}}
            if dist is not None:
                entry["linear_sd"] = self.linear_sd(q, dist)
            for d in self.of(q):
                entry["parameters"][d.parameter] = {
                    "derivative": d.value,
                    "error": d.error,
                    "step": d.step,
                    "elasticity": d.elasticity,
                    "low": d.low,
                    "high": d.high,
                    "linear_change": d.linear,
                    "flagged": d.flagged,
                }
            out["quantities"][q] = entry
        return out


# the variants of a parameter: (suffix, multiple of h or of t)
_STEPS = (("-2h", -2.0, "h"), ("-h", -1.0, "h"), ("+h", 1.0, "h"), ("+2h", 2.0, "h"))
_ENDS = (("-t", -1.0, "t"), ("+t", 1.0, "t"))


def step_tasks(tolerances: Sequence[Tolerance]) -> list[Task]:
    """The nominal design, then for each parameter its variants at ±h, ±2h and ±t."""
    tasks = [Task("nominal", 0, {})]
    for tol in tolerances:
        for suffix, k, unit in (*_STEPS, *_ENDS):
            delta = k * (tol.step if unit == "h" else tol.half)
            tasks.append(Task(f"{tol.name}{suffix}", 0, {tol.name: tol.nominal + delta}))
    return tasks


def sensitivity(
    path: str | Path,
    vary: Sequence[str] | Mapping[str, Any],
    of: Sequence[str] | None = None,
    *,
    options: BatchOptions | None = None,
    out: str | Path | None = None,
) -> Sensitivity:
    """The local sensitivities of the quantities ``of`` (default: the file's strokes,
    time ratios, peak and RMS efforts, pressure and transmission angles) to the
    parameters ``vary`` (``["a=±0.05", "b=±1%"]``), at the file's design.

    The variants run as one batch (``options``: executor, workers, positions, friction;
    one chunk unless ``options.chunk``), whose table is written to ``out`` (a temporary
    folder when None).  Raises :class:`SensitivityError` for a bad name or tolerance, or a
    nominal design that cannot be analysed.

    >>> s = sensitivity("mechanisms/slider_crank.yaml", ["a=±1"], ["slide.stroke"],
    ...                 options=BatchOptions(executor="serial"))  # doctest: +SKIP
    >>> s.of("slide.stroke")[0].value  # d(stroke, m)/d(a, mm)  # doctest: +SKIP
    0.002001...
    """
    st = study(path, vary, of, options)
    return derivatives(st, out)


def derivatives(st: Study, out: str | Path | None = None) -> Sensitivity:
    """:func:`sensitivity` of a :class:`Study`: its step batch, into ``out/steps``."""
    tasks = step_tasks(st.tolerances)
    opts = replace(st.options, chunk=st.options.chunk or len(tasks), overwrite=True, results=False)
    with _folder(out) as folder:
        rows, summary = batch_rows(st, tasks, folder / "steps" if out else folder, opts)
    values = {t.vid: st.values(r) for t, r in zip(tasks, rows)}
    failed = tuple(
        (t.vid, r.get("reason", "")) for t, r in zip(tasks, rows) if r.get("status") != "ok"
    )
    q0 = values["nominal"]
    ders = []
    for k, q in enumerate(st.names):
        for tol in st.tolerances:
            f = {s: values[f"{tol.name}{s}"][k] for s, _, _ in (*_STEPS, *_ENDS)}
            ders.append(_derivative(q, tol, q0[k], f))
    return Sensitivity(
        st.source.file,
        st.tolerances,
        st.names,
        tuple(st.unit(k) for k in range(len(st.names))),
        tuple(float(v) for v in q0),
        tuple(ders),
        failed,
        len(tasks),
        summary.seconds,
        summary.alone,
    )


def _derivative(q: str, tol: Tolerance, q0: float, f: Mapping[str, float]) -> Derivative:
    """The central difference of one quantity along one parameter, its error estimate and
    the tornado's ends, from the values ``f`` at ``±h``, ``±2h``, ``±t``."""
    h = tol.step
    d1 = (f["+h"] - f["-h"]) / (2.0 * h)
    d2 = (f["+2h"] - f["-2h"]) / (4.0 * h)
    biggest = max(abs(f[s]) for s in ("-2h", "-h", "+h", "+2h"))
    error = abs(d1 - d2) / 3.0 + EPS * biggest / h
    scale = max(abs(tol.nominal), tol.half)
    flagged = bool(
        math.isfinite(d1)
        and error > FLAG_SHARE * abs(d1)
        and error * scale > FLAG_SCALE * max(abs(q0), EPS)
    ) or not math.isfinite(error)
    with np.errstate(all="ignore"):
        elasticity = d1 * tol.nominal / q0 if q0 != 0 else math.nan
    return Derivative(
        q,
        tol.name,
        float(d1),
        float(error),
        h,
        float(elasticity),
        float(f["-t"]),
        float(f["+t"]),
        float(d1 * tol.half),
        flagged,
    )
