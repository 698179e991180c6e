"""The issue's full check (issue 38), ``slow``: for every shipped file with a motion driver,
in English and in Chinese, ``kinetostatics report --pdf`` succeeds, and its methods.json
closes every method to the issue's tolerances — each vector equation (velocities and
accelerations, every pair type writing both) to 1e-12 of its largest term, each force
polygon (frictionless and with friction) to 1e-9 of its largest force with its moments,
Joukowski's lever and the power method equal the solution's M_b to 1e-9, and the instant
centres give the pipeline's velocities to 1e-12 — and the PDF's text holds each equation
of the first position asked and its solved values."""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import pytest

from kinetostatics.cli import main
from tests.helpers import ROOT, motion_driven

pytestmark = pytest.mark.slow


def _pdf_text(path) -> str:
    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext (poppler) is not installed")
    out = subprocess.run(["pdftotext", "-layout", str(path), "-"], capture_output=True,
                         text=True, check=True)  # fmt: skip
    return re.sub(r"\s+", " ", out.stdout)


def _closes(data: dict) -> None:
    for label, p in data["vector_equations"].items():
        assert p["max_residual"] <= 1e-12, label
        for g in p["groups"]:
            assert not g["notes"], (label, g["group"], g["notes"])
            kinds = [e["kind"] for e in g["equations"]]
            assert kinds.count("velocity") == kinds.count("acceleration"), (label, g["group"])
    for key in ("force_polygons", "force_polygons_friction"):
        if key in data:
            assert data[key]["max_closure_error"] <= 1e-9, key
            for p in data[key]["positions"]:
                assert all(g["moment_error"] <= 1e-9 for g in p["groups"]), (key, p["label"])
    if "balancing_moment" in data:
        assert data["balancing_moment"]["max_relative_difference"] <= 1e-9
    for label, c in data["instant_centres"].items():
        assert c["max_error"] is None or c["max_error"] <= 1e-12, label


@pytest.mark.parametrize("lang", ["en", "zh"])
@pytest.mark.parametrize("stem", motion_driven())
def test_report_pdf_and_its_methods_close(tmp_path, stem, lang):
    path = ROOT / "mechanisms" / f"{stem}.yaml"
    args = ["report", str(path), "--out", str(tmp_path), "--format", "md", "pdf", "--dpi", "30"]
    assert main([*args, "--lang", lang]) == 0
    data = json.loads((tmp_path / "methods.json").read_text(encoding="utf-8"))
    _closes(data)
    text = _pdf_text(tmp_path / "report.pdf")
    first = next(iter(data["vector_equations"].values()))
    for g in first["groups"]:
        for e in g["equations"]:
            # the PDF may break a long line: its symbols, in order, with anything between
            symbols = [re.escape(s) for s in re.split(r" [=+] ", e["text"])]
            assert re.search(r".{0,40}?".join(symbols), text), (stem, lang, e["text"])
