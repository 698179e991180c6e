"""``kinetostatics export``: the mechanism at one position as DXF (read back with ezdxf)
and SVG.  The joints are found in the DXF where the result's point columns put them
(slider-crank: where its closed form puts them), in the file's length unit."""

import builtins
import math
import re
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.outputs.plotting.export import APP

ezdxf = pytest.importorskip("ezdxf")

ROCKER = """\
name: double rocker
units: {length: mm, angle: deg, speed: rpm}
links:
  ground: {points: {O: [0, 0], C: [60, 0]}}
  crank: {points: {O: [0, 0], A: [90, 0]}, mass: 1}
  coupler: {points: {A: [0, 0], B: [30, 0]}, mass: 1}
  rocker: {points: {C: [0, 0], B: [50, 0]}, mass: 1}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, coupler]}
  B: {type: revolute, links: [coupler, rocker]}
  C: {type: revolute, links: [ground, rocker]}
drivers:
  motor: {joint: O, motion: {speed: 10}}
sketch: {A: [90, 0], B: [100, 29]}
analysis: {start: 0, sweep: 20, positions: 21}
"""


def _tagged(doc, layer):
    """{name: entity} of the entities of ``layer`` named in the KINETOSTATICS xdata."""
    out = {}
    for e in doc.modelspace().query(f'*[layer=="{layer}"]'):
        if e.has_xdata(APP):
            tags = [t.value for t in e.get_xdata(APP)]
            out[tags[1]] = e
    return out


def _export(tmp_path, file, *extra):
    out = tmp_path / "m.dxf"
    assert main(["export", str(file), "--out", str(out), *extra]) == 0
    return ezdxf.readfile(str(out))


def test_slider_crank_joints_at_their_closed_form(tmp_path):
    """a = 100, b = 350 mm, guide at y = e = -20 mm; at φ = 30°:
    A = a(cos φ, sin φ), B = (a cos φ + √(b² − (a sin φ − e)²), e)."""
    doc = _export(tmp_path, "mechanisms/slider_crank.yaml", "--at", "30")
    assert doc.header["$INSUNITS"] == 4  # millimetres, as units.length
    a, b, e, phi = 100.0, 350.0, -20.0, math.radians(30.0)
    xa, ya = a * math.cos(phi), a * math.sin(phi)
    xb = xa + math.sqrt(b**2 - (ya - e) ** 2)
    expected = {"O": (0.0, 0.0), "A": (xa, ya), "B": (xb, e), "slide": (xb, e)}
    joints = _tagged(doc, "JOINTS")
    assert set(joints) == set(expected)
    for name, (x, y) in expected.items():
        c = joints[name].dxf.center
        assert (c.x, c.y) == pytest.approx((x, y), abs=1e-9), name
    points = _tagged(doc, "POINTS")
    assert points["rod.B"].dxf.location.x == pytest.approx(xb, abs=1e-9)


@pytest.mark.parametrize("name", ["stephenson_sixbar", "watt_sixbar", "jaw_crusher"])
def test_every_joint_at_its_point_column(tmp_path, name):
    """Each revolute at its pin: the result's column of its point on a moving link; the
    jaw crusher's gear pair at its pitch point, on the line of centres."""
    path = f"mechanisms/{name}.yaml"
    model = ks.load(path)
    result = ks.analyze(model)
    row = 40
    at = float(result["angle"][row])
    doc = _export(tmp_path, path, "--at", repr(at))
    scale = 1e3 if model.units.get("length") == "mm" else 1.0
    ground = model.ground.name
    joints = _tagged(doc, "JOINTS")

    def column(link, point):
        return np.array([result[f"{link}.{point}.{c}"][row] for c in "xy"]) * scale

    for j in model.joints:
        if j.kind == "gear":  # the pitch point: r1 = m z1 / 2 = 5 * 20 / 2 mm from Om
            ci, cj = (column(link, p) for link, p in zip(j.links, j.to_spec()["centres"]))
            x, y = ci + 50.0 * (cj - ci) / np.hypot(*(cj - ci))
        else:
            anchor = next(x for x in j.anchors() if x.at_joint and x.link != ground)
            x, y = column(anchor.link, anchor.point)
        c = joints[j.name].dxf.center
        assert (c.x, c.y) == pytest.approx((x, y), abs=1e-6 * scale), j.name


def test_forces_to_the_stated_scale(tmp_path):
    """Each reaction line, times the scale of the note, is the magnitude of a joint's
    reaction at that row (the result's Fx, Fy columns)."""
    doc = _export(tmp_path, "mechanisms/slider_crank.yaml", "--at", "30", "--forces")
    note = next(t.dxf.text for t in doc.modelspace().query("TEXT") if "drawing unit" in t.dxf.text)
    mu = float(re.search(r"1 drawing unit = ([0-9.e+-]+) N", note).group(1))
    result = ks.analyze(ks.load("mechanisms/slider_crank.yaml"))
    k = int(np.argmin(np.abs(result["angle"] - 30.0)))
    magnitudes = [
        math.hypot(result[f"{j}.Fx"][k], result[f"{j}.Fy"][k]) for j in ("O", "A", "B", "slide")
    ]
    lines = [
        e
        for e in doc.modelspace().query('LINE[layer=="FORCES"]')
        if e.has_xdata(APP) and e.get_xdata(APP)[0].value == "reaction"
    ]
    assert len(lines) == 4
    for e in lines:
        length = math.dist(tuple(e.dxf.start)[:2], tuple(e.dxf.end)[:2])
        assert min(abs(length * mu - m) / m for m in magnitudes) < 1e-3  # mu has 4 digits


def test_svg(tmp_path, capsys):
    out = tmp_path / "m.svg"
    assert (
        main(["export", "mechanisms/slider_crank.yaml", "--format", "svg", "--out", str(out)]) == 0
    )
    assert "angle 0 deg" in capsys.readouterr().out
    assert ET.parse(out).getroot().tag.endswith("svg")


def test_user_errors(tmp_path, capsys):
    rocker = tmp_path / "rocker.yaml"
    rocker.write_text(ROCKER)
    assert main(["export", str(rocker), "--at", "90", "--out", str(tmp_path / "r.dxf")]) == 2
    err = capsys.readouterr().err
    assert "90° is out of reach" in err and "reachable range" in err
    assert not (tmp_path / "r.dxf").exists()
    with pytest.raises(SystemExit) as exc:
        main(["export", str(rocker), "--format", "pdf"])
    assert exc.value.code == 2
    assert "invalid choice: 'pdf'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["export", str(rocker), "--at", "nan"])
    assert "expected a finite number" in capsys.readouterr().err


def test_missing_ezdxf(tmp_path, capsys, monkeypatch):
    real = builtins.__import__

    def no_ezdxf(name, *args, **kwargs):
        if name == "ezdxf" or name.startswith("ezdxf."):
            raise ImportError("No module named 'ezdxf'")
        return real(name, *args, **kwargs)

    for mod in [m for m in sys.modules if m == "ezdxf" or m.startswith("ezdxf.")]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setattr(builtins, "__import__", no_ezdxf)
    out = tmp_path / "m.dxf"
    assert main(["export", "mechanisms/slider_crank.yaml", "--out", str(out)]) == 2
    assert "pip install 'kinetostatics[dxf]'" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("name", ["cam_roller", "cam_flat_oscillating"])
def test_a_cam_profile_is_a_closed_polyline_through_the_contact(tmp_path, name):
    """Every pair draws through the contract: a cam's profile (and pitch curve) leave as
    closed polylines on the WHEELS layer (they were a TypeError)."""
    path = f"mechanisms/{name}.yaml"
    doc = _export(tmp_path, path, "--at", "30")
    curves = [e for e in doc.modelspace().query("LWPOLYLINE[layer=='WHEELS']") if e.closed]
    assert curves, "no closed profile curve"
    assert all(len(e) > 50 for e in curves)
