"""The flywheel design's assumptions as sentences (the design's record holds them in
English; the report's chapter translates the templates, then fills in the same numbers).

Text only, so that the report reads it without importing the design (:mod:`.flywheel`).
"""

from __future__ import annotations

__all__ = ["ASSUMPTIONS", "TORQUE_PHRASE", "assumption_texts"]

# The assumptions of a design: sentence templates (the report translates them, then fills
# in the same numbers), the torque phrase by whether friction is counted.
ASSUMPTIONS = (  # what is assumed, not how it is computed (no module or rule named)
    "driving moment constant, equal to the cycle mean of {torque} (M_d = work per cycle / 2π, "
    "the work integrated exactly over one cycle, piece by piece between the load events)",
    "balancing moment at the constant nominal crank speed ω_m = {omega_m:.6g} rad/s "
    "(link inertia torques at that speed included)",
    "ΔW_max exact: ΔW(φ) integrated over one cycle piece by piece between the load events, "
    "where M_b is smooth, its extremes at the load events or where M_d = M_b "
    "({positions} positions only for the pictures)",
    "energy method, first order in δ: ω_m = (ω_max + ω_min)/2 and the speed "
    "variation taken by the flywheel alone (J_F) or by the flywheel plus the "
    "machine's cycle-mean equivalent inertia (J_F − J_e)",
    "flywheel on the crank shaft; on the motor shaft J_F/i² (i: the reduction ratio; gear "
    "inertia neglected)",
)
TORQUE_PHRASE = {
    False: "the frictionless balancing moment",
    True: "the balancing moment with friction (consistent solution)",
}


def assumption_texts(
    friction: bool, omega_m: float, positions: int, translate=lambda text: text
) -> tuple[str, ...]:
    """The assumptions of a design as sentences; ``translate(text)`` turns each template
    (and the torque phrase) into another language before the numbers are filled in."""
    torque = translate(TORQUE_PHRASE[bool(friction)])
    return tuple(
        translate(t).format(torque=torque, omega_m=omega_m, positions=positions)
        for t in ASSUMPTIONS
    )
