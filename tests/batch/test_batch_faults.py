"""Batches under hostile input and faults: option ranges and sweep sizes checked
up front, environment failures (a file as --out, no permission, a full disk, a
lost executor) as one line with exit 2 and no temporary file, one batch per
output folder, resume that rejects a row cut inside its last cell, worker
processes that die with a killed batch, a killed worker, and failing variants
that leave the stacked analysis before its costly stages."""

from __future__ import annotations

import errno
import json
import os
import signal
import subprocess
import sys
import time
from concurrent.futures import Executor, Future
from pathlib import Path

import pytest

from kinetostatics import batch
from kinetostatics.analysis import results
from kinetostatics.batch import executors, limits, sweeps, variants
from kinetostatics.batch import table as batch_table
from kinetostatics.cli import main
from kinetostatics.errors import OutputError
from kinetostatics.kinetics import friction
from tests.helpers import LosingExecutor, distributed_or_skip

ROOT = Path(__file__).resolve().parents[2]
SLIDER = ROOT / "mechanisms" / "slider_crank.yaml"
SLOTTER = ROOT / "mechanisms" / "slotting_machine.yaml"
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "src"))


def _rows(out):
    return {r["variant"]: r for r in batch.read_summary(Path(out) / "summary.csv")[1]}


def _same_rows(a: dict, b: dict) -> bool:
    """The same variants with the same cells; numbers equal to 1e-12 relative (a resumed
    batch analyses its last variants in other chunks: stacked and single analyses agree to
    round-off, docs/batch.md)."""
    if a.keys() != b.keys():
        return False
    for v in a:
        if a[v].keys() != b[v].keys():
            return False
        for k, x in a[v].items():
            y = b[v][k]
            try:
                fx, fy = float(x), float(y)
            except (TypeError, ValueError):
                if x != y:
                    return False
                continue
            if not (
                fx == fy or abs(fx - fy) <= 1e-12 * max(abs(fx), abs(fy)) or (fx != fx and fy != fy)
            ):  # both empty (NaN)
                return False
    return True


def _ids(out) -> list[str]:
    """The variant column of the table as written (duplicates would show)."""
    return [r["variant"] for r in batch.read_summary(Path(out) / "summary.csv")[1]]


def _one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.rglob("*") if p.name.endswith(".tmp"))


# -- limits ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "option, value, message",
    [
        ("--positions", "1000000000", "--positions 1000000000: must be from 1 to 10000000"),
        ("--positions", "0", "--positions 0: must be from 1 to 10000000"),
        ("--workers", "0", "--workers 0: must be from 1 to 1024"),
        ("--workers", "100000", "--workers 100000: must be from 1 to 1024"),
        ("--chunk", "0", "--chunk 0: must be from 1 to 10000000"),
        ("--seed", "-1", "--seed -1: must be from 0 to"),
    ],
)
def test_batch_options_out_of_range_are_refused_up_front(tmp_path, capsys, option, value, message):
    args = [
        "batch",
        str(SLIDER),
        "--out",
        str(tmp_path / "o"),
        "--serial",
        "--set",
        "a=90,95",
        option,
        value,
    ]
    if option == "--seed":
        args += ["--random", "2"]
        args[args.index("a=90,95")] = "a=90:95"
    if option == "--workers":
        args.remove("--serial")
    assert main(args) == 2
    assert message in _one_line(capsys.readouterr().err)
    assert not (tmp_path / "o").exists()  # nothing computed


def test_random_beyond_the_limit_and_a_set_beyond_it_name_the_limit(tmp_path, capsys):
    out = str(tmp_path / "o")
    assert (
        main(["batch", str(SLIDER), "--out", out, "--set", "a=90:110", "--random", "100000000"])
        == 2
    )
    assert "--random 100000000: must be from 1 to 10000000" in _one_line(capsys.readouterr().err)
    assert main(["batch", str(SLIDER), "--out", out, "--set", "a=90:110:100000000"]) == 2
    line = _one_line(capsys.readouterr().err)
    assert "NUM 100000000 is more than the limit of 10000000 values" in line, line


@pytest.mark.timeout(60)  # refused before 10 million variants are made: a hang otherwise
def test_a_sweep_larger_than_memory_is_refused_before_it_is_made(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(limits, "available_memory", lambda: 2**20)  # 1 MiB free
    with pytest.raises(sweeps.SweepError, match="10000000 variants: about 76.3 GB"):
        sweeps.expand(sweeps.from_options(["a=90:110:10000000"]))  # the documented maximum
    with pytest.raises(sweeps.SweepError, match="the grid has 1000 variants"):
        sweeps.expand(sweeps.from_options(["a=90:110:10", "b=300:400:100"]))
    assert (
        main(
            [
                "batch",
                str(SLIDER),
                "--out",
                str(tmp_path / "o"),
                "--serial",
                "--set",
                "a=90:110:200",
                "--positions",
                "12",
            ]
        )
        == 2
    )
    line = _one_line(capsys.readouterr().err)
    assert "200 variants" in line and "more than the 0.0 GB available" in line, line
    assert not (tmp_path / "o").exists()
    with pytest.raises(batch.BatchError, match="positions 100000: one variant"):
        batch.run_batch(str(SLIDER), None, tmp_path / "p", executor="serial", positions=100_000)


# -- environment failures ----------------------------------------------------------------
def test_out_naming_a_file_is_one_line_exit_2(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["run", str(SLIDER), "--out", str(f)]) == 2
    assert (
        _one_line(capsys.readouterr().err) == f"kinetostatics: --out {f}: is a file, not a folder"
    )
    assert (
        main(
            [
                "batch",
                str(SLIDER),
                "--out",
                str(f),
                "--serial",
                "--set",
                "a=90,95",
                "--positions",
                "12",
            ]
        )
        == 2
    )
    assert (
        _one_line(capsys.readouterr().err) == f"kinetostatics: --out {f}: is a file, not a folder"
    )
    assert main(["run", str(SLIDER), "--out", str(f / "sub")]) == 2
    assert (
        _one_line(capsys.readouterr().err)
        == f"kinetostatics: --out {f / 'sub'}: cannot write {f / 'sub'}: Not a directory"
    )
    assert f.read_text() == "x"


def _refuse(err: int, after: int = 0, partial: bool = True):
    """A replacement of ``batch_table._Table._write`` failing with ``err`` after ``after``
    writes; the failing write leaves half its text (a full disk's partial write)."""
    real = batch_table._Table._write
    calls = {"n": 0}

    def write(path, text, mode):
        calls["n"] += 1
        if calls["n"] > after:
            if partial:
                with open(path, mode, encoding="utf-8", newline="") as fh:
                    fh.write(text[: len(text) // 2])
            raise OSError(err, os.strerror(err), str(path))
        real(path, text, mode)

    return write


def test_a_read_only_out_is_one_line_exit_2(tmp_path, capsys, monkeypatch):
    # root ignores permissions, so the refusal is injected where the files are written
    monkeypatch.setattr(batch_table._Table, "_write", staticmethod(_refuse(errno.EACCES, 0, False)))
    out = tmp_path / "ro"
    assert (
        main(
            [
                "batch",
                str(SLIDER),
                "--out",
                str(out),
                "--serial",
                "--set",
                "a=90,95",
                "--positions",
                "12",
            ]
        )
        == 2
    )
    line = _one_line(capsys.readouterr().err)
    assert line == f"kinetostatics: --out {out}: cannot write {out}/batch.json: Permission denied"
    assert _leftovers(out) == []

    def denied(self, path):
        raise PermissionError(errno.EACCES, "Permission denied", str(path))

    monkeypatch.setattr(results.Result, "to_csv", denied)
    assert main(["run", str(SLIDER), "--out", str(tmp_path / "r")]) == 2
    line = _one_line(capsys.readouterr().err)
    assert line == (
        f"kinetostatics: --out {tmp_path / 'r'}: cannot write "
        f"{tmp_path / 'r' / 'results.csv'}: Permission denied"
    ), line
    assert _leftovers(tmp_path / "r") == []


def test_a_full_disk_in_run_leaves_no_file_behind(tmp_path, capsys, monkeypatch):
    def full(self, path, summary=None):
        Path(path).write_text('{"half": ')
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(results.Result, "to_json", full)
    out = tmp_path / "r"
    assert main(["run", str(SLIDER), "--out", str(out)]) == 2
    assert _one_line(capsys.readouterr().err).endswith("No space left on device")
    assert _leftovers(out) == [] and not (out / "summary.json").exists()


@pytest.mark.parametrize("after", [1, 3, 5])
def test_a_full_disk_stops_the_batch_and_a_rerun_finds_every_row_once(
    tmp_path, capsys, monkeypatch, after
):
    """ENOSPC at the header, in the middle of the appended rows, at the final rewrite."""
    cmd = [
        "batch",
        str(SLIDER),
        "--out",
        str(tmp_path / "o"),
        "--serial",
        "--chunk",
        "2",
        "--set",
        "a=90:110:6",
        "--positions",
        "12",
    ]
    monkeypatch.setattr(batch_table._Table, "_write", staticmethod(_refuse(errno.ENOSPC, after)))
    assert main(cmd) == 2
    line = _one_line(capsys.readouterr().err)
    assert line.endswith("No space left on device"), line
    assert _leftovers(tmp_path / "o") == []
    monkeypatch.undo()
    assert main(cmd) == 0
    assert _ids(tmp_path / "o") == ["1", "2", "3", "4", "5", "6"]
    assert main([*cmd[:2], "--out", str(tmp_path / "fresh"), *cmd[4:]]) == 0
    assert _same_rows(_rows(tmp_path / "o"), _rows(tmp_path / "fresh"))
    assert _leftovers(tmp_path) == []


def test_a_lost_executor_is_one_line_and_the_rows_so_far_are_kept(tmp_path):
    vs = sweeps.expand(sweeps.from_options(["a=90:110:6"]))
    tasks = [batch.Task(v, 0, o) for v, o in vs]
    with pytest.raises(OutputError) as info:
        batch.run_batch(
            str(SLIDER), tasks, tmp_path, executor=LosingExecutor(2), chunk=1, positions=12
        )
    assert str(info.value).startswith(
        "the executor: failed (OSError: Timed out"
    ) and "run the same command again to resume" in str(info.value)
    assert _ids(tmp_path) == ["1", "2"]
    s = batch.run_batch(str(SLIDER), tasks, tmp_path, executor="serial", chunk=1, positions=12)
    assert (s.reused, s.computed) == (2, 4) and _ids(tmp_path) == [v for v, _ in vs]


def test_a_lost_dask_scheduler_is_one_line():
    distributed_or_skip()
    err = executors._executor_error("tcp://127.0.0.1:1", OSError("closed"), Path("o"))
    assert str(err).startswith("--scheduler tcp://127.0.0.1:1: failed (OSError: closed)")


# -- one batch per folder ----------------------------------------------------------------
def test_a_second_batch_on_the_same_out_is_refused_and_a_stale_lock_taken_over(tmp_path, capsys):
    out = tmp_path / "o"
    cmd = [
        sys.executable,
        "-m",
        "kinetostatics.cli",
        "batch",
        str(SLIDER),
        "--out",
        str(out),
        "--set",
        "a=80:120:60",
        "--positions",
        "12",
        "--serial",
        "--chunk",
        "1",
    ]
    p = subprocess.Popen(cmd, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and p.poll() is None:
            if (out / "summary.csv").exists() and len(_ids(out)) >= 2:
                break
            time.sleep(0.02)
        assert p.poll() is None, p.communicate()
        assert main(cmd[3:]) == 2
        line = _one_line(capsys.readouterr().err)
        assert (
            line.startswith(
                f"kinetostatics: {out}: another batch is writing to this folder (pid {p.pid} on "
            )
            and "use another --out" in line
        ), line
    finally:
        _, err = p.communicate(timeout=120)
    assert p.returncode == 0, err
    assert _ids(out) == [f"{k:02d}" for k in range(1, 61)]
    assert json.loads((out / "batch.json").read_text())["computed"] == 60
    assert not (out / "batch.lock").exists()
    # a lock left by a process that is gone: taken over
    (out / "batch.lock").write_text("pid 999999999 on elsewhere since 2000-01-01 00:00:00\n")
    assert main(cmd[3:]) == 0
    assert "60 from the previous run" in capsys.readouterr().out
    assert not (out / "batch.lock").exists()


def test_a_held_lock_refuses_the_python_api_too(tmp_path):
    lock = batch_table._Lock(tmp_path)
    lock.acquire()
    try:
        with pytest.raises(batch.BatchError, match="another batch is writing to this folder"):
            batch.run_batch(str(SLIDER), None, tmp_path, executor="serial", positions=12)
    finally:
        lock.release()
    assert (
        batch.run_batch(str(SLIDER), None, tmp_path, executor="serial", positions=12).computed == 1
    )


# -- resume ------------------------------------------------------------------------------
def test_resume_drops_a_row_cut_inside_its_last_cell(tmp_path):
    vs = sweeps.expand(sweeps.from_options(["a=90:110:4"]))
    tasks = [batch.Task(v, 0, o) for v, o in vs]
    opts = dict(executor="serial", positions=12, chunk=1)
    batch.run_batch(str(SLIDER), tasks, tmp_path / "b", **opts)
    full = _rows(tmp_path / "b")
    table = tmp_path / "b" / "summary.csv"
    text = table.read_text()
    last = text.rstrip("\n").rsplit("\n", 1)[1]
    assert last.startswith("4,") and len(last.split(",")[-1]) > 3
    table.write_text(text.rstrip("\n")[:-2])  # the cut falls inside the last cell
    cut = batch.read_summary(table)[1]
    assert [r["variant"] for r in cut] == ["1", "2", "3"]
    s = batch.run_batch(str(SLIDER), tasks, tmp_path / "b", **opts)
    assert (s.reused, s.computed) == (3, 1)
    assert _same_rows(_rows(tmp_path / "b"), full)


# -- killed processes --------------------------------------------------------------------
def _children(pid: int) -> list[int]:
    try:
        text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    except OSError:
        return []
    return [int(x) for x in text.split()]


def _alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] not in ("Z", "X")


def _start_batch(out: Path, n: int, rows: int) -> subprocess.Popen:
    cmd = [
        sys.executable,
        "-m",
        "kinetostatics.cli",
        "batch",
        str(SLIDER),
        "--out",
        str(out),
        "--set",
        f"a=80:120:{n}",
        "--positions",
        "12",
        "--workers",
        "2",
        "--chunk",
        "1",
    ]
    p = subprocess.Popen(cmd, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    p.args_list = cmd
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and p.poll() is None:
        if (out / "summary.csv").exists() and len(_ids(out)) >= rows and len(_children(p.pid)) >= 2:
            break
        time.sleep(0.02)
    assert p.poll() is None, p.communicate()
    return p


@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="needs Linux /proc")
def test_sigkill_of_the_batch_kills_its_workers_and_the_rerun_finds_every_row_once(tmp_path):
    out = tmp_path / "o"
    p = _start_batch(out, 400, 3)
    workers = _children(p.pid)
    p.kill()
    p.communicate(timeout=30)
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(_alive(w) for w in workers):
        time.sleep(0.05)
    assert not any(_alive(w) for w in workers), "orphan workers"
    done = len(_ids(out))
    assert 3 <= done < 400
    assert main([*p.args_list[3:-4], "--serial", "--chunk", "50"]) == 0  # lock taken over
    assert _ids(out) == [f"{k:03d}" for k in range(1, 401)]
    assert {r["status"] for r in _rows(out).values()} == {"ok"}


@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="needs Linux /proc")
def test_a_killed_worker_is_replaced_and_every_row_is_computed_once(tmp_path):
    out = tmp_path / "o"
    p = _start_batch(out, 30, 2)
    os.kill(_children(p.pid)[0], signal.SIGKILL)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 0, err
    assert _ids(out) == [f"{k:02d}" for k in range(1, 31)]
    assert {r["status"] for r in _rows(out).values()} == {"ok"}


# -- failing variants and the stacked analysis ------------------------------------------
def test_failing_variants_do_not_reach_the_stacked_friction_solution(monkeypatch, fixed_sketch):
    tpl = variants.Template.load(fixed_sketch)
    # 1 and 3 assemble away from the sketch of K = 2 (on another branch), 2 and 4 near it
    ovs = [
        {"K": 1.2, "H": 140.0, "L_O2O3": 180.0},
        {"K": 2.8, "H": 140.0, "L_O2O3": 120.0},
        {"K": 1.2, "H": 140.0, "L_O2O3": 170.0},
        {"K": 2.8, "H": 140.0, "L_O2O3": 180.0},
    ]
    calls = {"n": 0}
    real = friction._jacobian

    def counting(*a, **k):
        calls["n"] += 1
        return real(*a, **k)

    monkeypatch.setattr(friction, "_jacobian", counting)
    rows = variants.analyze_variants(tpl, ovs, positions=24, flywheel=False)
    assert [r["status"] for r in rows] == ["failed", "ok", "failed", "ok"]
    assert calls["n"] == 0  # no homotopy on a failed variant's NaN rows
    one = variants.analyze_variants(tpl, ovs, positions=24, flywheel=False, vectorise=False)
    for a, b in zip(rows, one):
        assert a.keys() == b.keys()
        for k in a:
            assert a[k] == b[k] or a[k] == pytest.approx(b[k], rel=1e-12), k


class _Cancelling(Executor):
    """Runs ``n`` chunks, then cancels every later one (a Dask client that lost
    its scheduler cancels the futures it holds)."""

    def __init__(self, n: int):
        self.n = n

    def submit(self, fn, /, *args, **kwargs):
        f: Future = Future()
        if self.n == 0:
            f.cancel()
            f.set_running_or_notify_cancel()
            return f
        self.n -= 1
        f.set_result(fn(*args, **kwargs))
        return f


def test_futures_cancelled_by_the_executor_stop_the_batch_with_one_line(tmp_path):
    vs = sweeps.expand(sweeps.from_options(["a=90:110:6"]))
    tasks = [batch.Task(v, 0, o) for v, o in vs]
    with pytest.raises(
        OutputError,
        match=r"^the executor: failed \(CancelledError\); "
        r"the finished rows are in",
    ):
        batch.run_batch(
            str(SLIDER), tasks, tmp_path, executor=_Cancelling(3), chunk=1, positions=12
        )
    done = _ids(tmp_path)
    assert set(done) < {v for v, _ in vs} and all(
        r["status"] == "ok" for r in _rows(tmp_path).values()
    )
    batch.run_batch(str(SLIDER), tasks, tmp_path, executor="serial", chunk=1, positions=12)
    assert _ids(tmp_path) == [v for v, _ in vs]


def test_without_flock_the_lock_file_names_a_live_or_a_dead_holder(tmp_path, monkeypatch):
    fcntl = pytest.importorskip("fcntl")

    def no_locks(fd, op):
        raise OSError(errno.ENOLCK, "No locks available")

    monkeypatch.setattr(fcntl, "flock", no_locks)
    (tmp_path / "batch.lock").write_text(f"pid {os.getppid()} on here since today\n")
    with pytest.raises(
        batch.BatchError,
        match=f"another batch is writing to this folder \\(pid {os.getppid()} on here",
    ):
        batch.run_batch(str(SLIDER), None, tmp_path, executor="serial", positions=12)
    (tmp_path / "batch.lock").write_text("pid 999999999 on here since yesterday\n")
    assert (
        batch.run_batch(str(SLIDER), None, tmp_path, executor="serial", positions=12).computed == 1
    )
    assert not (tmp_path / "batch.lock").exists()
