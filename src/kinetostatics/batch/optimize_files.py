"""The files of an optimisation: ``best.yaml`` (the file as written, its varied
parameters' values replaced in place), ``designs.csv`` (every evaluated design) and
``convergence.png`` (the best score over the evaluations)."""

from __future__ import annotations

import io
import math
from collections.abc import Sequence
from pathlib import Path

from ..base.files import make_folder, write_whole
from ..base.tables import write_table
from ..errors import output_error

__all__ = ["write_outputs", "with_parameters"]


def with_parameters(text: str, tree, values: dict[str, float]) -> str:
    """``text`` with the values of the parameters ``values`` replaced where they are
    written (the rest of the file, its comments and layout, as it was).  ``tree``: the
    composed file (:func:`~kinetostatics.base.document.compose` of ``text``)."""
    section = tree.get("parameters")
    spans = []
    for name, e in section.items():
        if name in values:
            node = e.node
            spans.append((node.start_mark.index, node.end_mark.index, repr(float(values[name]))))
    for a, b, new in sorted(spans, reverse=True):
        text = text[:a] + new + text[b:]
    return text


def _csv(result, names: Sequence[str], constraints) -> str:
    cols = ["evaluation", "stage", *names, "status", "reason", "objective"]
    cols += [c.text for c in constraints] + ["violation", "score"]
    units = ["", "", *["file"] * len(names), "", "", ""] + [""] * len(constraints) + ["", ""]

    def cell(v):
        if isinstance(v, float):
            return "" if math.isnan(v) else repr(v)
        return "" if v is None else str(v)

    buf = io.StringIO()
    rows = ([cell(d.get(c)) for c in cols] for d in result.designs)
    write_table(buf, cols, units, rows, lineterminator="\n")
    return buf.getvalue()


def _plot(result, path: Path) -> None:
    """The best score after each generation and each local step (a log scale when it
    stays positive and spans more than a decade); the infeasible levels are left out."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from .objectives import INFEASIBLE

    fig = Figure(figsize=(6.4, 4.0), dpi=120)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    xs = list(range(1, len(result.history) + 1))
    ys = [s if s < INFEASIBLE else math.nan for _, _, s in result.history]
    search = [x for x, (stage, _, _) in zip(xs, result.history) if stage == "search"]
    ax.plot(xs, ys, marker=".", lw=1.2)
    if search and len(search) < len(xs):
        ax.axvline(search[-1] + 0.5, color="0.5", ls="--", lw=0.8)
        ax.text(search[-1] + 0.5, 0.98, " local", transform=ax.get_xaxis_transform(), va="top")
    finite = [y for y in ys if math.isfinite(y)]
    if finite and min(finite) > 0 and max(finite) > 10 * min(finite):
        ax.set_yscale("log")
    ax.set_xlabel("generation, then local step")
    ax.set_ylabel("best objective (feasible)")
    ax.set_title("convergence")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, format="png")


def write_outputs(result, source, template, names, constraints, out: Path) -> dict[str, Path]:
    """``out/best.yaml``, ``out/designs.csv``, ``out/convergence.png``."""
    make_folder(out, "--out")
    files = {
        "best": out / "best.yaml",
        "designs": out / "designs.csv",
        "convergence": out / "convergence.png",
    }
    texts = {
        "best": with_parameters(source.text, template.tree, result.parameters),
        "designs": _csv(result, names, constraints),
    }
    for key, text in texts.items():
        try:
            write_whole(files[key], lambda tmp, text=text: tmp.write_text(text, encoding="utf-8"))
        except OSError as exc:
            raise output_error(exc, str(files[key])) from None
    try:
        write_whole(files["convergence"], lambda tmp: _plot(result, tmp))
    except OSError as exc:
        raise output_error(exc, str(files["convergence"])) from None
    return files
