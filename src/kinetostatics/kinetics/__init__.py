"""Layer 5, kinetics: applied and inertia loads (:mod:`.forces`), when a load acts
(:mod:`.conditions`), joint reactions and the effort (:mod:`.reactions`), friction
(:mod:`.friction`) and the Newton–Euler solution at every row (:mod:`.inverse`)."""
