"""Monte Carlo tolerance analysis of a mechanism file on the batch's path
(docs/sensitivity.md).

:func:`monte_carlo` draws ``samples`` designs, each toleranced parameter independently
(``numpy.random.default_rng(seed)``, one array of samples × parameters): ``normal``, its
tolerance ``±t`` read as 3σ (σ = t/3: 99.73 % of the designs within ±t, the rest beyond);
or ``uniform`` on [p − t, p + t].  The designs are the rows of one batch
(:func:`~.runner.run_batch`: processes, serial or Dask as :class:`~.runner.BatchOptions`
says, in chunks, resumable in its folder).  Each quantity's values over the designs that
were analysed give its mean, standard deviation, percentiles and histogram; each limit
(``"Q <= X"``) the share of those designs outside it.  A design that cannot be analysed (it
does not assemble over the cycle) is counted as failed, with its reason: never dropped
silently.  The share of designs outside the limits *or* failed is reported beside.
"""

from __future__ import annotations

import math
import re
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from .objectives import Constraint, OptimizeError
from .runner import BatchOptions
from .sensitivity import SensitivityError, Study, _folder, batch_rows, study
from .sources import Task

__all__ = ["Spread", "LimitShare", "MonteCarlo", "monte_carlo", "DISTRIBUTIONS", "PERCENTILES"]

DISTRIBUTIONS = ("normal", "uniform")
PERCENTILES = (0.135, 1.0, 5.0, 50.0, 95.0, 99.0, 99.865)  # 99.73 % between the ends: ±3σ
MAX_SAMPLES = 10_000_000


@dataclass(frozen=True)
class Spread:
    """One quantity over the designs analysed: ``n`` values (finite), ``mean``, ``sd``
    (the sample's, n − 1), ``sd_error`` (the standard error of ``sd``: sd/√(2(n − 1)) for a
    normal quantity), ``percentiles`` (:data:`PERCENTILES` → value), ``low``/``high`` (the
    least and largest), ``edges`` and ``counts`` of its histogram, ``missing`` (designs
    analysed where it has no value) and ``linear_sd`` (the linearised σ, when the
    sensitivities are known; else NaN)."""

    quantity: str
    unit: str
    nominal: float
    n: int
    mean: float
    sd: float
    sd_error: float
    percentiles: tuple[tuple[float, float], ...]
    low: float
    high: float
    edges: tuple[float, ...]
    counts: tuple[int, ...]
    missing: int
    linear_sd: float


@dataclass(frozen=True)
class LimitShare:
    """A limit ``text`` (``"Q <= X"``): ``outside`` designs (of the ``analysed`` ones) that
    break it, and ``no_value`` where a side has no value."""

    text: str
    outside: int
    no_value: int
    analysed: int

    @property
    def share(self) -> float:
        """The share of the analysed designs outside the limit."""
        return self.outside / self.analysed if self.analysed else math.nan


@dataclass(frozen=True)
class MonteCarlo:
    """A Monte Carlo tolerance analysis: ``samples`` designs drawn as ``dist`` with
    ``seed``; ``parameters`` ``(samples, n)`` (file units, the tolerances' order) and
    ``values`` ``(samples, m)`` (the quantities', NaN where a design failed or has no
    value); ``status`` and reason of each design; ``spreads`` of each quantity; ``limits``;
    ``failed`` (designs not analysed) with their ``reasons``: (a reason, how many) of the
    reasons alike but for their numbers, most frequent first; ``outside_any`` (analysed
    designs outside some limit); ``seconds``, ``alone`` (analysed one by one), ``reused``
    (rows from an earlier run)."""

    file: str
    dist: str
    seed: int
    samples: int
    tolerances: tuple
    quantities: tuple[str, ...]
    parameters: np.ndarray
    values: np.ndarray
    status: tuple[str, ...]
    reasons_by_sample: tuple[str, ...]
    spreads: tuple[Spread, ...]
    limits: tuple[LimitShare, ...]
    failed: int
    reasons: tuple[tuple[str, int], ...]
    outside_any: int
    seconds: float
    alone: int
    reused: int

    @property
    def analysed(self) -> int:
        return self.samples - self.failed

    @property
    def share_lost(self) -> float:
        """The share of all designs outside some limit or failed (a failed design counts
        as lost: it cannot be built to work)."""
        return (self.outside_any + self.failed) / self.samples

    def to_dict(self) -> dict[str, Any]:
        """sensitivity.json's ``monte_carlo`` part."""
        return {
            "dist": self.dist,
            "tolerance_reading": (
                "±t is 3 standard deviations of a normal distribution (sigma = t/3)"
                if self.dist == "normal"
                else "±t is the whole range of a uniform distribution (sigma = t/sqrt(3))"
            ),
            "seed": self.seed,
            "samples": self.samples,
            "analysed": self.analysed,
            "failed": self.failed,
            "failed_reasons": [{"reason": r, "count": c} for r, c in self.reasons],
            "analysed_alone": self.alone,
            "reused": self.reused,
            "seconds": round(self.seconds, 3),
            "quantities": {s.quantity: _spread_dict(s) for s in self.spreads},
            "limits": [
                {
                    "limit": lim.text,
                    "outside": lim.outside,
                    "no_value": lim.no_value,
                    "analysed": lim.analysed,
                    "share_outside": lim.share,
                }
                for lim in self.limits
            ],
            "outside_any_limit": self.outside_any,
            "share_outside_or_failed": self.share_lost,
        }


def _spread_dict(s: Spread) -> dict[str, Any]:
    return {
        "unit": s.unit,
        "nominal": s.nominal,
        "n": s.n,
        "missing": s.missing,
        "mean": s.mean,
        "sd": s.sd,
        "sd_error": s.sd_error,
        "linear_sd": s.linear_sd,
        "percentiles": {f"p{p:g}": v for p, v in s.percentiles},
        "min": s.low,
        "max": s.high,
        "histogram": {"edges": list(s.edges), "counts": list(s.counts)},
    }


def draw(tolerances: Sequence, samples: int, dist: str, seed: int) -> np.ndarray:
    """The designs ``(samples, n)``: ``numpy.random.default_rng(seed)``, one array."""
    rng = np.random.default_rng(seed)
    p = np.array([t.nominal for t in tolerances])
    half = np.array([t.half for t in tolerances])
    if dist == "normal":
        return p + (half / 3.0) * rng.standard_normal((samples, len(tolerances)))
    return p + half * rng.uniform(-1.0, 1.0, (samples, len(tolerances)))


def parse_limits(limits: Sequence[str], known: Sequence[str]) -> tuple[Constraint, ...]:
    """``["Q <= X", …]`` as constraints, each name checked (a SensitivityError names it)."""
    out = []
    for text in limits:
        try:
            c = Constraint.parse(text)
            c.check_names(known)
        except OptimizeError as exc:
            msg = str(exc).replace("--subject-to", "--limit")
            raise SensitivityError(msg) from None
        out.append(c)
    return tuple(out)


def check_options(samples: int, dist: str, seed: int) -> None:
    """SensitivityError for an option out of its range."""
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)):
        raise SensitivityError(f"--samples {samples!r}: must be a whole number")
    if not 2 <= samples <= MAX_SAMPLES:
        raise SensitivityError(f"--samples {samples}: must be from 2 to {MAX_SAMPLES}")
    if dist not in DISTRIBUTIONS:
        raise SensitivityError(f"--dist {dist!r}: use normal or uniform")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise SensitivityError(f"--seed {seed!r}: must be a whole number")
    if not 0 <= seed <= 2**63 - 1:
        raise SensitivityError(f"--seed {seed}: must be from 0 to {2**63 - 1}")


def monte_carlo(  # noqa: PLR0913  the public keywords (docs/sensitivity.md)
    path: str | Path,
    vary: Sequence[str] | Mapping[str, Any],
    of: Sequence[str] | None = None,
    *,
    samples: int = 1000,
    dist: str = "normal",
    seed: int = 0,
    limits: Sequence[str] = (),
    options: BatchOptions | None = None,
    out: str | Path | None = None,
    linear: Mapping[str, float] | None = None,
) -> MonteCarlo:
    """A Monte Carlo tolerance analysis of the quantities ``of`` (as
    :func:`~.sensitivity.sensitivity`) over ``samples`` designs drawn within the
    tolerances ``vary`` as ``dist`` (``normal``: ±t is 3σ; ``uniform``), seeded.

    ``limits`` (``"motor.torque_peak <= 120"``): the share of designs outside each;
    ``options``: the batch's executor, workers, chunk, positions, friction, progress, and
    ``overwrite`` (start afresh in an ``out`` holding another analysis; the same analysis
    run again resumes); ``out``: the folder of the batch's table (temporary when None);
    ``linear``: the linearised σ of each quantity, to report beside the sample's.

    >>> mc = monte_carlo("mechanisms/slider_crank.yaml", ["a=±0.1"], ["slide.stroke"],
    ...                  samples=200, options=BatchOptions(executor="serial"))  # doctest: +SKIP
    >>> mc.spreads[0].sd  # doctest: +SKIP
    6.68...e-05
    """
    check_options(samples, dist, seed)
    st = study(path, vary, of, options)
    return run_samples(st, samples, dist, seed, limits, out, linear)


def run_samples(  # noqa: PLR0913  the study and its Monte Carlo options
    st: Study,
    samples: int,
    dist: str,
    seed: int,
    limits: Sequence[str] = (),
    out: str | Path | None = None,
    linear: Mapping[str, float] | None = None,
) -> MonteCarlo:
    """:func:`monte_carlo` of a :class:`~.sensitivity.Study`, its batch into ``out/samples``."""
    check_options(samples, dist, seed)
    known = [k for k in st.nominal if k not in ("status", "reason")]
    constraints = parse_limits(limits, known)
    x = draw(st.tolerances, samples, dist, seed)
    names = [t.name for t in st.tolerances]
    width = len(str(samples))
    tasks = [
        Task(f"{k + 1:0{width}d}", 0, {n: float(v) for n, v in zip(names, row)})
        for k, row in enumerate(x)
    ]
    opts = replace(st.options, results=False)
    with _folder(out) as folder:
        rows, summary = batch_rows(st, tasks, folder / "samples" if out else folder, opts)
    values = np.array([st.values(r) for r in rows]).reshape(samples, len(st.quantities))
    status = tuple(r.get("status", "error") for r in rows)
    ok = np.array([s == "ok" for s in status])
    reasons = _reasons([r.get("reason", "") for r, good in zip(rows, ok) if not good])
    shares = []
    outside_any = np.zeros(samples, dtype=bool)
    for c in constraints:
        margins = np.array([c.margin(r) if good else math.nan for r, good in zip(rows, ok)])
        with np.errstate(invalid="ignore"):
            bad = ok & (margins < 0)
        outside_any |= bad
        shares.append(
            LimitShare(c.text, int(bad.sum()), int((ok & np.isnan(margins)).sum()), int(ok.sum()))
        )
    spreads = tuple(
        _spread(q, st.unit(k), float(st.quantities[k].value(st.nominal)), values[ok, k], linear)
        for k, q in enumerate(st.names)
    )
    return MonteCarlo(
        st.source.file,
        dist,
        seed,
        samples,
        st.tolerances,
        st.names,
        x,
        values,
        status,
        tuple(r.get("reason", "") for r in rows),
        spreads,
        tuple(shares),
        int((~ok).sum()),
        reasons,
        int(outside_any.sum()),
        summary.seconds,
        summary.alone,
        summary.reused,
    )


_NUMBER = re.compile(r"[-+]?\d+(?:\.\d*)?(?:e[-+]?\d+)?")


def _reasons(texts: Sequence[str]) -> tuple[tuple[str, int], ...]:
    """The failed designs' reasons grouped by their words (the numbers in them — the angle
    where a design stops assembling, its gap — differ from design to design): ``(the first
    design's reason, how many)``, the most frequent first."""
    groups: Counter = Counter()
    first: dict[str, str] = {}
    for text in texts:
        key = _NUMBER.sub("#", text)
        groups[key] += 1
        first.setdefault(key, text)
    return tuple((first[k], c) for k, c in groups.most_common())


def _spread(q: str, unit: str, nominal: float, v: np.ndarray, linear) -> Spread:
    """The statistics of one quantity's values ``v`` over the designs analysed."""
    finite = v[np.isfinite(v)]
    n = len(finite)
    lin = float(linear[q]) if linear and q in linear else math.nan
    if n == 0:
        nan = math.nan
        return Spread(q, unit, nominal, 0, nan, nan, nan, (), nan, nan, (), (), len(v), lin)
    sd = float(np.std(finite, ddof=1)) if n > 1 else math.nan
    bins = int(min(50, max(10, round(math.sqrt(n)))))
    if finite.max() == finite.min():
        counts, edges = np.array([n]), np.array([finite.min(), finite.max()])
    else:
        counts, edges = np.histogram(finite, bins=bins)
    return Spread(
        q,
        unit,
        nominal,
        n,
        float(finite.mean()),
        sd,
        sd / math.sqrt(2.0 * (n - 1)) if n > 1 else math.nan,
        tuple((p, float(np.percentile(finite, p))) for p in PERCENTILES),
        float(finite.min()),
        float(finite.max()),
        tuple(float(e) for e in edges),
        tuple(int(c) for c in counts),
        len(v) - n,
        lin,
    )
