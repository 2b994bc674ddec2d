"""The `uplift` command: a typer app assembled from the command modules in this package.

The commands are split by group (analyze/modes, record, sweep/spectra) because one
module holding all of them would pass 400 lines; nothing but CLI code lives here.
"""
