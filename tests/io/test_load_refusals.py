"""Files refused at load with one line naming what the user wrote (issue 36): a file over
the link limit stops at that cause, a spring whose two points always coincide, an
``output:`` that names no output (docs/errors.md, docs/yaml.md)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.base.limits import MAX_LINKS
from kinetostatics.cli import main
from kinetostatics.dynamics.stages import full_summary


def _chain(n: int) -> str:
    """A serial chain of ``n`` moving links, each named by loads, elements, sketch, output."""
    lines = ["links:", "  ground: {points: {O: [0, 0]}}"]
    lines += [f"  l{i}: {{points: {{P: [0, 0], Q: [1, 0]}}, mass: 1}}" for i in range(n)]
    lines += ["joints:", "  j0: {type: revolute, links: [ground, l0], points: [O, P]}"]
    lines += [
        f"  j{i}: {{type: revolute, links: [l{i - 1}, l{i}], points: [Q, P]}}" for i in range(1, n)
    ]
    lines += [
        "drivers: {motor: {joint: j0, motion: {speed: 10}}}",
        "loads: {w: {type: torque, link: l3, value: 1}}",
        "elements: {s: {type: spring, between: [l1.Q, l4.P], stiffness: 1, free_length: 1}}",
        "sketch: {l1.Q: [1, 0]}",
        "output: l5",
    ]
    return "\n".join(lines) + "\n"


def test_over_the_link_limit_is_one_line(tmp_path, capsys):
    """Over MAX_LINKS the links section is refused whole; what names a link is not
    reported again as 'unknown link' (it was: one line per joint end, load, element)."""
    with pytest.raises(ks.ModelError) as info:
        ks.loads(_chain(MAX_LINKS), file="many.yaml")
    assert [m for _, m in info.value.problems] == [
        f"{MAX_LINKS + 1} links; the limit is {MAX_LINKS}"
    ]
    path = tmp_path / "many.yaml"
    path.write_text(_chain(MAX_LINKS))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    line = f"{path}:1:1: links: {MAX_LINKS + 1} links; the limit is {MAX_LINKS}"
    assert err.splitlines() == [line]


def test_just_under_the_link_limit_loads():
    model = ks.loads(_chain(MAX_LINKS - 1))
    assert len(model.links) == MAX_LINKS


# -- a spring or damper between two points that always coincide (issue 36, item 5) -------
FOUR_BAR = """\
name: four-bar with a spring
units: {length: mm, angle: deg, speed: rpm}
links:
  ground:
    points: {O: [0, 0], D: [300, 0], S: [150, 200], X: [100, 0], O2: [0, 0]}
  crank: {points: {O: [0, 0], A: [100, 0]}, com: [50, 0], mass: 1.0, inertia: 0.001}
  coupler: {points: {A: [0, 0], B: [350, 0]}, com: [175, 0], mass: 2.0, inertia: 0.02}
  rocker: {points: {D: [0, 0], B: [250, 0]}, com: [125, 0], mass: 1.5, inertia: 0.008}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, coupler]}
  B: {type: revolute, links: [coupler, rocker]}
  D: {type: revolute, links: [ground, rocker]}
drivers:
  motor: {joint: O, motion: {speed: 120}}
elements:
  pull: {type: ELEMENT, between: [ENDS], KEYS}
sketch: {A: [100, 0], B: [350, 245]}
analysis: {start: 0, sweep: 360, positions: 36}
"""
SPRING = "stiffness: 2, free_length: 10"


def _four_bar(ends: str, element: str = "spring", keys: str = SPRING) -> str:
    return FOUR_BAR.replace("ELEMENT", element).replace("ENDS", ends).replace("KEYS", keys)


@pytest.mark.parametrize(
    ("ends", "element", "keys", "by"),
    [
        ("ground.O, crank.O", "spring", SPRING, "revolute 'O'"),  # the file
        ("crank.O, ground.O2", "spring", SPRING, "revolute 'O'"),  # O2: O's place on ground
        ("ground.O, coupler.B", "damper", "damping: 0.05", None),  # apart: accepted
        ("crank.A, rocker.B", "spring", SPRING, None),  # apart: accepted
        ("crank.A, coupler.A", "damper", "damping: 0.05", "revolute 'A'"),
    ],
)
def test_element_between_coincident_points(ends, element, keys, by):
    text = _four_bar(ends, element, keys)
    if by is None:
        ks.loads(text)
        return
    with pytest.raises(ks.ModelError) as info:
        ks.loads(text, file="m.yaml")
    (where, message), *rest = info.value.problems
    assert not rest and where.path == "elements.pull.between"
    a, b = (e.strip() for e in ends.split(","))
    assert message.startswith(f"{a} and {b} are at the same place at every position")
    assert f"held together by {by})" in message and f"the {element}'s direction" in message


def test_element_at_a_compound_hinge():
    """The jaw crusher's rear and front toggles share the pitman's pin B through two
    revolutes (B3, B4): a spring between rear.B and front.B always has length 0."""
    from tests.helpers import ROOT

    text = (ROOT / "mechanisms" / "jaw_crusher.yaml").read_text()
    text = text.replace(
        "drivers:\n",
        "elements: {s: {type: spring, between: [rear.B, front.B], stiffness: 1, "
        "free_length: 0}}\ndrivers:\n",
        1,
    )
    with pytest.raises(ks.ModelError) as info:
        ks.loads(text)
    (_, message), *rest = info.value.problems
    assert not rest
    assert "held together by revolute 'B3', revolute 'B4')" in message


def test_element_whose_length_reaches_zero_is_warned():
    """ground.X = crank.A at crank 0°: |A − X| = 2·100 mm·|sin(θ/2)| is zero on that row
    only (36 rows, 0° to 350°); the warning names it, and no other."""
    with pytest.warns(ks.errors.ElementWarning) as caught:
        result = ks.analyze(ks.build_system(ks.loads(_four_bar("ground.X, crank.A"))))
    theta = np.radians(result["angle"])
    expected = 0.2 * np.abs(np.sin(theta / 2))
    assert np.allclose(result["pull.length"], expected, rtol=0, atol=1e-12 * 0.2)
    messages = [str(w.message) for w in caught if issubclass(w.category, ks.errors.ElementWarning)]
    zero = np.nonzero(expected <= 1e-9 * 0.45)[0]
    assert zero.tolist() == [0]
    assert messages == [
        "element 'pull': ground.X and crank.A meet (length 0) at 1 position(s), motor = 0°: "
        "the spring's direction is undefined there and its force acts on nothing"
    ]


def test_element_apart_is_not_warned():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", ks.errors.ElementWarning)
        ks.analyze(ks.build_system(ks.loads(_four_bar("ground.S, rocker.B"))))


# -- output: what docs/yaml.md says it names, and nothing else (issue 36, item 17) --------
KINDS = (
    "output takes a moving link that no motion driver moves on the frame, an undriven "
    "revolute, or an undriven prismatic pair on the frame"
)


@pytest.mark.parametrize(
    ("value", "head"),
    [
        (
            "crank",
            "link 'crank' is moved on the frame by joint 'O' of motion driver 'motor': "
            "it is the input",
        ),  # accepted before, with an empty outputs
        ("O", "'O' is the joint of motion driver 'motor', the input"),
        ("ground", "'ground' is the frame, not an output"),
        ("rockr", "unknown link or joint 'rockr' (did you mean 'rocker'?)"),
    ],
)
def test_output_refusals_name_the_key_and_the_kinds(value, head):
    text = _four_bar("ground.S, rocker.B") + f"output: {value}\n"
    with pytest.raises(ks.ModelError) as info:
        ks.loads(text, file="m.yaml")
    (where, message), *rest = info.value.problems
    assert not rest and where.path == "output"
    assert message == f"{head}; {KINDS}"


@pytest.mark.parametrize("value", ["rocker", "coupler", "D", "B"])
def test_output_accepts_what_the_docs_name(value):
    """A moving link other than the input, an undriven revolute on the frame (D) or
    between moving links (B): each gives one output with a swing."""
    s = full_summary(ks.analyze(ks.loads(_four_bar("ground.S, rocker.B") + f"output: {value}\n")))
    assert s["output"] == value and len(s["outputs"]) == 1
    assert next(iter(s["outputs"].values()))["swing"] > 0
