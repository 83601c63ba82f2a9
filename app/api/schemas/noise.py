"""The response model of the noise characterisation: each sensor's Allan deviation and the noise terms read
from it."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from app.api.schemas.common import CalibrationCommon, Out, Vec3Out

Figures3 = list[float | None]


class SensorNoiseModel(Out):
    unit: str = Field(description="The sensor's unit (gyroscope rad/s, accelerometer m/s^2, magnetometer uT).")
    bias: Vec3Out = Field(description="Mean of the still part, per axis.")
    noise_density: Figures3 = Field(
        description="N, white noise: the −½ line at τ = 1 s (IEEE Std 952, Annex C); null where not seen."
    )
    random_walk: Figures3 = Field(description="K, the +½ line at τ = 3 s; null where the recording is too short.")
    bias_instability: Figures3 = Field(description="B, the flat floor / 0.664; null where not seen.")
    noise_density_unit: str = Field(description="e.g. rad/s/√Hz (Kalibr's gyroscope_noise_density).")
    random_walk_unit: str = Field(description="e.g. rad/s²/√Hz (Kalibr's gyroscope_random_walk).")
    bias_instability_unit: str


class NoiseModel(Out):
    type: Literal["noise"]
    acc: SensorNoiseModel | None = None
    gyr: SensorNoiseModel | None = None
    mag: SensorNoiseModel | None = None


Intervals3 = list[list[float] | None]


class SensorNoiseUncertainty(Out):
    noise_density: Intervals3 = Field(
        description="95 % interval [lo, hi] per axis (χ², equivalent degrees of freedom)."
    )
    random_walk: Intervals3
    bias_instability: Intervals3
    bias: Intervals3


class NoiseUncertainty(Out):
    confidence: float
    acc: SensorNoiseUncertainty | None = None
    gyr: SensorNoiseUncertainty | None = None
    mag: SensorNoiseUncertainty | None = None


class AllanTable(Out):
    tau_s: list[float] = Field(
        description="τ = m / fs, at least 10 per decade, up to the longest the recording supports."
    )
    value: list[Vec3Out] = Field(description="Overlapping Allan deviation (n_τ × 3), in the sensor's unit.")
    lo: list[Vec3Out] = Field(description="Lower end of each point's 95 % interval.")
    hi: list[Vec3Out] = Field(description="Upper end.")
    edf: list[Vec3Out] = Field(description="Equivalent degrees of freedom of each point (NIST SP 1065, Table 5).")
    n_terms: list[int] = Field(description="Second differences summed at each τ.")


class SensorNoiseMetrics(Out):
    tau_noise_density_s: Figures3 = Field(description="The τ each axis's N was read at.")
    tau_bias_instability_s: Figures3
    tau_random_walk_s: Figures3
    adev_min: Vec3Out = Field(description="The curve's minimum (B ≥ it / 0.664 holds the other terms too).")
    tau_adev_min_s: Vec3Out
    bias_standard_error: Vec3Out = Field(
        description="Standard error of the bias: the fitted Allan deviation at the duration."
    )
    hump_tau_s: Figures3 = Field(
        [None, None, None],
        description="Where a periodic disturbance's hump stands above the white-noise line: the τ of its peak "
        "(None: no hump). The disturbance is fitted as a term of its own.",
    )
    hump_hz: Figures3 = Field([None, None, None], description="The disturbance's fitted frequency (Hz).")
    record_for_s: dict[str, float] = Field(
        {},
        description="Each term no axis's curve showed, where a longer still recording would show it: how long "
        "that recording would be (s).",
    )


class NoiseMetrics(Out):
    acc: SensorNoiseMetrics | None = None
    gyr: SensorNoiseMetrics | None = None
    mag: SensorNoiseMetrics | None = None


class StillPart(Out):
    start: int = Field(description="First sample used.")
    end: int = Field(description="The sample after the last one used.")
    n_samples: int
    fraction: float = Field(description="Of the recording.")
    detected_from: str = Field(
        description=(
            'The sensors whose stillness was tested, joined by ", " (every sensor the recording holds: '
            "still on all of them)."
        )
    )


class NoiseOut(CalibrationCommon):
    method: Literal["noise"]
    gravity: float | None = Field(  # type: ignore[assignment]  # pydantic: this result has no gravity
        None, description="Not used by a noise characterisation."
    )
    model: NoiseModel
    uncertainty: NoiseUncertainty
    metrics: NoiseMetrics
    adev: dict[str, AllanTable] = Field(description="Sensor → its Allan deviation table.")
    sampling_rate_hz: float
    duration_s: float = Field(description="Of the still part used.")
    still: StillPart | None
    units_stated: bool = Field(
        False,
        description="The recording's format states its units (a flight controller's log): an implausible figure "
        "is not taken for a misread unit. Absent when false.",
    )
