"""Batches (issue 10): sweeps, the summary table against single runs, failing
variants, resume, executors, the command line and `best`."""

from __future__ import annotations

import csv
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics import batch
from kinetostatics.batch import best, sweeps, variants
from kinetostatics.cli import main

ROOT = Path(__file__).resolve().parents[2]
SLIDER = ROOT / "mechanisms" / "slider_crank.yaml"
SLOTTER = ROOT / "mechanisms" / "slotting_machine.yaml"


def _tasks(vs):
    return [batch.Task(vid, 0, ov) for vid, ov in vs]


def _rows(out):
    return {r["variant"]: r for r in batch.read_summary(Path(out) / "summary.csv")[1]}


def _close(a: str, b: str, rel=1e-12) -> bool:
    if a == b:
        return True
    try:
        x, y = float(a), float(b)
    except ValueError:
        return False
    return math.isclose(x, y, rel_tol=rel, abs_tol=0.0)


# -- sweeps ----------------------------------------------------------------------------
def test_grid_zip_and_product_order(tmp_path):
    text = """
grid:
  K: {range: {from: 1.5, to: 2.0, step: 0.25}}
  H: [90, 110]
zip: {c: [100, 125], d: {linspace: {from: 100, to: 120, num: 2}}}
"""
    vs = sweeps.expand(sweeps.load_sweep(text, "s.yaml"))
    assert len(vs) == 3 * 2 * 2
    assert [v for _, v in vs[:3]] == [
        {"K": 1.5, "H": 90.0, "c": 100.0, "d": 100.0},
        {"K": 1.5, "H": 90.0, "c": 125.0, "d": 120.0},
        {"K": 1.5, "H": 110.0, "c": 100.0, "d": 100.0},
    ]
    assert vs[-1][1]["K"] == 2.0  # the range includes its end
    assert [vid for vid, _ in vs][:2] == ["01", "02"]


def test_random_is_reproducible_and_in_range():
    def draw(seed):
        text = (
            f"random: {{n: 50, seed: {seed}, params: {{K: {{uniform: [1.5, 2.5]}}, "
            "H: {normal: [100, 5]}, Q: {choice: [800, 1000]}, n_teeth: {integers: [1, 3]}}}"
        )
        return sweeps.expand(sweeps.load_sweep(text, "s.yaml"))

    a, b, c = draw(7), draw(7), draw(8)
    assert a == b and a != c
    K = np.array([v["K"] for _, v in a])
    assert K.min() >= 1.5 and K.max() < 2.5 and np.ptp(K) > 0.5
    assert {v["Q"] for _, v in a} == {800.0, 1000.0}
    assert {v["n_teeth"] for _, v in a} <= {1.0, 2.0, 3.0}
    cli = sweeps.expand(sweeps.from_options(["K=1.5:2.5"], random=50, seed=7))
    assert [v["K"] for _, v in cli] == list(K)  # the same generator, the same draws


def test_table_with_ids_comments_and_blanks(tmp_path):
    (tmp_path / "class.csv").write_text(
        "# course design 2026\nvariant,K,H\nann,1.8,100\nbob,2.1,\n"
    )
    vs = sweeps.expand(sweeps.load_sweep("table: class.csv", "s.yaml"), tmp_path)
    assert vs == [("ann", {"K": 1.8, "H": 100.0}), ("bob", {"K": 2.1})]


def test_cli_sets_make_a_grid():
    vs = sweeps.expand(sweeps.from_options(["K=1.5:2.5:3", "H=90,100"]))
    assert [v for _, v in vs] == [{"K": k, "H": h} for k in (1.5, 2.0, 2.5) for h in (90.0, 100.0)]


@pytest.mark.parametrize(
    "text, message",
    [
        (
            "grid: {K: {rang: {from: 1, to: 2, step: 1}}}",
            "s.yaml:1:18: grid.K.rang: unknown form 'rang' (did you mean 'range'?)",
        ),
        ("gird: {K: [1]}", "unknown sweep block 'gird' (did you mean 'grid'?)"),
        (
            "grid:\n  K: {range: {from: 1, to: 2, step: -1}}",
            "s.yaml:2:37: grid.K.range.step: step -1 does not lead from 1 to 2",
        ),
        ("zip: {a: [1, 2], b: [1]}", "zip lists differ in length: a 2, b 1"),
        ("grid: {a: [1, x]}", "s.yaml:1:15: grid.a[1]: expected a number, got 'x'"),
        ("random: {n: 3, seed: 1, params: {Q: {uniform: [2, 1]}}}", "uniform of 'Q' needs lo < hi"),
        ("random: {n: 3, params: {Q: {uniform: [1, 2]}}}", "random: missing 'seed'"),
        (
            "grid: {a: [1]}\nzip: {a: [2]}",
            "parameter 'a' is swept twice (also at s.yaml:1:7: grid)",
        ),
    ],
)
def test_bad_sweeps_name_the_place(text, message):
    with pytest.raises(sweeps.SweepError) as exc:
        sweeps.expand(sweeps.load_sweep(text, "s.yaml"))
    assert message in str(exc.value) and "\n" not in str(exc.value)


def test_bad_table_names_the_line(tmp_path):
    (tmp_path / "t.csv").write_text("K,H\n1.8,100\n2.1,abc\n")
    with pytest.raises(sweeps.SweepError, match=r"t\.csv:3:1: column 'H': 'abc' is not a number"):
        sweeps.read_table(tmp_path / "t.csv")


def test_unknown_parameter_fails_before_any_analysis(tmp_path, capsys):
    code = main(["batch", str(SLIDER), "--out", str(tmp_path), "--set", "aa=1,2"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err
    assert "the sweep sets 'aa', which the file does not declare (did you mean 'a'?)" in err
    assert not (tmp_path / "summary.csv").exists()
    with pytest.raises(sweeps.SweepError, match="sets 'bb'"):  # the API checks too
        batch.run_batch(str(SLIDER), _tasks([("1", {"bb": 1.0})]), tmp_path / "api")
    assert not (tmp_path / "api").exists()
    assert main(["batch", str(SLIDER), "--out", str(tmp_path), "--flywheel"]) == 2
    assert "--flywheel needs a flywheel: {delta: ...} section" in capsys.readouterr().err


# -- the summary row against an independent single run ---------------------------------
def _variant_file(tmp_path, name, a, b):
    text = SLIDER.read_text()
    text, n1 = re.subn(r"^  a: 100 ", f"  a: {a} ", text, flags=re.M)
    text, n2 = re.subn(r"^  b: 350 ", f"  b: {b} ", text, flags=re.M)
    text, n3 = re.subn(r"positions: 360", "positions: 36", text)
    assert n1 == n2 == n3 == 1
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    return path


def test_summary_row_equals_a_single_run(tmp_path):
    vs = [("short", {"a": 90.0, "b": 330.0}), ("long", {"a": 110.0, "b": 380.0})]
    batch.run_batch(str(SLIDER), _tasks(vs), tmp_path / "b", executor="serial", positions=36)
    rows = _rows(tmp_path / "b")
    for vid, ov in vs:
        out = tmp_path / f"run_{vid}"
        assert (
            main(["run", str(_variant_file(tmp_path, vid, ov["a"], ov["b"])), "--out", str(out)])
            == 0
        )
        s = json.loads((out / "summary.json").read_text())
        with open(out / "results.csv") as fh:
            lines = [line for line in fh if not line.startswith("#")]
        cols = {
            k: np.array([float(x) if x else np.nan for x in v])
            for k, v in zip(next(csv.reader(lines[:1])), zip(*csv.reader(lines[1:])))
        }
        row = rows[vid]
        assert row["status"] == "ok" and float(row["a"]) == ov["a"]
        expect = {
            "slide.stroke": s["outputs"]["slide"]["stroke"],
            "slide.time_ratio": s["outputs"]["slide"]["time_ratio"],
            "motor.torque_peak": s["drivers"]["motor"]["peak"],
            "motor.torque_friction_peak": s["drivers"]["motor"]["peak_friction"],
            "motor.torque_friction_approx_peak": s["drivers"]["motor"]["peak_friction_approx"],
            "motor.torque_rms": np.sqrt(np.mean(cols["motor.torque"] ** 2)),
            "motor.torque_friction_rms": np.sqrt(np.mean(cols["motor.torque_friction"] ** 2)),
            "rod_slider.pressure_angle_max": np.max(cols["rod_slider.pressure_angle"]),
            **{f"{j}.reaction_peak": p["peak"] for j, p in s["reaction_peaks"].items()},
            **{
                f"{j}.reaction_peak_friction": p["peak_friction"]
                for j, p in s["reaction_peaks"].items()
            },
        }
        for name, value in expect.items():
            assert float(row[name]) == pytest.approx(value, rel=1e-12), name


def test_a_variant_that_cannot_assemble_is_a_row_with_its_reason(tmp_path):
    vs = [("1", {"b": 350.0}), ("2", {"b": 80.0}), ("3", {"b": 400.0})]  # 2: rod < crank
    s = batch.run_batch(str(SLIDER), _tasks(vs), tmp_path, executor="serial", positions=24, chunk=3)
    rows = _rows(tmp_path)
    assert (s.total, s.failed) == (3, 1)
    assert s.alone == 1  # 2: out of the vectorised analysis, for its reason; counted
    assert json.loads((tmp_path / "batch.json").read_text())["runs"][-1]["alone"] == 1
    assert [rows[k]["status"] for k in "123"] == ["ok", "failed", "ok"]
    assert "RRP dyad {rod, slider} cannot assemble" in rows["2"]["reason"]
    assert rows["2"]["failed.group"] == "RRP dyad {rod, slider}" and rows["1"]["failed.group"] == ""
    assert rows["1"]["full_cycle"] == "True" and rows["2"]["full_cycle"] == "False"
    assert rows["2"]["motor.torque_peak"] == "" and float(rows["3"]["motor.torque_peak"]) > 0


# -- resume ----------------------------------------------------------------------------
def test_an_interrupted_batch_resumes_without_recomputing(tmp_path, monkeypatch):
    vs = sweeps.expand(sweeps.from_options(["a=90:110:5", "b=300,350"]))  # 10 variants
    tasks = _tasks(vs)
    opts = dict(executor="serial", positions=24, chunk=2)

    def stop_after_two_chunks(done):
        if done >= 4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        batch.run_batch(str(SLIDER), tasks, tmp_path / "b", on_chunk=stop_after_two_chunks, **opts)
    assert sorted(_rows(tmp_path / "b")) == ["01", "02", "03", "04"]
    with open(tmp_path / "b" / "summary.csv", "a") as fh:
        fh.write("05,95.0,300")  # a row cut short by the interrupt
    seen = []
    real = variants._analyze_variants  # what a chunk calls

    def counting(template, overrides, **kw):
        overrides = list(overrides)
        seen.extend(overrides)
        return real(template, overrides, **kw)

    monkeypatch.setattr(variants, "_analyze_variants", counting)
    s = batch.run_batch(str(SLIDER), tasks, tmp_path / "b", **opts)
    assert (s.reused, s.computed) == (4, 6)
    assert seen == [ov for _, ov in vs[4:]]  # only the unfinished ones, 05 included
    assert json.loads((tmp_path / "b" / "batch.json").read_text())["computed"] == 10
    monkeypatch.setattr(variants, "_analyze_variants", real)
    batch.run_batch(str(SLIDER), tasks, tmp_path / "fresh", **opts)
    assert _rows(tmp_path / "b") == _rows(tmp_path / "fresh")
    header = (tmp_path / "b" / "summary.csv").read_text().splitlines()
    assert header[0].startswith("# units: ,file,file,") and [
        line.split(",")[0] for line in header[2:]
    ] == [vid for vid, _ in vs]  # in variant order at the end


def test_the_variants_analysed_one_by_one_are_counted_and_shown(tmp_path, capsys):
    """The vectorised analysis is the fast path; a variant it does not take is analysed
    alone, with the same row: the batch counts those (batch.json, the summary line), so
    a batch that leaves the fast path does not do so silently."""
    args = ["batch", str(SLOTTER), "--set", "K=1.9,2.1", "--positions", "12", "--chunk", "2"]
    assert main([*args, "--out", str(tmp_path / "fast"), "--no-flywheel"]) == 0
    assert "one by one" not in capsys.readouterr().out
    assert main([*args, "--out", str(tmp_path / "slow"), "--flywheel"]) == 0  # one by one
    assert "; 2 analysed one by one (outside the vectorised analysis)" in capsys.readouterr().out
    state = json.loads((tmp_path / "slow" / "batch.json").read_text())
    assert state["runs"][-1]["alone"] == 2


def test_a_rerun_with_another_sweep_is_refused(tmp_path):
    opts = dict(executor="serial", positions=12)
    batch.run_batch(str(SLIDER), _tasks([("1", {"a": 90.0})]), tmp_path, **opts)
    with pytest.raises(batch.BatchError, match="holds another batch"):
        batch.run_batch(str(SLIDER), _tasks([("1", {"a": 95.0})]), tmp_path, **opts)
    s = batch.run_batch(str(SLIDER), _tasks([("1", {"a": 95.0})]), tmp_path, overwrite=True, **opts)
    assert s.computed == 1 and float(_rows(tmp_path)["1"]["a"]) == 95.0


# -- executors and chunking ------------------------------------------------------------
SLOTTER_VARIANTS = [
    ("1", {"K": 1.8}),
    ("2", {"K": 2.2, "H": 120.0}),
    ("3", {"K": 1.0}),
    ("4", {"L_O2O3": 120.0}),
    ("5", {"Q": 1500.0, "G5": 400.0}),
]


def _same_rows(a, b):
    assert a.keys() == b.keys()
    for vid in a:
        assert a[vid].keys() == b[vid].keys()
        for k in a[vid]:
            assert _close(a[vid][k], b[vid][k]), (vid, k, a[vid][k], b[vid][k])


def test_executors_and_chunk_sizes_give_the_same_rows(tmp_path):
    tasks = _tasks(SLOTTER_VARIANTS)
    ref = tmp_path / "serial1"
    batch.run_batch(str(SLOTTER), tasks, ref, executor="serial", chunk=1, positions=24)
    rows = _rows(ref)
    assert rows["3"]["status"] == "failed" and "division by zero" in rows["3"]["reason"]
    assert rows["1"]["status"] == "ok" and rows["1"]["flywheel.inertia"] != ""
    batch.run_batch(
        str(SLOTTER), tasks, tmp_path / "serial5", executor="serial", chunk=5, positions=24
    )
    s = batch.run_batch(
        str(SLOTTER),
        tasks,
        tmp_path / "proc",
        executor="processes",
        workers=2,
        chunk=2,
        positions=24,
    )
    assert (s.workers, s.chunk) == (2, 2)
    _same_rows(rows, _rows(tmp_path / "serial5"))
    _same_rows(rows, _rows(tmp_path / "proc"))


@pytest.mark.timeout(120)
def test_a_local_dask_cluster_gives_the_same_rows(tmp_path, dask_cluster):
    tasks = _tasks(SLOTTER_VARIANTS[:3])
    batch.run_batch(str(SLOTTER), tasks, tmp_path / "ref", executor="serial", positions=24)
    s = batch.run_batch(
        str(SLOTTER),
        tasks,
        tmp_path / "dask",
        executor=dask_cluster.scheduler_address,
        chunk=2,
        positions=24,
    )
    assert s.total == 3
    _same_rows(_rows(tmp_path / "ref"), _rows(tmp_path / "dask"))


def test_a_chunk_brings_its_variants_parameters_as_the_table_evaluates_them():
    """The worker sends each variant's parameters as its model has them; the table's
    parameter columns used to be evaluated again in the batch's own process, by
    ``variant_parameters`` (the file's parameters in dependency order): the same numbers,
    and the same evaluation where a variant's model is not built."""
    from kinetostatics.batch.executors import analyze_chunk
    from kinetostatics.batch.sources import Chunk, Source, template_of, variant_parameters

    source = Source(str(SLOTTER), SLOTTER.read_text())
    ovs = ({}, {"K": 1.8, "H": 95.0}, {"L_O2O3": 140.0, "BC_ratio": 0.9}, {"G3": -1.0})
    rows = analyze_chunk(Chunk(source, ("1", "2", "3", "4"), ovs, positions=12))
    tpl = template_of(source.file, source.text)
    assert [r["status"] for r in rows] == ["ok", "ok", "ok", "failed"]  # G3 < 0: no model
    for ov, params in zip(ovs[:3], rows.parameters):
        assert list(params.items()) == list(variant_parameters(tpl, ov).items())
    assert rows.parameters[3] is None  # the table evaluates it


def test_a_crashing_chunk_is_an_error_row_and_a_rerun_retries_it(tmp_path, monkeypatch):
    real = variants._analyze_variants  # what a chunk calls

    def crash_on_k2(template, overrides, **kw):
        overrides = list(overrides)
        if any(ov.get("a") == 95.0 for ov in overrides):
            raise MemoryError("worker lost")
        return real(template, overrides, **kw)

    monkeypatch.setattr(variants, "_analyze_variants", crash_on_k2)
    tasks = _tasks([("1", {"a": 90.0}), ("2", {"a": 95.0}), ("3", {"a": 100.0})])
    s = batch.run_batch(str(SLIDER), tasks, tmp_path, executor="serial", chunk=1, positions=12)
    rows = _rows(tmp_path)
    assert s.errors == 1 and rows["2"]["status"] == "error"
    assert rows["2"]["reason"] == "MemoryError: worker lost" and rows["3"]["status"] == "ok"
    monkeypatch.setattr(variants, "_analyze_variants", real)
    s = batch.run_batch(str(SLIDER), tasks, tmp_path, executor="serial", chunk=1, positions=12)
    assert (s.computed, s.errors, _rows(tmp_path)["2"]["status"]) == (1, 0, "ok")


# -- folders, result files, the command line -------------------------------------------
def test_a_folder_batch_runs_each_file_and_reports_a_broken_one(tmp_path):
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "ann.yaml").write_text(SLIDER.read_text())
    (folder / "bob.yaml").write_text(SLIDER.read_text().replace("  b: 350 ", "  b: 80 "))
    (folder / "cid.yaml").write_text("links: {ground: {}}\njoints: 3\n")
    (folder / "dan.yaml").write_bytes(b"name: caf\xe9\n")  # not UTF-8
    code = main(
        [
            "batch",
            str(folder),
            "--out",
            str(tmp_path / "out"),
            "--positions",
            "12",
            "--serial",
            "--results",
        ]
    )
    assert code == 0
    rows = _rows(tmp_path / "out")
    assert [rows[k]["status"] for k in ("ann", "bob", "cid", "dan")] == [
        "ok",
        "failed",
        "failed",
        "failed",
    ]
    assert "dan.yaml:1:10: the file is not UTF-8 text" in rows["dan"]["reason"]
    assert rows["bob"]["b"] == "80.0" and "cannot assemble" in rows["bob"]["reason"]
    assert "cid.yaml:2:" in rows["cid"]["reason"]
    assert (tmp_path / "out" / "variants" / "ann" / "results.csv").is_file()
    assert (tmp_path / "out" / "variants" / "ann" / "summary.json").is_file()
    assert not (tmp_path / "out" / "variants" / "bob").exists()


def test_the_file_sweep_section_is_used_and_best_prints_the_top_row(tmp_path, capsys):
    path = tmp_path / "slider.yaml"
    path.write_text(SLIDER.read_text() + "sweep:\n  grid: {a: [90, 100, 110]}\n")
    assert ks.load(path).parameters["a"] == 100.0  # the loader ignores it
    code = main(
        [
            "batch",
            str(path),
            "--out",
            str(tmp_path / "out"),
            "--positions",
            "12",
            "--serial",
            "--best",
            "min motor.torque_friction_peak",
            "--where",
            "rod_slider.pressure_angle_max <= 30",
            "--top",
            "1",
        ]
    )
    out = capsys.readouterr().out
    assert code == 0 and "3 variants" in out
    table = out.strip().splitlines()[-2:]
    assert table[0].split()[:3] == ["variant", "a", "motor.torque_friction_peak"]
    assert table[1].split()[:2] == ["1", "90"]


def test_batch_help_and_a_bad_set_exit_2_with_one_line(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["batch", "--help"])
    assert exc.value.code == 0 and "--scheduler" in capsys.readouterr().out
    code = main(["batch", str(SLIDER), "--out", str(tmp_path), "--set", "a=1:x:3"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err == "kinetostatics: --set: 'a=1:x:3': 'x' is not a number"


def test_best_on_a_hand_made_table(tmp_path, capsys):
    (tmp_path / "summary.csv").write_text(
        "# units: ,file,,,N*m,deg\n"
        "variant,K,status,reason,motor.torque_peak,ram.pressure_angle_max\n"
        "a,1.5,ok,,30.0,12.0\n"  # smallest torque, but violates the constraint
        "b,1.8,ok,,40.0,8.0\n"
        "c,2.0,failed,cannot assemble,,\n"
        "d,2.2,ok,,35.0,9.5\n"
    )
    table = best.best(
        tmp_path / "summary.csv", "min motor.torque_peak", ["ram.pressure_angle_max <= 10"], top=5
    )
    assert [line.split()[0] for line in table.splitlines()[1:]] == ["d", "b"]
    assert main(["best", str(tmp_path), "--best", "max motor.torque_peak", "--top", "1"]) == 0
    assert capsys.readouterr().out.splitlines()[1].split()[:3] == ["b", "1.8", "40"]
    with pytest.raises(
        best.BestError,
        match=r"no column 'motor.torque_pk' \(did you mean "
        r"'motor.torque_peak'\?\)",
    ):
        best.best(tmp_path / "summary.csv", "min motor.torque_pk")
    assert main(["best", str(tmp_path), "--best", "min K", "--where", "K =< 2"]) == 2
    assert "expected 'COLUMN OP NUMBER'" in capsys.readouterr().err


def test_ctrl_c_leaves_the_finished_rows_and_the_same_command_resumes(tmp_path):
    """End to end: a real SIGINT to `kinetostatics batch`, then the same command."""
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "out"
    cmd = [
        sys.executable,
        "-m",
        "kinetostatics.cli",
        "batch",
        str(SLIDER),
        "--out",
        str(out),
        "--set",
        "a=80:120:600",
        "--positions",
        "12",
        "--serial",
        "--chunk",
        "1",
    ]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    p = subprocess.Popen(
        cmd,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and p.poll() is None:
        table = out / "summary.csv"
        if table.exists() and len(batch.read_summary(table)[1]) >= 3:
            break
        time.sleep(0.05)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    assert err.strip().splitlines()[-1].startswith("kinetostatics: interrupted; the finished rows")
    done = len(_rows(out))
    assert 3 <= done < 600
    assert main(cmd[3:-2]) == 0  # chunks do not change results: any size resumes
    runs = json.loads((out / "batch.json").read_text())["runs"]
    assert [r["computed"] for r in runs] == [done, 600 - done]
    assert len(_rows(out)) == 600


LOSE_THE_SCHEDULER = """
import functools, sys, warnings
import distributed
import kinetostatics.batch as B
from kinetostatics.cli import main
with warnings.catch_warnings():  # the setup's ("Port 8787 is already in use")
    warnings.simplefilter("ignore")
    cluster = distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, protocol="tcp", host="127.0.0.1",
        scheduler_port=0, dashboard_address=None,
    )
B.run_batch = functools.partial(B.run_batch, on_chunk=lambda done: cluster.close())
sys.exit(main(["batch", sys.argv[1], "--out", sys.argv[2], "--set", "a=90:110:6",
               "--positions", "12", "--chunk", "2", "--scheduler", cluster.scheduler_address]))
"""


def test_a_lost_dask_scheduler_is_one_line(tmp_path):
    """The scheduler goes away after the first chunk (the cluster is closed): the batch
    stops with one line on stderr and exit 2, not distributed's reconnection tracebacks
    (issue 36, item 12: 47 lines before the last)."""
    import os
    import subprocess
    import sys

    from tests.helpers import distributed_or_skip

    distributed_or_skip()
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    p = subprocess.run(
        [sys.executable, "-c", LOSE_THE_SCHEDULER, str(SLIDER), str(tmp_path / "b")],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
    )
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("kinetostatics: --scheduler tcp://127.0.0.1:") and (
        "run the same command again to resume" in lines[0]
    )


def test_batch_options_fingerprint_only_what_changes_the_rows():
    """run_batch's keywords as one frozen record; batch.json's options (the fingerprint of
    the rows) are the analysis's three, not how the batch runs."""
    import dataclasses

    from kinetostatics.batch.runner import BatchOptions

    o = BatchOptions(positions=36, executor="serial", chunk=3, friction=False)
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.chunk = 4
    assert o.analysis == {"positions": 36, "friction": False, "flywheel": None}
