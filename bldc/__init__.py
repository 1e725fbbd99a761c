"""The `bldc-codegen` command line: the application layer over the generator
(`codegen`), the checks (`verify`, `oracle`) and the simulation (`sim`).

It lives outside `codegen` so the generator imports nothing of what checks it (the
import contract in pyproject.toml); `python -m codegen` is an alias.
"""
