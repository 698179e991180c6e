"""The fixtures every folder of the tests shares (tests/README.md); the shared helpers
are in ``tests/helpers.py``."""

import logging
import re
from pathlib import Path

import pytest

from tests.helpers import ROOT, distributed_or_skip

# a glyph drawn from no font (an empty box on paper): matplotlib's text warns (a UserWarning,
# an error by pyproject's filterwarnings), its mathtext and fpdf2 log it
_NO_GLYPH = re.compile(r"does not have a glyph|missing the following glyphs|missing from font")


class _NoGlyphLog(logging.Handler):
    def __init__(self):
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record):
        if _NO_GLYPH.search(record.getMessage()):
            self.messages.append(record.getMessage())


@pytest.fixture(autouse=True)
def no_missing_glyph():
    """Every test fails that draws a picture or a PDF with a character its fonts lack."""
    handler = _NoGlyphLog()
    loggers = [logging.getLogger(name) for name in ("matplotlib", "fpdf")]
    for logger in loggers:
        logger.addHandler(handler)
    yield
    for logger in loggers:
        logger.removeHandler(handler)
    if handler.messages:
        pytest.fail(f"{len(handler.messages)} missing glyph(s): {handler.messages[0]}")


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="module")
def dask_cluster(request):
    """A small Dask cluster on 127.0.0.1 (one worker of two threads in this process, no
    dashboard), closed when the module's tests are done; its ``scheduler_address`` is
    what ``--scheduler`` takes."""
    distributed = distributed_or_skip()
    cluster = distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=2,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        scheduler_port=0,
        dashboard_address=None,
        timeout=30,
    )
    request.addfinalizer(cluster.close)
    return cluster


@pytest.fixture
def fixed_sketch(tmp_path) -> Path:
    """The slotting machine with its sketch in numbers (the pose for K = 2, H = 100), not
    in the expressions that follow K and H: a variant far enough from K = 2 assembles away
    from it."""
    text = (ROOT / "mechanisms" / "slotting_machine.yaml").read_text(encoding="utf-8")
    head, rest = text.split("\nsketch:", 1)
    tail = rest.split("\nanalysis:", 1)[1]
    literal = "\nsketch:\n  A: [-112.5, -65]\n  B: [86.6, 50]\n  C: [93.3, 150]\nanalysis:"
    path = tmp_path / "slotting_machine.yaml"
    path.write_text(head + literal + tail, encoding="utf-8")
    return path


@pytest.fixture(scope="session")
def slotting_reports(tmp_path_factory) -> dict[str, Path]:
    """The shipped slotting machine's Markdown report in English and in Chinese (dpi 30),
    written once for the tests of the report's terms and of ``--positions``:
    ``{"en": folder, "zh": folder}``."""
    from kinetostatics.cli import main

    out = {}
    for lang in ("en", "zh"):
        folder = tmp_path_factory.mktemp(f"slotting_{lang}")
        args = ["report", str(ROOT / "mechanisms" / "slotting_machine.yaml"), "--out"]
        args += [str(folder), "--format", "md", "--dpi", "30", "--lang", lang]
        assert main(args) == 0
        out[lang] = folder
    return out
