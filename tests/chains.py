"""Large generated linkages for the size-scaling tests and benchmark.

``dyad_chain(n)`` is a crank–rocker four-bar followed by a chain of RRR dyads:
``n`` dyads in all (the four-bar's coupler and rocker are the first), 2n + 1
moving links.  Every later dyad is a rod and a rocker pivoted on the ground, the
rod as long as the distance between the pivots and the rocker's points at the
radii of the points they join: each stage is a parallelogram, so every rocker
turns exactly as the first and the chain stays as far from singular as the
four-bar (transmission angles above 40°) over the whole crank turn, however long.
With ``redundant=True`` each stage gets a second rod beside the first, which makes
it overconstrained (Grübler mobility 2 − n).

``open_chain(n)`` is a serial chain of n binary links with one motion driver: its
mobility is n, so it is unsolvable and its links do not decompose into groups.
"""

from __future__ import annotations

import math

FRAME, CRANK, COUPLER, ROCKER = 220.0, 60.0, 250.0, 150.0  # mm, as the Watt six-bar's
PITCH = 200.0  # mm between the pivots of successive rockers
RADII = (ROCKER, 120.0)  # radii of a rocker's two points, alternating along the chain
EXTRA = 90.0  # radius of the points of the redundant rods
UNITS = "{length: mm, angle: deg, speed: rpm, mass: kg, force: N, torque: N*m, inertia: kg*m^2}"


def _first_rocker_angle() -> float:
    """The four-bar's rocker angle at crank angle 0 (upper assembly), rad."""
    d = FRAME - CRANK  # from A = (CRANK, 0) to the rocker's pivot (FRAME, 0)
    a = (COUPLER**2 - ROCKER**2 + d**2) / (2 * d)
    h = math.sqrt(COUPLER**2 - a**2)
    return math.atan2(h, CRANK + a - FRAME)


def _f(x: float) -> str:
    return f"{x:.12g}"


def _link(name: str, points: dict[str, float], com: float, mass: float, inertia: float) -> str:
    pts = ", ".join(f"{p}: [{_f(x)}, 0]" for p, x in points.items())
    return (
        f"  {name}:\n    points: {{{pts}}}\n    com: [{_f(com)}, 0]\n"
        f"    mass: {mass}\n    inertia: {inertia}"
    )


def _revolute(name: str, a: str, b: str) -> str:
    return f"  {name}: {{type: revolute, links: [{a}, {b}]}}"


def dyad_chain(n: int, positions: int = 360, redundant: bool = False) -> str:
    """YAML of the four-bar + RRR-dyad chain with ``n`` ≥ 1 dyads (2n + 1 moving links)."""
    phi = _first_rocker_angle()
    c, s = math.cos(phi), math.sin(phi)
    ground = {"O0": (0.0, 0.0)}
    links = [
        _link("crank", {"O0": 0, "A": CRANK}, 15, 1.2, 0.0016),
        _link("rod1", {"A": 0, "B1": COUPLER}, COUPLER / 2, 2.0, 0.0105),
    ]
    joints = [_revolute("O0", "ground", "crank"), _revolute("A", "crank", "rod1")]
    sketch = {"A": (CRANK, 0.0)}
    loads = []
    for k in range(1, n + 1):
        x0 = FRAME + (k - 1) * PITCH
        r_in, r_out = RADII[(k - 1) % 2], RADII[k % 2]
        ground[f"O{k}"] = (x0, 0.0)
        points = {f"O{k}": 0, f"B{k}": r_in}
        if k < n:
            points[f"C{k}"] = r_out
        if redundant and k < n:
            points[f"E{k}"] = EXTRA
        if redundant and k > 1:
            points[f"F{k}"] = EXTRA
        links.append(_link(f"rocker{k}", points, 60, 1.5, 0.004))
        joints += [
            _revolute(f"O{k}", "ground", f"rocker{k}"),
            _revolute(f"B{k}", f"rod{k}", f"rocker{k}"),
        ]
        sketch[f"B{k}"] = (x0 + r_in * c, r_in * s)
        loads.append(f"  t{k}: {{type: torque, link: rocker{k}, value: {-1.0 if k % 2 else 0.5}}}")
        if k < n:
            links.append(
                _link(f"rod{k + 1}", {f"C{k}": 0, f"B{k + 1}": PITCH}, PITCH / 2, 1.0, 0.004)
            )
            joints.append(_revolute(f"C{k}", f"rocker{k}", f"rod{k + 1}"))
            sketch[f"C{k}"] = (x0 + r_out * c, r_out * s)
        if redundant and k > 1:
            links.append(
                _link(f"extra{k}", {f"E{k - 1}": 0, f"F{k}": PITCH}, PITCH / 2, 1.0, 0.004)
            )
            joints += [
                _revolute(f"E{k - 1}", f"rocker{k - 1}", f"extra{k}"),
                _revolute(f"F{k}", f"extra{k}", f"rocker{k}"),
            ]
    pivots = ", ".join(f"{p}: [{_f(x)}, {_f(y)}]" for p, (x, y) in ground.items())
    text = [
        f"name: dyad chain {n}",
        f"units: {UNITS}",
        "gravity: [0, -9.81]",
        "links:",
        f"  ground:\n    points: {{{pivots}}}",
        *links,
        "joints:",
        *joints,
        "drivers:\n  motor: {joint: O0, motion: {speed: 120}}",
        "loads:",
        *loads,
        "sketch:",
        *(f"  {p}: [{_f(x)}, {_f(y)}]" for p, (x, y) in sketch.items()),
        f"analysis: {{start: 0, sweep: 360, positions: {positions}}}",
    ]
    return "\n".join(text) + "\n"


def open_chain(n: int) -> str:
    """YAML of a serial chain of ``n`` binary links driven at its first joint only."""
    links = [_link(f"l{k}", {f"j{k}": 0, f"j{k + 1}": 100}, 50, 1.0, 0.001) for k in range(n)]
    joints = [_revolute("j0", "ground", "l0")]
    joints += [_revolute(f"j{k}", f"l{k - 1}", f"l{k}") for k in range(1, n)]
    text = [
        f"name: open chain {n}",
        f"units: {UNITS}",
        "links:",
        "  ground:\n    points: {j0: [0, 0]}",
        *links,
        "joints:",
        *joints,
        "drivers:\n  motor: {joint: j0, motion: {speed: 60}}",
    ]
    return "\n".join(text) + "\n"


def fan(n: int) -> str:
    """YAML of a hub link held by ``n`` two-link spokes pinned to the ground, the first
    driven: mobility 3, so after the driven link nothing decomposes, and the hub has
    as many connected sets of links around it as the binomial coefficients of n."""
    ground = ", ".join(f"G{k}: [{100 * k}, 0]" for k in range(n))
    hub = ", ".join(f"H{k}: [{100 * k}, 0]" for k in range(n))
    links = [f"  hub:\n    points: {{{hub}}}\n    mass: 1"]
    joints = []
    for k in range(n):
        links.append(_link(f"a{k}", {f"G{k}": 0, f"M{k}": 100}, 50, 1.0, 0.001))
        links.append(_link(f"b{k}", {f"M{k}": 0, f"H{k}": 100}, 50, 1.0, 0.001))
        joints += [
            _revolute(f"G{k}", "ground", f"a{k}"),
            _revolute(f"M{k}", f"a{k}", f"b{k}"),
            _revolute(f"H{k}", f"b{k}", "hub"),
        ]
    text = [
        f"name: fan {n}",
        f"units: {UNITS}",
        "links:",
        f"  ground:\n    points: {{{ground}}}",
        *links,
        "joints:",
        *joints,
        "drivers:\n  motor: {joint: G0, motion: {speed: 60}}",
    ]
    return "\n".join(text) + "\n"
