"""The file being edited and its analyses: the text on disk, saving it whole, and one
analysis at a time, a newer request superseding an older one.

:class:`Session` is the server's mutable working object: the file's path, the generation
of the newest analysis asked for, and the last good analysis (the downloads are its files).
An analysis request carries the page's generation number; one that a newer request has
overtaken while it waited, or while it was computed, answers ``superseded`` and its
document is dropped.
"""

from __future__ import annotations

import tempfile
import threading
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

from ..analysis.pipeline import analyze
from ..base.files import write_file
from ..dynamics.stages import cycle_stage, report_stage
from ..errors import KinetostaticsError, printable
from ..io import read_text
from ..io.plausible import torque_warning
from ..methods.stage import methods_stage
from ..outputs.report import write_report
from .problems import check_text, problems_of
from .snapshot import snapshot
from .wire import wire_text

__all__ = ["Session", "Good", "DOWNLOADS"]

# the files the page downloads: name -> media type
DOWNLOADS = {
    "results.csv": "text/csv; charset=utf-8",
    "summary.json": "application/json",
    "report.pdf": "application/pdf",
}


@dataclass(frozen=True)
class Good:
    """The last text that analysed without a problem: its model and result."""

    text: str
    model: object
    result: object


def run_warnings(model, result) -> list[str]:
    """The warnings ``run`` prints after an analysis, from the rows alone: redundant
    constraints, a failed self-check, an implausible driving torque (without singular
    positions)."""
    s = result.summary()
    out = []
    if s["indeterminate_reactions"]:
        out.append(
            "warning: redundant constraints: the reactions are the minimum-norm solution "
            "(statically indeterminate)"
        )
    if not result.checks.ok:
        out.append(f"warning: {result.checks.warning()}")
    if not s["singular_positions"]:
        for name, d in s["drivers"].items():
            if line := torque_warning(model, name, d.get("peak", float("nan")), d["unit"]):
                out.append(f"warning: {line}")
    return out


class Session:
    """One mechanism file edited in the browser (module docstring)."""

    def __init__(self, path: Path):
        self.path = Path(path)
        self.latest = 0  # the newest generation asked for
        self.good: Good | None = None
        self._gen = threading.Lock()  # guards latest
        self._work = threading.Lock()  # one analysis at a time
        self._files = threading.Lock()  # one download at a time (a report takes seconds:
        # the analyses of new edits go on meanwhile, on the last good record, which is frozen)

    # -- the file ------------------------------------------------------------------
    def mtime(self) -> float | None:
        try:
            return self.path.stat().st_mtime
        except OSError:
            return None

    def read(self) -> dict:
        """The file's text and modification time (a missing file: empty, mtime None)."""
        text = read_text(self.path) if self.path.exists() else ""
        return {"text": text, "mtime": self.mtime(), "file": str(self.path)}

    def save(self, text: str) -> dict:
        """Write ``text`` whole (a temporary file and ``os.replace``); the new mtime.  A
        file written with CRLF line ends keeps them (the page's text has LF alone)."""
        try:
            crlf = b"\r\n" in self.path.read_bytes()
        except OSError:
            crlf = False
        data = text.replace("\r\n", "\n").replace("\n", "\r\n") if crlf else text
        write_file(self.path, str(self.path), lambda tmp: tmp.write_bytes(data.encode("utf-8")))
        return {"mtime": self.mtime()}

    # -- analyses ------------------------------------------------------------------
    def _ask(self, generation: int) -> None:
        with self._gen:
            self.latest = max(self.latest, generation)

    def _overtaken(self, generation: int) -> bool:
        with self._gen:
            return generation < self.latest

    def analyse(self, text: str, generation: int, lang: str = "en") -> dict:
        """The problems of ``text`` or the document of its analysis (module docstring)."""
        self._ask(generation)
        head = {"generation": generation}
        with self._work:
            if self._overtaken(generation):
                return {**head, "superseded": True}
            t0 = time.perf_counter()
            checked = check_text(text, str(self.path))
            if checked.problems:
                return {
                    **head,
                    "ok": False,
                    "problems": [p.to_dict() for p in checked.problems],
                    "warnings": list(checked.warnings),
                }
            said = list(checked.warnings)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    result = analyze(checked.model)
                except KinetostaticsError as exc:
                    probs = problems_of(exc, str(self.path))
                    return {
                        **head,
                        "ok": False,
                        "problems": [p.to_dict() for p in probs],
                        "warnings": said,
                    }
            said += [f"warning: {printable(str(w.message))}" for w in caught]
            said += run_warnings(checked.model, result)
            if self._overtaken(generation):
                return {**head, "superseded": True}
            doc = snapshot(result, lang=lang)
            self.good = Good(text, checked.model, result)
            return {
                **head,
                "ok": True,
                "problems": [],
                "warnings": list(dict.fromkeys(said)),
                "seconds": time.perf_counter() - t0,
                "analysis": doc,
            }

    def answer(self, text: str, generation: int, lang: str = "en") -> str:
        """:meth:`analyse` as strict JSON text (non-finite numbers null, and named)."""
        return wire_text(self.analyse(text, generation, lang))

    # -- downloads -----------------------------------------------------------------
    def download(self, name: str, lang: str = "en") -> bytes:
        """``results.csv``, ``summary.json`` or ``report.pdf`` of the last good analysis,
        made by the writers of ``run`` and ``report``."""
        good = self.good
        if good is None:
            raise KinetostaticsError("nothing analysed yet: fix the problems first")
        with self._files, tempfile.TemporaryDirectory(prefix="kinetostatics-edit-") as tmp:
            out = Path(tmp)
            if name == "results.csv":
                good.result.to_csv(out / name)
                return (out / name).read_bytes()
            if name == "summary.json":
                s = good.result.summary(cycle_stage(good.result))
                good.result.to_json(out / name, s)
                return (out / name).read_bytes()
            if name == "report.pdf":
                paths = write_report(
                    good.model,
                    out,
                    formats=["pdf"],
                    lang=lang,
                    cycle=report_stage,
                    methods=methods_stage,
                )
                return Path(paths["pdf"]).read_bytes()
        raise KinetostaticsError(f"no download '{name}' (have {', '.join(DOWNLOADS)})")
