"""A result as tables (analysis/frames.py): members, select, pandas, xarray, the short
repr, the notebook view, and ks.__version__.  Expected values are the offset
slider-crank's closed forms (crank a = 100 mm, rod b = 350 mm, guide at e = -20 mm,
300 rpm): A = a(cos θ, sin θ), x_B = a cos θ + √(b² − (a sin θ − e)²)."""

import builtins
import importlib.metadata
import re
import subprocess
import sys

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.errors import MissingPackageError

A, B, E = 0.100, 0.350, -0.020


@pytest.fixture(scope="module")
def result():
    return ks.analyze(ks.load("mechanisms/slider_crank.yaml"))


def _slider_x(theta_deg):
    th = np.radians(theta_deg)
    return A * np.cos(th) + np.sqrt(B**2 - (A * np.sin(th) - E) ** 2)


def test_members_and_select(result):
    groups = result.members()
    for member in ("crank", "rod", "slider", "O", "slide", "motor", "power", "time", "angle"):
        assert member in groups
    assert "crank.A.x" in groups["crank"] and "rod.B.vy" in groups["rod"]
    assert groups["time"] == ["time"]
    crank = result.select("crank")
    th = np.radians(result["angle"])
    np.testing.assert_allclose(crank["A.x"], A * np.cos(th), atol=1e-12)
    np.testing.assert_allclose(crank["A.y"], A * np.sin(th), atol=1e-12)
    np.testing.assert_allclose(crank["omega"], 300 * 2 * np.pi / 60, rtol=1e-12)
    with pytest.raises(KeyError, match="no member 'cranck'.*did you mean 'crank'"):
        result.select("cranck")


def test_to_pandas(result):
    df = result.to_pandas()
    assert df.shape == (360, len(result.columns))
    assert df.index.name == "position"
    assert df.attrs["units"]["crank.omega"] == "rad/s"  # docs/conventions.md
    assert df.attrs["units"]["slider.x"] == "m"
    assert df.attrs["units"]["motor.torque"] == "N*m"
    np.testing.assert_allclose(df["slider.x"], _slider_x(df["angle"]), atol=1e-10)
    multi = result.to_pandas(multiindex=True)
    assert ("rod", "B.x") in multi.columns and ("time", "") in multi.columns
    assert list(multi.columns.names) == ["member", "quantity"]
    np.testing.assert_allclose(multi["slider"]["x"], _slider_x(df["angle"]), atol=1e-10)
    assert multi.attrs["units"][("crank", "alpha")] == "rad/s^2"


def test_to_xarray(result):
    ds = result.to_xarray()
    assert ds.sizes == {"position": 360}
    for name in ("time", "angle", "travel"):
        assert name in ds.coords
    assert ds["crank.omega"].attrs["units"] == "rad/s"
    assert ds["angle"].attrs["units"] == "deg"
    at90 = ds.sel(angle=90.0)
    assert float(at90["slider.x"]) == pytest.approx(_slider_x(90.0), abs=1e-10)
    assert float(at90["crank.A.y"]) == pytest.approx(A, abs=1e-12)
    # time at 90° of a 300 rpm crank: a quarter turn of 0.2 s
    assert float(at90["time"]) == pytest.approx(0.05, abs=1e-12)


def test_missing_package_names_the_extra(result, monkeypatch):
    real = builtins.__import__

    def no_pandas(name, *args, **kwargs):
        if name == "pandas" or name.startswith("pandas."):
            raise ImportError("No module named 'pandas'")
        return real(name, *args, **kwargs)

    monkeypatch.delitem(sys.modules, "pandas", raising=False)
    monkeypatch.setattr(builtins, "__import__", no_pandas)
    with pytest.raises(MissingPackageError, match=r"pip install 'kinetostatics\[pandas\]'"):
        result.to_pandas()


def test_short_repr_and_html(result):
    text = repr(result)
    assert len(text) < 200 and "\n" not in text
    assert "offset slider-crank" in text and "360 positions" in text
    assert f"{len(result.columns)} columns" in text and "checks ok" in text
    page = result._repr_html_()
    assert len(page) < 5000
    assert page.count("<tr>") == 1 + 5  # the header and five rows
    # the first row's crank centre-of-mass speed at 0°: ω r1 upwards, r1 = 30 mm
    vy = 300 * 2 * np.pi / 60 * 0.030
    assert f"<td>{vy:.6g}</td>" in page


def test_version():
    assert re.fullmatch(r"\d+\.\d+.*", ks.__version__)
    # the installed distribution's metadata is read from the same place
    assert importlib.metadata.version("kinetostatics") == ks.__version__
    run = subprocess.run(
        [sys.executable, "-m", "kinetostatics.cli", "--version"],
        capture_output=True,
        text=True,
        env={"PYTHONPATH": "src", "PATH": ""},
    )
    assert run.returncode == 0
    assert run.stdout.strip() == f"kinetostatics {ks.__version__}"
