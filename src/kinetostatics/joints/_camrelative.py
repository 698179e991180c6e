r"""The relative motion of a cam pair's links (``cam.py``'s ``relative_motion``): the
textbook's terms of a vector equation at the contact, by the equivalent lower pairs of a
higher pair (高副低代).

* **Knife edge and roller**: the follower's point F (the knife's tip, the roller's centre)
  moves, relative to the cam, along the pitch curve (the path of F in the cam's frame).
  With T its unit tangent and n its outward normal turned into the frame, ρ the pitch
  curve's radius of curvature at the contact (> 0 convex: its centre inside), v_r the
  speed along T and ω_i the cam's angular velocity:

      v_F(j) = v_F(i) + v_r T
      a_F(j) = a_F(i) + (v_r²/ρ)(−n) + a^t_r T + 2 ω_i × v_r T,

  the normal term of the relative path, its tangential term (an unknown of the group) and
  the Coriolis term of the turning cam.
* **Flat face**: the cam profile's centre of curvature K at the contact (a point of the
  cam, at ρ inside the contact along the normal) keeps its distance ρ from the face, so
  relative to the follower it moves parallel to the face: the follower's point at K
  relative to the cam's K moves along the face (the speed v_r, unknown), with the
  tangential acceleration a^r_r and the Coriolis term 2 ω_j × v_r of the turning face
  (of the follower, link j: the relative path is straight in the follower's frame).

The speeds and the tangential accelerations are the links' own relative motion along T
(the unknowns a graphical solution reads off its polygon); the normal and Coriolis terms
are the closed forms above, so a vector equation closes only where the links' velocities
and accelerations keep the contact (``methods/vectors.py`` checks the closure).
"""

from __future__ import annotations

from ..base.geometry import dot, perp, turn
from .relative import RelativeMotion, RelativeTerm

__all__ = ["cam_motion"]


def _at(q, v, a, point):
    """(velocity, acceleration) of the point of the link at ``point`` (global)."""
    r = point - q[:2]
    w = float(v[2])
    return v[:2] + w * perp(r), a[:2] + float(a[2]) * perp(r) - w * w * r


def cam_motion(cam, qi, qj, vi, vj, ai, aj, labels) -> RelativeMotion:
    """The cam pair's terms (module docstring) at one pose of its links."""
    li, lj = labels
    s = cam.synthesis
    theta, X, n, z = cam._contact(qi, qj)  # the cam's frame, from its centre
    centre = qi[:2] + turn(qi, cam.o)
    normal = turn(qi, n)
    T = perp(normal)
    if s.flat:
        rho = float(s.curvature(theta))
        point, name = centre + turn(qi, X - rho * n), "K"
    else:
        rho = float(s.curvature(theta)) + s.radius  # the pitch curve's
        point, name = centre + turn(qi, z), cam.names[1]
    (vpi, api), (vpj, apj) = _at(qi, vi, ai, point), _at(qj, vj, aj, point)
    speed = float(dot(T, vpj - vpi))
    tangential = float(dot(T, apj - api))
    rel = f"{name}{lj}{name}{li}"
    curve = "the face" if s.flat else "the pitch curve" if s.radius else "the profile"
    along = f"∥ the tangent of {curve}"
    velocity = (RelativeTerm(f"v_{rel}", speed * T, along),)
    if s.flat:  # K slides along the face of the turning follower
        acceleration = (
            RelativeTerm(f"a^r_{rel}", tangential * T, along),
            RelativeTerm(
                f"a^k_{rel}",
                2.0 * float(vj[2]) * speed * perp(T),
                "⊥ the face",
                f"2·ω{lj}·v_{rel}",
                rate=False,
            ),
        )
        return RelativeMotion(point, name, True, velocity, acceleration)
    acceleration = (
        RelativeTerm(
            f"a^n_{rel}",
            -(speed * speed / rho) * normal,
            f"{name}→ its centre of curvature (ρ = {abs(rho) * 1e3:.4g} mm)",
            f"v_{rel}²/ρ",
            rate=False,
        ),
        RelativeTerm(f"a^t_{rel}", tangential * T, along),
        RelativeTerm(
            f"a^k_{rel}",
            2.0 * float(vi[2]) * speed * perp(T),
            f"⊥ the tangent of {curve}",
            f"2·ω{li}·v_{rel}",
            rate=False,
        ),
    )
    return RelativeMotion(point, name, True, velocity, acceleration)
