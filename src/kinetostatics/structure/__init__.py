"""Layer 3, structure: the joint graph, loops and Assur groups (:mod:`.graph`), the drivers'
constraints (:mod:`.drivers`) and the index layout built once per model (:mod:`.system`)."""
