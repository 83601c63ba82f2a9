"""The workflow's steps by method family: recordings, the still readings, the cube, auto-calibration, noise,
the compass and temperature, one module each (docs/architecture.md). The method table (app/methods.py)
names each method's handler here; :mod:`app.workflows.results` keeps what the families share about a result."""
