"""The Frama-C proof of a generated core: its harness and partitioning, from the design."""
