"""Layer 4, kinematics: the schedule in time (:mod:`.schedule`), positions by Newton with
branch tracking (:mod:`.positions`, closed forms in :mod:`.dyads`), velocities and
accelerations (:mod:`.differences` for the finite-difference check), point states
(:mod:`.state`) and roots in time (:mod:`.events`)."""
