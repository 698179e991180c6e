"""``import kinetostatics`` and ``kinetostatics run`` load only what they use (issue 40):
every module loaded is paid at the start of every command, so the modules each leaves
off its path are listed here, checked in a fresh process (``sys.modules`` at its end)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from kinetostatics.cli import BLAS_THREADS, EXTENSIONS

ROOT = Path(__file__).resolve().parents[2]

# what `run` of a file without sizing data never needs
RUN_LAZY = (
    # the other commands: their parsers are built only for them (cli.main)
    *EXTENSIONS,
    # the sizing stage, for a file with bearing, pin or section data
    "kinetostatics.sizing",
    "kinetostatics.methods",
    # the layers of the other commands
    "kinetostatics.batch",
    "kinetostatics.editor",
    "kinetostatics.outputs.plotting",
    "kinetostatics.outputs.report",
    # heavy packages: pictures, integrators, PDF, fonts, the editor's server
    "matplotlib",
    "scipy",
    "networkx",
    "fontTools",
    "fpdf",
    "email",
    "http",
    "decimal",
    "difflib",
    "tempfile",
    "importlib.resources",
    # NumPy's masked arrays: np.unique(x) imports them (~7-12 ms) to ask whether x is one
    "numpy.ma",
)
# and what `import kinetostatics` leaves to the first use of a name (NumPy included: a
# command sets its BLAS threads before NumPy loads, cli.main)
IMPORT_LAZY = RUN_LAZY + (
    "numpy",
    "kinetostatics.model",
    "kinetostatics.outputs",
    "kinetostatics.analysis",
    "kinetostatics.structure",
    "kinetostatics.kinematics",
    "kinetostatics.kinetics",
    "kinetostatics.dynamics",
)


def _loaded(code: str, names: tuple[str, ...], env: dict | None = None) -> list[str]:
    """Which of ``names`` are in ``sys.modules`` after ``code`` runs in a fresh process, on
    the default backend (the compiled backend's numba loads scipy, email and others itself:
    the suite run with ``KINETOSTATICS_BACKEND=numba`` leaves it out here)."""
    if env is None:
        env = {k: v for k, v in os.environ.items() if k != "KINETOSTATICS_BACKEND"}
    script = f"import json, sys\n{code}\nprint(json.dumps(sorted(sys.modules)))"
    out = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
        env=env,
    )
    modules = set(json.loads(out.stdout.splitlines()[-1]))
    return [n for n in names if n in modules]


def test_import_kinetostatics_loads_no_stage_and_no_heavy_package():
    assert _loaded("import kinetostatics", IMPORT_LAZY) == []


def test_run_of_a_file_without_sizing_data_loads_only_what_it_uses(tmp_path):
    code = (
        "from kinetostatics.cli import main\n"
        f"code = main(['run', 'mechanisms/slotting_machine.yaml', '--out', {str(tmp_path)!r}])\n"
        "assert code == 0, code"
    )
    assert _loaded(code, RUN_LAZY) == []
    assert (tmp_path / "results.csv").is_file() and (tmp_path / "summary.json").is_file()
    assert not (tmp_path / "sizing.json").exists()


def test_run_of_a_file_with_sizing_data_loads_the_sizing_stage(tmp_path):
    """The other side of the sizing stage's laziness: a file with sizing data sizes."""
    code = (
        "from kinetostatics.cli import main\n"
        "code = main(['run', 'mechanisms/slider_crank_sized.yaml', '--out', "
        f"{str(tmp_path)!r}])\n"
        "assert code == 0, code"
    )
    assert _loaded(code, ("kinetostatics.sizing",)) == ["kinetostatics.sizing"]
    assert (tmp_path / "sizing.json").is_file()


@pytest.mark.parametrize("given", [None, "2"])
def test_a_command_starts_one_blas_thread_unless_told_otherwise(given):
    """A command sets OpenBLAS to one thread before NumPy loads (its threads only spin
    for the commands' small blocks), and keeps a value the user gave; the process then
    has as many threads as that (Linux: its tasks)."""
    env = {k: v for k, v in os.environ.items() if k not in BLAS_THREADS}
    if given is not None:
        env["OPENBLAS_NUM_THREADS"] = given
    code = (
        "import os\n"
        "from kinetostatics.cli import main\n"
        "assert main(['check', 'mechanisms/slider_crank.yaml']) == 0\n"
        "import numpy\n"
        "tasks = os.listdir('/proc/self/task') if os.path.isdir('/proc/self/task') else None\n"
        "print(os.environ['OPENBLAS_NUM_THREADS'], None if tasks is None else len(tasks))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT, env=env
    )
    value, tasks = out.stdout.split()[-2:]
    assert value == (given or "1")
    if tasks != "None" and given is None:
        assert int(tasks) == 1
