"""The editor's server without a browser (issue 42): the token and the address, the
problems as ``kinetostatics check`` gives them, the analysis's document against the
result's columns and the free-body identity, a newer request superseding an older one, the
atomic save, the downloads, and Ctrl-C."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.editor import session as session_module
from kinetostatics.editor.server import EditorServer
from kinetostatics.editor.session import Session
from tests.helpers import ROOT

SLOTTING = ROOT / "mechanisms" / "slotting_machine.yaml"


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    """A server of a copy of the slotting machine, in a thread of this process."""
    folder = tmp_path_factory.mktemp("edit")
    path = folder / "slotting_machine.yaml"
    shutil.copy(SLOTTING, path)
    server = EditorServer(Session(path))
    thread = threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.05})
    thread.start()
    yield server
    server.shutdown()
    server.server_close()
    thread.join()


def _get(url: str, headers: dict | None = None, body: dict | None = None):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, headers=headers or {})
    try:
        with urllib.request.urlopen(req, timeout=60) as r:
            return r.status, r.read(), dict(r.headers)
    except urllib.error.HTTPError as e:
        return e.code, e.read(), dict(e.headers)


def test_it_listens_on_127_0_0_1_only_and_wants_the_token(served):
    base = f"http://127.0.0.1:{served.port}"
    assert served.server_address[0] == "127.0.0.1"
    assert len(served.token) >= 32
    assert _get(base + "/")[0] == 403
    assert _get(base + "/api/file")[0] == 403
    wrong = served.token[:-1] + ("y" if served.token.endswith("x") else "x")  # one char off
    assert _get(f"{base}/{wrong}/api/file")[0] == 403
    assert _get(f"{base}/nope/{served.token}/api/file")[0] == 403
    # another page's address for this server (DNS rebinding) is refused too
    assert _get(served.url + "api/file", {"Host": f"evil.example:{served.port}"})[0] == 403
    code, body, _ = _get(served.url)
    assert code == 200 and b'<svg id="drawing"' in body
    code, body, _ = _get(served.url + "api/file")
    assert code == 200 and json.loads(body)["text"] == SLOTTING.read_text(encoding="utf-8")


def test_the_page_needs_no_network():
    """Every file the page loads is the package's own: the only address in them is the SVG
    namespace's name (not fetched)."""
    import re

    page = Path(ks.__file__).parent / "editor" / "page"
    assert {f.name for f in page.iterdir()} >= {"index.html", "app.js", "style.css"}
    for f in page.iterdir():
        text = f.read_text(encoding="utf-8")
        found = set(re.findall(r"(?:https?:)?//[\w.-]+\.\w+[^\s\"'`]*", text))
        assert found <= {"http://www.w3.org/2000/svg"}, (f.name, found)
        assert "@import" not in text and "import(" not in text, f.name


def test_problems_are_check_s_lines_at_their_line_and_column(tmp_path, capsys):
    text = SLOTTING.read_text(encoding="utf-8").replace("  c: 125 ", "  c: 12 5 ")
    bad = tmp_path / "bad.yaml"
    bad.write_text(text, encoding="utf-8")
    assert main(["check", str(bad)]) == 2
    cli_lines = capsys.readouterr().err.strip().splitlines()
    answer = Session(bad).analyse(text, 1)
    assert not answer["ok"]
    assert [p["text"] for p in answer["problems"]] == cli_lines
    where = [ln for ln, s in enumerate(text.splitlines(), 1) if s.startswith("  c: 12 5")]
    assert [p["line"] for p in answer["problems"]] == where
    assert all(p["col"] >= 1 for p in answer["problems"])
    assert answer["problems"][0]["text"].startswith(f"{bad}:{where[0]}:")


def test_the_document_is_the_result_s_positions(served):
    """The drawn joints and points at each row are the result's columns (m) at that row."""
    answer = json.loads(served.session.answer(SLOTTING.read_text(encoding="utf-8"), 10))
    doc = answer["analysis"]
    r = ks.analyze(ks.load(SLOTTING))
    assert doc["rows"] == len(r)
    scale = doc["span"]
    for k in (0, 37, 200, len(r) - 1):
        row = doc["row"][k]
        assert doc["angle"][k] == pytest.approx(r["angle"][row], abs=1e-9)
        for p in doc["points"]:
            got = np.array(p["xy"][k])
            want = np.array([r[f"{p['name']}.x"][row], r[f"{p['name']}.y"][row]])
            assert np.max(np.abs(got - want)) <= 1e-9 * scale, p["name"]
        joints = {j["name"]: np.array(j["xy"][k]) for j in doc["joints"]}
        for name, point in (("O2", "crank.O2"), ("A", "crank.A"), ("B", "bar.B"), ("C", "rod.C")):
            want = np.array([r[f"{point}.x"][row], r[f"{point}.y"][row]])
            assert np.max(np.abs(joints[name] - want)) <= 1e-9 * scale, name
        # the crank's outline: the bar from O2 to A
        crank = np.array(next(lk for lk in doc["links"] if lk["name"] == "crank")["outline"][k])
        ends = [np.array([r[f"crank.{p}.x"][row], r[f"crank.{p}.y"][row]]) for p in ("O2", "A")]
        gap = min(
            max(np.max(np.abs(crank[0] - ends[0])), np.max(np.abs(crank[1] - ends[1]))),
            max(np.max(np.abs(crank[0] - ends[1])), np.max(np.abs(crank[1] - ends[0]))),
        )
        assert gap <= 1e-9 * scale


def _ground_balance(doc, k: int, key: str) -> np.ndarray:
    """The sum of every force on the moving links at row k: the frame's reactions on them,
    the weights, the inertia forces and the external loads (d'Alembert: zero)."""
    total = np.zeros(2)
    for a in doc["loads"][key]:
        if a["force"] is None or not a["active"][k]:
            continue
        f = np.array(a["force"][k])
        if a["kind"] == "reaction":
            # F_Rij: link i on link j; the frame is number 6 in the slotting machine
            sym = a["label"].removeprefix("F_R")
            if "6" not in sym:
                continue  # between two moving links: internal
            f = f if sym.startswith("6") else -f
        total += f
    return total


@pytest.mark.parametrize("key", ["plain", "friction"])
def test_the_drawn_forces_balance_on_the_whole_machine(served, key):
    """d'Alembert: the frame's reactions, the weights, the inertia forces and the external
    loads drawn at a row sum to zero (to round-off of the largest), with and without
    friction — an identity the document's forces must meet."""
    answer = json.loads(served.session.answer(SLOTTING.read_text(encoding="utf-8"), 11))
    doc = answer["analysis"]
    biggest = max(
        float(np.max(np.hypot(*np.array(a["force"]).T))) for a in doc["loads"][key] if a["force"]
    )
    for k in range(0, doc["rows"], 7):
        assert np.max(np.abs(_ground_balance(doc, k, key))) <= 1e-7 * biggest, k


def test_friction_circles_are_the_pins_radii(served):
    """Each pin's friction circle has the file's friction radius (1 mm) at every row where
    the pin turns (none where it is at rest relative: no friction couple there)."""
    doc = json.loads(served.session.answer(SLOTTING.read_text(encoding="utf-8"), 12))["analysis"]
    circles = {c["joint"]: c for c in doc["friction_circles"]}
    assert set(circles) == {"O2", "A", "O3", "B", "C"}
    for c in circles.values():
        r = np.array([v for v in c["radius"] if v])
        assert len(r) > 0.9 * doc["rows"]
        assert np.max(np.abs(r - 1e-3)) < 1e-9


def test_a_newer_request_supersedes_an_older_one(tmp_path):
    path = tmp_path / "m.yaml"
    shutil.copy(SLOTTING, path)
    s = Session(path)
    text = SLOTTING.read_text(encoding="utf-8")
    answers = {}
    with s._work:  # an analysis is running: both wait for it
        t1 = threading.Thread(target=lambda: answers.setdefault(1, s.analyse(text, 1)))
        t1.start()
        time.sleep(0.2)
        t2 = threading.Thread(target=lambda: answers.setdefault(2, s.analyse(text, 2)))
        t2.start()
        time.sleep(0.2)
    t1.join(60)
    t2.join(60)
    assert answers[1] == {"generation": 1, "superseded": True}
    assert answers[2]["ok"] and answers[2]["generation"] == 2


def test_save_writes_the_file_whole(served, tmp_path):
    path = served.session.path
    text = path.read_text(encoding="utf-8").replace("H: 100 ", "H: 90  ")
    code, body, _ = _get(
        served.url + "api/save", {"Content-Type": "application/json"}, {"text": text}
    )
    assert code == 200
    assert path.read_text(encoding="utf-8") == text
    assert json.loads(body)["mtime"] == path.stat().st_mtime
    assert sorted(p.name for p in path.parent.iterdir()) == [path.name]  # no temporary left
    shutil.copy(SLOTTING, path)


def test_downloads_are_run_s_files(served, tmp_path):
    served.session.analyse(SLOTTING.read_text(encoding="utf-8"), 20)
    code, body, headers = _get(served.url + "api/download/results.csv")
    assert code == 200 and "results.csv" in headers["Content-Disposition"]
    assert main(["run", str(SLOTTING), "--out", str(tmp_path / "out")]) == 0
    assert body == (tmp_path / "out" / "results.csv").read_bytes()
    code, body, _ = _get(served.url + "api/download/summary.json")
    assert code == 200
    assert json.loads(body) == json.loads((tmp_path / "out" / "summary.json").read_bytes())
    assert _get(served.url + "api/download/nothing.txt")[0] == 404


def test_the_pdf_download_is_the_report_s(served, monkeypatch):
    """The route hands the report's writer the last good model and serves its PDF (the
    real report is the slow browser test's: it takes seconds)."""
    seen = {}

    def write_report(model, out, **kw):
        seen.update(kw, model=model)
        (Path(out) / "report.pdf").write_bytes(b"%PDF-1.3 stand-in")
        return {"pdf": Path(out) / "report.pdf"}

    monkeypatch.setattr(session_module, "write_report", write_report)
    served.session.analyse(SLOTTING.read_text(encoding="utf-8"), 30)
    code, body, headers = _get(served.url + "api/download/report.pdf?lang=zh")
    assert code == 200 and body == b"%PDF-1.3 stand-in"
    assert headers["Content-Type"] == "application/pdf"
    assert seen["formats"] == ["pdf"] and seen["lang"] == "zh"
    assert seen["model"] is served.session.good.model
    assert seen["cycle"] is not None and seen["methods"] is not None


def test_ctrl_c_ends_with_one_line_and_130(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    proc = subprocess.Popen(
        [sys.executable, "-m", "kinetostatics", "edit", str(SLOTTING), "--no-browser"],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        line = proc.stdout.readline()
        assert "http://127.0.0.1:" in line and "Ctrl-C" in line
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode == 130
    assert err.strip().splitlines() == ["kinetostatics: edit: interrupted"]


def test_edit_help_is_honest(capsys):
    with pytest.raises(SystemExit):
        main(["edit", "--help"])
    out = capsys.readouterr().out
    for words in ("127.0.0.1", "--port", "--no-browser", "Ctrl-C", "token"):
        assert words in out, words


def test_save_keeps_a_file_s_crlf_line_ends(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_bytes(SLOTTING.read_bytes().replace(b"\n", b"\r\n"))
    text = SLOTTING.read_text(encoding="utf-8").replace("H: 100 ", "H: 90  ")  # LF, as a page
    Session(path).save(text)
    assert path.read_bytes() == text.replace("\n", "\r\n").encode("utf-8")


def test_a_sketched_point_far_from_its_assembly_is_marked(tmp_path):
    """The sketch's C moved 20 mm up (8 % of the reference length, the same branch): its
    target is 20 mm from where C assembled, and marked far; A and B are not."""
    text = SLOTTING.read_text(encoding="utf-8")
    moved = text.replace(
        "  C: [X, L_O3B*sind(phi3) + sqrt(", "  C: [X, 20 + L_O3B*sind(phi3) + sqrt("
    )
    assert moved != text
    doc = Session(SLOTTING).analyse(moved, 1)["analysis"]
    sketch = {s["key"]: s for s in doc["sketch"]}
    assert sketch["C"]["far"] and abs(sketch["C"]["distance"] - 0.020) < 1e-9
    assert not sketch["A"]["far"] and not sketch["B"]["far"]
    assert sketch["A"]["distance"] < 1e-12


def test_without_a_browser_the_browser_tests_skip_but_fail_under_ci(monkeypatch):
    from _pytest.outcomes import Failed, Skipped

    from tests.editor import test_browser

    monkeypatch.delenv("CI", raising=False)
    with pytest.raises(Skipped, match="no Chromium"):
        test_browser._missing("no Chromium")
    monkeypatch.setenv("CI", "true")
    with pytest.raises(Failed, match="CI must run the browser tests: no Chromium"):
        test_browser._missing("no Chromium")


def test_the_warnings_are_run_s(tmp_path, capsys):
    """A cutting force of 1e9 N: the implausible driving torque that run warns of is in the
    page's warnings, in run's words."""
    text = SLOTTING.read_text(encoding="utf-8").replace("  Q: 1000 ", "  Q: 1e9  ")
    path = tmp_path / "big.yaml"
    path.write_text(text, encoding="utf-8")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    said = [
        line.removeprefix("kinetostatics: ")
        for line in capsys.readouterr().err.splitlines()
        if line.startswith("kinetostatics: warning:")
    ]
    assert any("motor" in line for line in said), said
    answer = Session(path).analyse(text, 1)
    assert answer["ok"] and set(said) <= set(answer["warnings"]), (said, answer["warnings"])
