"""``optimize`` on every executor: serially, on a pool of processes and on a Dask cluster
(the ``dask_cluster`` fixture: 127.0.0.1, closed when the module is done) it evaluates
the same designs in the same order and finds the same best design — the executor only
changes where a population's chunks are analysed (docs/optimisation.md, *Executors*).
The reference is the serial run, which evaluates each population as one batch in this
process; a design's numbers do not depend on the other designs of its chunk."""

from __future__ import annotations

import math

import pytest

import kinetostatics as ks
from kinetostatics.batch.objectives import OptimizeError
from kinetostatics.batch.variants import Template, analyze_variants
from kinetostatics.cli import main
from kinetostatics.errors import KinetostaticsError
from tests.helpers import ROOT, LosingExecutor

SLOTTER = ROOT / "mechanisms" / "slotting_machine.yaml"
VARY = {"L_O2O3": (110.0, 240.0), "BC_ratio": (0.6, 1.6)}
SMALL = dict(popsize=4, maxiter=3, local_maxiter=12, positions=24, seed=3, progress=False)


def _same(a, b) -> None:
    """The same best design and objective to 1e-12, and the same designs in order."""
    for name in VARY:
        assert a.parameters[name] == pytest.approx(b.parameters[name], rel=1e-12, abs=0)
    assert a.objective == pytest.approx(b.objective, rel=1e-12, abs=0)
    assert len(a.designs) == len(b.designs)
    for da, db in zip(a.designs, b.designs):
        assert [da[n] for n in VARY] == [db[n] for n in VARY]
        assert da["status"] == db["status"]
        if not math.isnan(da["objective"]):
            assert da["objective"] == pytest.approx(db["objective"], rel=1e-12, abs=0)


@pytest.fixture(scope="module")
def serial():
    return ks.optimize(SLOTTER, VARY, "motor.torque_peak", **SMALL)


def test_the_serial_optimum_is_a_batch_row_and_beats_the_file(serial):
    """The reference run itself: its best design's torque is that design's batch row
    (analysed again on its own) and no worse than the file as written, which is in the
    first population (its bounds hold it)."""
    assert serial.feasible and len(serial.designs) > 8
    assert serial.designs[0]["L_O2O3"] == 150.0 and serial.designs[0]["BC_ratio"] == 1.0
    template = Template.load(SLOTTER)
    file, best = analyze_variants(template, [{}, serial.parameters], positions=24, flywheel=False)
    assert best["motor.torque_peak"] == pytest.approx(serial.objective, rel=1e-12)
    assert serial.objective <= file["motor.torque_peak"]


@pytest.mark.timeout(120)
def test_a_pool_of_processes_finds_the_same_design(serial):
    _same(
        serial,
        ks.optimize(SLOTTER, VARY, "motor.torque_peak", executor="processes", workers=2, **SMALL),
    )


@pytest.mark.timeout(120)
def test_a_dask_cluster_finds_the_same_design(serial, dask_cluster):
    address = dask_cluster.scheduler_address
    assert address.startswith("tcp://127.0.0.1:")
    _same(serial, ks.optimize(SLOTTER, VARY, "motor.torque_peak", executor=address, **SMALL))
    assert "analyze_chunk" in dask_cluster.scheduler.task_prefixes  # the cluster did the work


@pytest.mark.timeout(120)
def test_the_command_takes_a_scheduler_and_workers(serial, dask_cluster, tmp_path):
    """``--scheduler ADDRESS`` and ``--workers 2`` write the same best.yaml and
    designs.csv as the serial command, whose best design is the API's."""
    common = ["optimize", str(SLOTTER), "--vary", "L_O2O3=110:240", "--vary", "BC_ratio=0.6:1.6"]
    common += ["--minimize", "motor.torque_peak", "--popsize", "4", "--maxiter", "3"]
    common += ["--positions", "24", "--seed", "3", "--quiet"]
    runs = {
        "serial": [],
        "dask": ["--scheduler", dask_cluster.scheduler_address],
        "pool": ["--workers", "2"],
    }
    texts = {}
    for name, extra in runs.items():
        out = tmp_path / name
        # the API's local_maxiter=12 is not a command option: compare the search only
        assert main([*common, "--no-polish", *extra, "--out", str(out)]) == 0
        texts[name] = [(out / f).read_text() for f in ("best.yaml", "designs.csv")]
    assert texts["dask"] == texts["serial"] and texts["pool"] == texts["serial"]
    best = ks.load(tmp_path / "serial" / "best.yaml").parameters
    searched = [d for d in serial.designs if d["stage"] != "local"]
    top = min(searched, key=lambda d: d["score"])
    assert [best[n] for n in VARY] == [top[n] for n in VARY]


def test_the_executor_options_are_checked(capsys):
    args = ["optimize", str(SLOTTER), "--vary", "BC_ratio=0.6:1.6", "--minimize", "a"]
    assert main([*args, "--workers", "0"]) != 0
    assert "--workers 0: must be from 1 to 1024" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # argparse: not both
        main([*args, "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"])
    with pytest.raises(KinetostaticsError, match="executor 3.0: use 'processes'"):
        ks.optimize(SLOTTER, VARY, "motor.torque_peak", executor=3.0, progress=False)


def test_a_lost_executor_is_one_line():
    with pytest.raises(OptimizeError) as info:
        ks.optimize(
            SLOTTER, VARY, "motor.torque_peak", executor=LosingExecutor(3), workers=2, **SMALL
        )
    assert str(info.value) == (
        "the executor: failed (OSError: Timed out trying to connect to tcp://127.0.0.1:8786)"
    )


def test_a_flywheel_is_sized_only_when_an_expression_names_it():
    """The file's flywheel: is sized (variant by variant) when the objective names
    flywheel.inertia — the value of that design's batch row — and skipped otherwise."""
    small = dict(popsize=3, maxiter=1, positions=24, polish=False, progress=False)
    named = ks.optimize(SLOTTER, {"BC_ratio": (0.8, 1.2)}, "flywheel.inertia", **small)
    (row,) = analyze_variants(Template.load(SLOTTER), [named.parameters], positions=24)
    assert named.objective == pytest.approx(row["flywheel.inertia"], rel=1e-12)
    assert named.objective > 0
    plain = ks.optimize(SLOTTER, {"BC_ratio": (0.8, 1.2)}, "motor.torque_peak", **small)
    assert "flywheel.inertia" not in plain.row and "motor.torque_peak" in plain.row
