"""Layer 8, outputs: what people read — the summary (:mod:`.summary`), the report
(:mod:`.report`), the pictures (:mod:`.plotting`) — and the public loader
(:mod:`.loading`: read a file, then expand its clearances, which needs the layers below)."""
