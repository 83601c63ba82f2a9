import csv
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture(scope="session")
def table7():
    """Särkkä et al. Table VII as {sensor: {column: array}} (rows x, y, z)."""
    with open(DATA / "003_table7.csv") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    out = {}
    for sensor in ("gyr", "acc", "mag"):
        rs = [r for r in rows if r["sensor"] == sensor]
        out[sensor] = {k: np.array([float(r[k]) for r in rs]) for k in rs[0] if k not in ("sensor", "row")}
    return out
