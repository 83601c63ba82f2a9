"""One result family: every method's result rebuilds from its versioned plain form by its type,
carries its units, and gives the correction f = M (m − o) that its own apply computes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from app.calibration import CalibrationError, fit_six_position
from app.calibration.cube.calibrate import calibrate_cube
from app.calibration.registry import from_dict, registered_types
from app.calibration.shared.result import SCHEMA_VERSION
from app.calibration.still.nonorthogonal import fit_nonorthogonal
from app.calibration.still.triangular import fit_triangular
from simulations.cube import FIELD_UT, simulate_session
from tests.conftest import seed_table

G = 9.81
SIX = {
    "+x": [G + 0.1, 0.05, -0.02],
    "-x": [-G + 0.12, 0.03, 0.01],
    "+y": [0.02, G - 0.05, 0.1],
    "-y": [0.01, -G - 0.02, 0.08],
    "+z": [0.05, 0.02, G + 0.2],
    "-z": [0.04, 0.01, -G + 0.15],
}


def _cube():
    s = simulate_session(np.random.default_rng(21), sampling_rate_hz=100.0)
    cube = calibrate_cube(
        s.acc, s.gyr, s.mag, sampling_rate_hz=100.0, protocol="cube24", gravity=9.80665, field_ut=FIELD_UT
    )
    return dataclasses.replace(cube, units={"acc": "raw", "gyr": "raw", "mag": "raw"})


RESULTS = {
    "affine": lambda: fit_six_position(list(SIX.values()), list(SIX), gravity=G),
    "nonorthogonal": lambda: fit_nonorthogonal(seed_table(1)[:20], gravity=9.806),
    "triangular": lambda: fit_triangular(seed_table(2)[:20], gravity=9.806),
    "cube": _cube,
}
"""Each method's result by its model type, made by the test that takes it (the cube's simulated session was
fitted at the module's import, which every worker of the suite pays)."""


def test_registry_knows_every_type():
    assert set(registered_types()) == {
        "affine",
        "nonorthogonal",
        "triangular",
        "cube",
        "autocal",
        "noise",
        "magnetometer",
        "temperature",
        "compass_flight",
        "imported",
    }


@pytest.mark.parametrize("model_type", RESULTS)
def test_round_trip_units_and_correction(model_type):
    result = RESULTS[model_type]()
    assert model_type == result.MODEL_TYPE
    body = result.to_dict()
    assert body["schema_version"] == SCHEMA_VERSION and body["model"]["type"] == result.MODEL_TYPE
    assert body["ok"] is result.ok and body["unit"] == result.unit and body["output_unit"] == result.output_unit
    again = from_dict(body)

    def kept(d):
        return {k: v for k, v in d.items() if k != "segments"}  # (the cube's segmentation is not kept)

    assert type(again) is type(result) and kept(again.to_dict()) == kept(body)
    assert type(from_dict(body)) is type(result)
    rng = np.random.default_rng(3)
    for sensor, c in result.corrections().items():
        assert c.sensor == sensor and c.source
        raw = rng.normal(size=(20, 3)) * 5
        expected = result.apply(**{sensor: raw})[sensor] if result.MODEL_TYPE == "cube" else result.apply(raw)
        np.testing.assert_allclose(c.apply(raw), expected, rtol=1e-10, atol=1e-9)


def test_a_subclass_refuses_another_type_and_newer_versions_are_refused():
    six = fit_six_position(list(SIX.values()), list(SIX), gravity=G).to_dict()
    from app.calibration.still.triangular import TriangularCalibration

    with pytest.raises(CalibrationError, match="not a triangular model"):
        TriangularCalibration.from_dict(six)
    with pytest.raises(CalibrationError, match="newer than this trical reads"):
        from_dict({**six, "schema_version": SCHEMA_VERSION + 1})
    with pytest.raises(CalibrationError, match="unknown model type"):
        from_dict({**six, "model": {"type": "quartic"}, "method": "quartic"})
    # Bodies stored before the version field are read as version 1.
    legacy = {k: v for k, v in six.items() if k != "schema_version"}
    assert from_dict(legacy).to_dict() == six
