"""The base layer: helpers that know nothing of mechanisms, and the reader of YAML
with file locations (:mod:`.spec`).  Imports nothing of the package above it."""
