"""Layer 4, kinematics: the schedule in time (:mod:`.schedule`), positions by Newton with
branch tracking (:mod:`.positions`: Newton per group in :mod:`.newton`, the start pose from
the sketch in :mod:`.start`, continuation along the path in :mod:`.continuation`, closed
forms in :mod:`.dyads` and along the path in :mod:`.closed_path`), velocities and
accelerations (:mod:`.derivatives`; :mod:`.differences` for the finite-difference check),
point states (:mod:`.state`), roots in time (:mod:`.events`) and the record the stage
hands on, :class:`~.motion.Motion` (:mod:`.motion`)."""
