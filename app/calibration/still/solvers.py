"""The solvers of Farago, Maczak and Gingl's triangular model (IEEE Access), by name: the one list the core, the
request models and the CLI offer (app.calibration.still.triangular documents each)."""

from typing import Literal, get_args

Solver = Literal["lm", "gradient", "fixed16", "fixed32"]
SOLVERS: tuple[str, ...] = get_args(Solver)
"""``lm``: Levenberg–Marquardt on the distances to the ellipsoid; ``gradient``: the paper's finite-difference
descent in float; ``fixed16`` / ``fixed32``: the same descent in 16- and 32-bit fixed point."""
