"""Spikes in still recordings (app/calibration/noise/spikes.py): found on real still boards and phones not once, and on
a seeded MPU-6050 with torn reads every one, the noise density back to the clean recording's."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.noise.characterise import characterise_noise
from app.calibration.noise.spikes import remove_spikes, spike_mask
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from simulations.noise import simulate_still
from tests.conftest import DATA

CORPUS = DATA / "real" / "corpus"
STILL = [  # real recordings at rest: (file, read options)
    (
        CORPUS / "bno055_pi_still_serial_capture" / "imu_raw.csv",
        ReadOptions(
            columns="acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z,mag_x,mag_y,mag_z,-", sampling_rate_hz=50, lsb_per_g=1000
        ),
    ),
    (CORPUS / "hmc5883l_esp32_still_counts" / "mag_data.csv", ReadOptions()),
    (CORPUS / "mpu6050_still_gyro_counts_named_gyro" / "gyro_static.csv", ReadOptions(sampling_rate_hz=100)),
    (CORPUS / "tagged_lines_gyro_still" / "gyro.txt", ReadOptions()),
    (
        DATA / "real" / "mpu6050_session2_still_30s.csv",
        ReadOptions(columns="acc_x,acc_y,acc_z", units={"acc": "raw"}, sampling_rate_hz=100),
    ),
]


@pytest.mark.parametrize("path, options", STILL, ids=[p.parent.name + "/" + p.name for p, _ in STILL])
def test_no_spike_is_found_in_a_real_still_recording(path, options):
    log = read_log(path, options, name=path.name)
    for sensor in log.channels:
        _, spikes = remove_spikes(np.asarray(getattr(log, sensor)))
        assert not spikes.any(), (sensor, spikes.sum(axis=0))


def test_torn_reads_of_a_seeded_mpu6050_are_all_found_and_the_density_comes_back():
    """A still MPU-6050 gyroscope in counts (white noise 1.2 counts per sample at 100 Hz, bias drift) whose y
    axis holds 45 torn reads, ±256 counts for one sample: all 45 found, nothing else, and the white-noise
    density within 2 % of the clean recording's (with them left in, it reads several times too high)."""
    rng = np.random.default_rng(45)
    fs = 100.0
    clean = np.round(
        simulate_still(rng, n_samples=30_000, sampling_rate_hz=fs, N=0.12, B=0.5, K=0.02, bias=[-427, 147, -81])
    )
    torn = clean.copy()
    at = rng.choice(np.arange(10, len(torn) - 10), size=45, replace=False)
    torn[at, 1] += rng.choice([-256.0, 256.0], size=45)
    assert np.array_equal(np.flatnonzero(spike_mask(torn[:, 1])), np.sort(at))
    cleaned, spikes = remove_spikes(torn)
    assert spikes.sum(axis=0).tolist() == [0, 45, 0]
    density = lambda x: np.asarray(characterise_noise(x, fs, unit="raw", sensor="gyr")["model"]["noise_density"])  # noqa: E731
    before, with_spikes, after = density(clean), density(torn), density(cleaned)
    assert with_spikes[1] > 2 * before[1]
    np.testing.assert_allclose(after, before, rtol=0.02)


def test_a_knock_a_step_and_a_turn_are_not_spikes():
    """Things that leave and do not come straight back, or take more than two samples, stay: a step of the level
    (the device set down in another orientation), a three-sample knock, a steady turn."""
    rng = np.random.default_rng(7)
    x = rng.normal(scale=1.0, size=2000)
    x[1000:] += 80.0  # a step
    x[500:503] += 60.0  # a knock of three samples
    x[1500:1700] += np.linspace(0, 400, 200)  # a ramp
    assert not spike_mask(x).any()
