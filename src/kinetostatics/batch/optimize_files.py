"""The files of an optimisation: ``best.yaml`` (the file as written, its varied
parameters' values replaced in place, after a comment for each parameter on a bound),
``designs.csv`` (every evaluated design, appended as the search goes and read back by a
resumed search: :func:`designs_on_disk`) and ``convergence.png`` (the best score over the
evaluations)."""

from __future__ import annotations

import io
import math
from collections.abc import Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..base.files import make_folder, write_whole
from ..base.tables import write_table
from ..errors import output_error
from .objectives import INFEASIBLE, OptimizeError
from .sources import BatchError
from .table import _fingerprint, _Lock, _read_state, _replace, _Table, _write_state, read_summary

__all__ = ["write_outputs", "with_parameters", "designs_on_disk"]

DESIGNS = "designs.csv"
STATE = "optimize.json"  # the search's fingerprint, for a resume
LOCK = "optimize.lock"  # one search per output folder


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


def bound_note(result, prefix: str = "") -> str:
    """A line for each parameter of the best design that is on a bound of its ``--vary``
    (``result.on_bound``), e.g. ``a = 120 is on its upper bound …``; empty when none is."""
    return "".join(
        f"{prefix}{name} = {result.parameters[name]:.10g} is on its {side} bound "
        "(--vary): the optimum may lie beyond it\n"
        for name, side in result.on_bound.items()
    )


def _columns(names: Sequence[str], constraints) -> tuple[list[str], list[str]]:
    """The columns of ``designs.csv`` and their units."""
    cols = ["evaluation", "stage", *names, "status", "reason", "objective"]
    cols += [c.text for c in constraints] + ["violation", "score"]
    units = ["", "", *["file"] * len(names), "", "", ""] + [""] * len(constraints) + ["", ""]
    return cols, units


def _cell(v) -> str:
    if isinstance(v, float):
        return "" if math.isnan(v) else repr(v)
    return "" if v is None else str(v)


def _rows_text(designs, cols: Sequence[str], units: Sequence[str], header: bool) -> str:
    buf = io.StringIO()
    rows = ([_cell(d.get(c)) for c in cols] for d in designs)
    write_table(buf, cols, units, rows, header=header, lineterminator="\n")
    return buf.getvalue()


def _csv(result, names: Sequence[str], constraints) -> str:
    cols, units = _columns(names, constraints)
    return _rows_text(result.designs, cols, units, header=True)


def _number(cell: str) -> float:
    return float(cell) if cell != "" else math.nan


def _record(row: dict[str, str], names: Sequence[str], constraints) -> dict[str, Any] | None:
    """A design read back from ``designs.csv`` as :class:`~.designs._Problem` keeps it
    (its batch row left out); None for a row that does not read as one."""
    try:
        rec: dict[str, Any] = {"evaluation": int(row["evaluation"]), "stage": row["stage"]}
        rec.update((n, float(row[n])) for n in names)
        rec.update(status=row["status"], reason=row["reason"])
        rec["objective"] = _number(row["objective"])
        margins = [_number(row[c.text]) for c in constraints]
        if rec["status"] != "failed":
            rec.update((c.text, m) for c, m in zip(constraints, margins))
        rec["violation"], rec["score"] = _number(row["violation"]), _number(row["score"])
    except (KeyError, ValueError):
        return None
    if rec["status"] not in ("ok", "infeasible", "failed") or math.isnan(rec["score"]):
        return None
    rec["margins"] = margins if rec["status"] != "failed" else []
    rec["row"] = None
    return rec


class _Designs:
    """``DIR/designs.csv`` as the search goes: the designs read back from an interrupted
    run of the same search (``records``), and each evaluation's new designs appended
    (:meth:`add`) and flushed to the disk — the batch's table on disk
    (:mod:`.table`: appended whole lines, a cut last line left out when read back,
    ``optimize.json`` holding the search's fingerprint, one writer per folder)."""

    def __init__(self, out: Path, names, constraints):
        self.path = out / DESIGNS
        self.cols, self.units = _columns(names, constraints)
        self.where = f"--out {out}"
        self.records: list[dict[str, Any]] = []

    def discard(self) -> None:
        """Remove ``designs.csv`` and ``optimize.json`` (a search that was a mistake)."""
        for path in (self.path, self.path.with_name(STATE)):
            try:
                path.unlink()
            except OSError:
                pass

    def add(self, designs) -> None:

        text = _rows_text(designs, self.cols, self.units, header=False)
        try:
            _Table._write(self.path, text, "a")
        except OSError as exc:  # a full disk: stop; the rows on disk stay valid
            raise output_error(exc, self.where) from None


@contextmanager
def designs_on_disk(out, source, search: dict, names, constraints, overwrite: bool):
    """The :class:`_Designs` of ``out`` (None without ``out``), with the folder locked
    while the search runs.  A folder that holds designs of another search (another file,
    --vary, objective, constraints or option) is refused unless ``overwrite``."""
    if out is None:
        yield None
        return

    out = Path(out)
    where = f"--out {out}"
    make_folder(out, where)
    disk = _Designs(out, names, constraints)
    lock = _Lock(out)
    lock.path = out / LOCK
    try:
        lock.acquire()
    except OSError as exc:
        raise output_error(exc, where) from None
    except BatchError as exc:  # the lock's words are a batch's
        raise OptimizeError(str(exc).replace("another batch", "another search")) from None
    try:
        fingerprint = _fingerprint([source], [], search)
        state_path = out / STATE
        rows = []
        if disk.path.exists() and not overwrite:
            try:
                _, rows = read_summary(disk.path)
            except (OSError, UnicodeDecodeError):
                rows = []
            if rows and _read_state(state_path).get("fingerprint") != fingerprint:
                raise OptimizeError(
                    f"{where}: holds the designs of another search (another file, --vary, "
                    "--minimize, --subject-to or option); use another --out, or --overwrite "
                    "to start afresh"
                )
        records = [r for r in (_record(row, names, constraints) for row in rows) if r]
        disk.records = sorted(records, key=lambda r: r["evaluation"])
        try:
            _write_state(state_path, {"fingerprint": fingerprint, "search": search})
            # the designs read back, whole lines only: the file rewritten before any append
            text = _rows_text(disk.records, disk.cols, disk.units, header=True)
            _replace(disk.path, text, _Table._write)
        except OSError as exc:
            raise output_error(exc, where) from None
        yield disk
    finally:
        lock.release()


def _plot(result, path: Path) -> None:
    """The best score after each generation and each local step (a log scale when it
    stays positive and spans more than a decade); the infeasible levels are left out."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

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
        "designs": out / DESIGNS,
        "convergence": out / "convergence.png",
    }
    texts = {
        "best": bound_note(result, "# ")
        + with_parameters(source.text, template.tree, result.parameters),
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
