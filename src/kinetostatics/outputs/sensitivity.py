"""sensitivity.md: the page ``kinetostatics sensitivity`` writes beside sensitivity.json
(docs/sensitivity.md), in English, from the records of ``batch.sensitivity`` and
``batch.tolerance`` read by their attributes (this layer does not import the batch's)."""

from __future__ import annotations

import math

__all__ = ["sensitivity_markdown"]


def _g(x: float, digits: int = 6) -> str:
    return f"{x:.{digits}g}" if isinstance(x, (int, float)) and math.isfinite(x) else "—"


def _unit(unit: str) -> str:
    return "" if unit in ("", "1") else f" {unit}"


def sensitivity_markdown(sens, mc=None, pictures=()) -> str:
    """The page: the tolerances, each quantity's derivatives with their error estimates and
    steps, its tornado chart, and with ``mc`` the Monte Carlo's spread, percentiles, limits
    and failed designs.  ``pictures``: ``(title, file name)`` of the pictures written."""
    lines = [f"# Sensitivity and tolerances: {sens.file}", ""]
    lines += [
        "Tolerances (`--vary`), in the file's units:",
        "",
        "| parameter | nominal | tolerance ±t | step h |",
        "|---|---|---|---|",
    ]
    for t in sens.tolerances:
        tol = f"{t.text} = ±{_g(t.half)}" if t.relative else f"±{_g(t.half)}"
        lines.append(f"| `{t.name}` | {_g(t.nominal, 10)} | {tol} | {_g(t.step, 4)} |")
    lines += [
        "",
        "Each derivative is the central difference D(h) = (Q(p + h) − Q(p − h)) / 2h with "
        "h = ε^(1/3)·max(|p|, t); its error estimate is |D(h) − D(2h)| / 3 + ε·max|Q| / h. "
        "`Q(p − t)` and `Q(p + t)` are the quantity with one parameter at a time at the "
        "ends of its tolerance (the tornado chart's bars); the elasticity is (p/Q)·dQ/dp. "
        f"{sens.variants} designs in one batch, {sens.seconds:.2f} s.",
        "",
    ]
    for k, q in enumerate(sens.quantities):
        unit = _unit(sens.units[k])
        lines += [f"## `{q}`", "", f"Nominal: {_g(sens.nominal[k], 10)}{unit}.", ""]
        u = sens.units[k]
        per = f" [{u} per unit of p]" if unit else ""  # p in the file's units
        q_in = f" [{u}]" if unit else ""
        lines += [
            f"| parameter | dQ/dp{per} | error estimate{per} | elasticity [1] "
            f"| Q(p − t){q_in} | Q(p + t){q_in} | note |",
            "|---|---|---|---|---|---|---|",
        ]
        for d in sens.of(q):
            note = "not smooth here: see the error" if d.flagged else ""
            lines.append(
                f"| `{d.parameter}` | {_g(d.value, 8)} | {_g(d.error, 2)} | "
                f"{_g(d.elasticity, 4)} | {_g(d.low, 8)} | {_g(d.high, 8)} | {note} |"
            )
        lines.append("")
        if mc is not None:
            lines += _spread_lines(mc, q)
        for title, name in pictures:
            if title.endswith(f" {q}"):
                lines += [f"![{title}]({name})", ""]
    if sens.failed:
        lines += ["Designs of the sensitivity batch that could not be analysed:", ""]
        lines += [f"- `{v}`: {r}" for v, r in sens.failed] + [""]
    if mc is not None:
        lines += _monte_carlo_lines(mc)
    return "\n".join(lines).rstrip() + "\n"


def _spread_lines(mc, q: str) -> list[str]:
    sp = next(s for s in mc.spreads if s.quantity == q)
    pts = ", ".join(f"{p:g} %: {_g(v, 8)}" for p, v in sp.percentiles)
    out = [
        f"Monte Carlo ({sp.n} designs with a value): mean {_g(sp.mean, 8)}, standard "
        f"deviation {_g(sp.sd, 4)} ± {_g(sp.sd_error, 2)} (linearised: {_g(sp.linear_sd, 4)}), "
        f"least {_g(sp.low, 8)}, largest {_g(sp.high, 8)}.",
        "",
        f"Percentiles: {pts}.",
        "",
    ]
    if sp.missing:
        out += [f"{sp.missing} designs analysed have no value of it.", ""]
    return out


def _monte_carlo_lines(mc) -> list[str]:
    reading = (
        "each tolerance ±t read as 3 standard deviations of a normal distribution (σ = t/3; "
        "0.27 % of the designs fall beyond ±t)"
        if mc.dist == "normal"
        else "each tolerance ±t the whole range of a uniform distribution (σ = t/√3)"
    )
    out = [
        "## Monte Carlo",
        "",
        f"{mc.samples} designs, seed {mc.seed}, {reading}; the parameters drawn "
        f"independently. {mc.analysed} analysed, {mc.failed} failed "
        f"({mc.seconds:.2f} s{f', {mc.reused} from an earlier run' if mc.reused else ''}).",
        "",
    ]
    if mc.limits:
        out += ["| limit | outside | of the designs analysed | share |", "|---|---|---|---|"]
        for lim in mc.limits:
            out.append(
                f"| `{lim.text}` | {lim.outside} | {lim.analysed} | {_g(100 * lim.share, 4)} % |"
            )
        out += [
            "",
            f"Outside some limit: {mc.outside_any}; outside some limit or failed: "
            f"{mc.outside_any + mc.failed} of {mc.samples} ({_g(100 * mc.share_lost, 4)} %).",
            "",
        ]
    if mc.reasons:
        out += ["Failed designs, by reason:", ""]
        out += [f"- {c} × {r}" for r, c in mc.reasons[:10]]
        if len(mc.reasons) > 10:
            out.append(f"- … and {len(mc.reasons) - 10} more reasons (samples.csv has each)")
        out.append("")
    return out
