"""The screenshot of docs/editor.md: ``kinetostatics edit`` on the slotting machine in
headless Chromium (the browser tests' flags), the crank at the middle of the cutting
stroke, the loads drawn.

    python docs/scripts/editor_screenshot.py [--lang zh] [--out docs/editor.png]

needs Chromium (``apt-get install chromium``) and Playwright (``pip install playwright``;
no browser download: the system's Chromium is used).  tests/editor/test_browser.py takes
the same picture with :func:`shoot` into its own folder.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
VIEW = {"width": 1500, "height": 950}
INDEX = 120  # the row shown: 120° of crank travel from position 1, the ram cutting


def shoot(page, out: Path, lang: str = "en", index: int = INDEX) -> None:
    """The page as it is, in ``lang``, at the row ``index``, written to ``out`` (PNG)."""
    generation = page.evaluate("window.editorState.generation")
    if page.evaluate("window.editorState.lang") != lang:
        page.select_option("#lang", lang)
        page.wait_for_function(
            "g => { const s = window.editorState; "
            "return s.generation > g && s.shown === s.generation && s.busySince === null; }",
            arg=generation,
            timeout=30_000,
        )
    page.eval_on_selector(
        "#slider", "(el, v) => { el.value = v; el.dispatchEvent(new Event('input')); }", index
    )
    page.screenshot(path=str(out))


def main(argv: list[str]) -> int:
    from playwright.sync_api import sync_playwright

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--lang", choices=("en", "zh"), default="en")
    parser.add_argument("--out", default=str(ROOT / "docs" / "editor.png"))
    args = parser.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="editor-shot-"))
    path = work / "slotting_machine.yaml"
    shutil.copy(ROOT / "mechanisms" / "slotting_machine.yaml", path)
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    proc = subprocess.Popen(
        [sys.executable, "-m", "kinetostatics", "edit", str(path), "--no-browser"],
        env=env,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        url = re.search(r"http://\S+/", proc.stdout.readline()).group(0)
        with sync_playwright() as pw:
            context = pw.chromium.launch_persistent_context(
                str(work / "profile"),
                executable_path=shutil.which("chromium") or "/usr/bin/chromium",
                headless=True,
                args=FLAGS,
                viewport=VIEW,
            )
            page = context.new_page()
            page.goto(url)
            page.wait_for_selector("svg#drawing [data-joint=O2]", timeout=30_000)
            shoot(page, Path(args.out), args.lang)
            context.close()
    finally:
        proc.kill()
        proc.wait()
        shutil.rmtree(work, ignore_errors=True)
    print(f"screenshot -> {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
