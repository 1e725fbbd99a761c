"""An independent oracle: the core's expected behaviour from the spec and the paper.

It shares nothing with the generator: its own unit conversions (`units`), its own
reading of the spec's quantities from the YAML (`quantities`, which verify compares
with the loader's first), switching table (`switching`), equations (`paper`, `rule`)
and contract (`model`). It imports only the validated spec (codegen.spec_model /
codegen.spec_loader); an import contract in `make lint` keeps it that way.
"""
