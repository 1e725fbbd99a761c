"""The subcommands of `bldc-codegen`, registered with bldc.cli.register in the order
`--help` lists them. A new command is a module here with its functions and one
`register(Command(...))`, plus its import below (in the place it should be listed)."""

# isort: skip_file
from bldc.commands import spec  # init, derive, audit, generate
from bldc.commands import checks  # firmware, verify, unity, simulate, bench, all

__all__ = ["checks", "spec"]
