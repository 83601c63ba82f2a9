"""The REST API's request and response models, one module per resource (calibrations, recordings, sessions,
links, health); the calibrations' response models by method family, over the shared bases in ``common``.

The calibration request models live in :mod:`app.calibration_requests` (the CLI builds them too); the
responses describe every field each method returns, so that ``/openapi.json`` documents them.
"""
