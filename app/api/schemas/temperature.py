"""The response model of the temperature calibration: each sensor's offsets as a polynomial of its
temperature, with the binned readings and the fitted curve."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from app.api.schemas.common import CalibrationCommon, Out, Vec3Out


class SensorTemperatureModel(Out):
    unit: Literal["m/s^2", "rad/s"] = Field(description="The offsets' unit (PX4's and ArduPilot's).")
    t_ref_c: float = Field(description="T_ref: the middle of the recorded range (PX4's process_sensor_caldata.py).")
    t_min_c: float = Field(description="The coldest temperature recorded; the firmware clamps below it.")
    t_max_c: float = Field(description="The warmest.")
    relative: bool = Field(
        description="True for the accelerometer: X0 = 0, the drift relative to its reading at "
        "T_ref (gravity's projection is unknown without poses)."
    )
    order: list[int] = Field(description="Per axis, the order (1–3) chosen on bands of temperature left out.")
    coefficients: list[list[float]] = Field(
        description="3×4: per axis X0…X3 of o(T) = Σ X_k dT^k, dT = clamp(T, t_min_c, t_max_c) − t_ref_c; subtracted."
    )


class TemperatureModel(Out):
    type: Literal["temperature"]
    acc: SensorTemperatureModel | None = None
    gyr: SensorTemperatureModel | None = None


class SensorTemperatureUncertainty(Out):
    coefficients: list[list[float]] = Field(description="95 % half-widths of the coefficients (0 where not fitted).")
    dof: list[float] = Field(description="Per axis, the effective residual degrees of freedom of the Student-t.")
    autocorrelation: list[float] = Field(
        description="Per axis, the lag-1 autocorrelation of the bins' residuals "
        "the covariance was inflated by (0 when negative)."
    )
    covariance: list[list[list[float]]] = Field(description="Per axis, the 4×4 covariance of X0…X3.")
    random_walk: list[float] = Field(
        description="Per axis, the bias's random walk in time estimated beside the bins' "
        "scatter (REML), in the unit per √s: 0 when none is seen."
    )


class TemperatureUncertainty(Out):
    confidence: float
    acc: SensorTemperatureUncertainty | None = None
    gyr: SensorTemperatureUncertainty | None = None


class SensorTemperatureMetrics(Out):
    unit: Literal["mg", "deg/s"] = Field(description="The unit of the figures below (mg of 9.80665 m/s², °/s).")
    span_c: float
    drift_raw: Vec3Out = Field(description="Peak-to-peak of the bins' offsets over the range, raw, per axis.")
    drift_after: Vec3Out = Field(description="The same after the fit's correction (in-sample).")
    drift_cv: Vec3Out = Field(description="The same, each bin corrected by the fit made without its band.")
    cv_error: Vec3Out = Field(description="RMS error on bands left out, per axis, of the chosen order.")
    cv_error_raw: Vec3Out = Field(description="The same with no correction (a constant offset).")
    cv_error_by_order: list[Vec3Out] = Field(description="Per axis, orders 1, 2, 3.")
    drift_raw_max: float
    drift_cv_max: float
    n_samples: int
    n_bins: int
    samples_per_band: list[int]
    bins_per_band: list[int]


class TemperatureMetrics(Out):
    acc: SensorTemperatureMetrics | None = None
    gyr: SensorTemperatureMetrics | None = None


class TemperatureBins(Out):
    t_c: list[float] = Field(description="Mean temperature of each bin.")
    offset: list[Vec3Out] = Field(description="Mean offset of each bin (the accelerometer's relative to T_ref).")
    count: list[int]


class TemperatureCurve(Out):
    t_c: list[float]
    offset: list[Vec3Out] = Field(description="The fitted offset at each temperature.")
    half_width: list[Vec3Out] = Field(description="Its 95 % half-width.")


class TemperatureOut(CalibrationCommon):
    method: Literal["temperature"]
    gravity: float | None = Field(  # type: ignore[assignment]  # pydantic: this result has no gravity
        None, description="Not used by a temperature calibration."
    )
    model: TemperatureModel
    uncertainty: TemperatureUncertainty
    metrics: TemperatureMetrics
    bins: dict[str, TemperatureBins] = Field(description="Sensor → the binned readings the fit saw.")
    curve: dict[str, TemperatureCurve] = Field(description="Sensor → the fit and its band over the range.")
    sensor_ids: dict[str, int] | None = Field(
        None,
        description="Sensor → the firmware's device id of the sensor a flight log's IMU was read from (PX4's "
        "TC_A0_ID, TC_G0_ID in the px4 export); absent for other recordings.",
    )
