"""Every figure of a calibration in words, for the result's Details: a name, its unit and one line saying
what it is. The page shows these, never the stored key; a key not listed here is shown by a name made
from it (app/web/tables.py hands this table to the page)."""

from __future__ import annotations

G = "of g"

METRICS: dict[str, tuple[str, str, str]] = {
    # What to expect on readings the fit did not see.
    "cv_error_mg": ("Error on new orientations", "mg", "mean | |a| − g | of each reading calibrated by the fit made without it"),
    "cv_error_max_mg": ("Largest error on new orientations", "mg", "the worst of those left-out readings"),
    "cv_scheme": ("How readings were left out", "", "leave-one-out: each in turn; 10-fold: a tenth at a time"),
    "cv_note": ("Why no error on new orientations", "", "a fit with no reading to spare cannot be tested on one it did not see"),
    "holdout_count": ("Held-out readings", "readings", "further readings given to check the fit, not used by it"),
    "holdout_error_before_mg": ("Held-out error before", "mg", "mean | |m| − g | of the held-out readings as read"),
    "holdout_error_after_mg": ("Held-out error after", "mg", "the same, calibrated"),
    "holdout_norm_error_max": ("Largest held-out norm error after", G, "max | |a| − g | / g over the held-out readings, calibrated"),
    "holdout_norm_error_max_raw": ("Largest held-out norm error before", G, "the same, as read"),
    "holdout_improvement": ("Held-out improvement", "×", "held-out error before divided by after"),
    # On the readings fitted.
    "count": ("Readings", "readings", "still readings (poses) the fit used"),
    "dof": ("Readings to spare", "per axis", "residual degrees of freedom of the least-squares design (readings "
            "minus parameters, per axis): what the 95 % intervals are estimated from; with 0 there are none"),
    "condition_number": ("Condition number", "", "how far the poses are from determining the parameters well: near 1 is best, "
                         "large means poses too alike"),
    "error_before_mg": ("Error before", "mg", "mean | |m| − g | of the fitted readings as read"),
    "error_after_mg": ("Error after", "mg", "the same, calibrated (on the readings fitted)"),
    "norm_error_max": ("Largest norm error after", G, "max | |a| − g | / g over the fitted readings, calibrated"),
    "norm_error_max_raw": ("Largest norm error before", G, "the same, as read"),
    "fit_error_max": ("Largest direction error after", G, "max ‖a − the pose's expected reading‖ / g, calibrated "
                      "(Georgieva et al., ESGI'95, section 3.5)"),
    "fit_error_max_raw": ("Largest direction error before", G, "the same, as read"),
    "fit_improvement": ("Direction error improvement", "×", "largest direction error before divided by after"),
    "norm_improvement": ("Norm error improvement", "×", "largest norm error before divided by after"),
    "improvement": ("Improvement", "×", "error before divided by after (Farago et al., IEEE Access, eq. (21))"),
    "improvement_pct": ("Improvement", "%", "how much smaller the error is after calibration"),
    "rms_residual": ("Residual", "input unit", "root mean square of what the model leaves of the readings"),
    "rms_norm_residual": ("Norm residual", "input unit", "root mean square of | |a| − g | after calibration"),
    "converged": ("Converged", "", "whether the iterative fit reached its tolerance"),
    "iterations": ("Iterations", "", "steps the iterative fit took"),
    "noise_estimate": ("Noise", "input unit", "the readings' noise as the fit estimates it"),
    "solver": ("Solver", "", "the numerical method of the fit"),
    "cost_12": ("Cost", "", "the sum minimised, Farago et al., IEEE Access, eq. (12), at the solution"),
    "cost_17": ("Cost", "", "the sum minimised, Georgieva et al., ESGI'95, eq. (17), at the solution"),
    "h": ("Finite-difference step", "", "the step of the descent solvers' gradient"),
    "distance_to_lm": ("Distance to the least-squares solution", "", "how far the descent solver ended from it"),
    "p_raw": ("Parameters as integers", "", "fixed-point values a microcontroller holds"),
    "q_format": ("Fixed-point format", "", "the Q format of those integers"),
    "saturated": ("Saturated", "", "whether a fixed-point parameter hit its range"),
    "angle_deviation_max_deg": ("Largest angle off square", "°", "how far the sensor's axes are from perpendicular, at most"),
    "rough_s": ("Rough shifts", "input unit", "the offsets of the first, orthogonal fit (ESGI'95 section 2.2, step 2)"),
    "rough_b": ("Rough scales", "", "the scales of that first fit"),
    "sampling_rate_hz_min": ("Slowest capture rate", "Hz", "the lowest sampling rate of the captures"),
    "sampling_rate_hz_max": ("Fastest capture rate", "Hz", "the highest sampling rate of the captures"),
    "correlation_inflation": ("Interval widening for correlated noise", "×", "factor on the intervals because the residuals "
                              "are correlated in time"),
    "count_control": ("Control points", "points", "points held out to test the fit"),
    "fit_error_before_mg": ("Error before", "mg", "on the control points, as read"),
    "fit_error_after_mg": ("Error after", "mg", "on the control points, calibrated"),
    "fit_norm_error_max": ("Largest norm error after", G, "over the points fitted"),
    "fit_condition_number": ("Condition number", "", "of the design of the points fitted"),
    "fit_converged": ("Converged", "", "whether the fit reached its tolerance"),
    "fit_iterations": ("Iterations", "", "steps of the fit"),
    "fit_noise_estimate": ("Noise", "input unit", "the readings' noise as the fit estimates it"),
    "n_samples": ("Samples", "samples", "readings in the recording"),
    "n_still_found": ("Still segments", "segments", "rests found before they were matched to the positions"),
    "n_positions_found": ("Positions found", "positions", "rests matched to the protocol's positions"),
    "n_positions_used": ("Positions used", "positions", "positions the fit used"),
    "n_handling": ("Handling left out", "rests and moves", "pauses, re-placements and moves by hand left out"),
    "positions_from": ("Positions from", "", "detected from the gyroscope, or an annotated list"),
    "rotations_used": ("Turns used", "turns", "turns between positions the gyroscope fit used"),
    "returned_to_start": ("Back at the start", "", "whether the sequence ended where it began"),
    "duration_s": ("Duration", "s", "length of the recording"),
    # The compass.
    "field_ut": ("Field strength F", "µT", "the magnitude the calibrated readings take"),
    "field_source": ("Field strength from", "", "given, the IGRF model at the place and date, or estimated from the readings"),
    "field_model": ("Field model", "", "the geomagnetic model used"),
    "field_date": ("Field date", "", "the day the model was evaluated for"),
    "declination_deg": ("Declination", "°", "the model's angle of north from true north, east positive"),
    "inclination_deg": ("Dip", "°", "the model's field angle below the horizontal"),
    "measured_inclination_deg": ("Measured dip", "°", "the calibrated field's angle below the horizontal, against gravity at rest"),
    "rests": ("Rests", "rests", "accelerometer rests the measured dip uses (none: no dip measured)"),
    "cv_error_ut": ("Error on new directions", "µT", "RMS of |h| − F, each direction calibrated by the fit made without it"),
    "cv_error_max_ut": ("Largest error on new directions", "µT", "RMS of the worst direction"),
    "fit_error_ut": ("Error on the readings fitted", "µT", "RMS of |h| − F"),
    "raw_error_ut": ("Error before", "µT", "RMS of |m| − F of the readings as read"),
    "norm_spread_ut": ("Spread of |h| after", "µT", "5–95 % range of the calibrated magnitude"),
    "norm_spread_raw_ut": ("Spread of |m| before", "µT", "the same, as read"),
    "noise_ut": ("Noise", "µT", "residual standard deviation"),
    "coverage": ("Directions covered", "fraction", "share of the 20 faces of a sphere the readings reach"),
    "missing_directions": ("Directions missing", "", "faces not reached"),
    "thickness": ("Out of one plane", "fraction", "how far the readings leave their best plane: 0 for a turn kept flat"),
    "fit_stage": ("Fit shown", "", "the refined fit, or the closed form kept when the refinement ran away"),
    # Noise (per sensor).
    "adev_min": ("Lowest Allan deviation", "sensor unit", "the floor of the curve"),
    "tau_adev_min_s": ("Averaging time at the floor", "s", "τ where the Allan deviation is lowest"),
    "tau_noise_density_s": ("τ of the noise density", "s", "where N was read"),
    "tau_random_walk_s": ("τ of the random walk", "s", "where K was read"),
    "tau_bias_instability_s": ("τ of the bias instability", "s", "where B was read"),
    "bias_standard_error": ("Bias standard error", "sensor unit", "the Allan deviation at the recording's length"),
}
"""key → (name, unit, one line on what it is). A ``_raw`` twin or a ``holdout_`` figure has its own line."""

SENSOR_WORDS = {"acc": "Accelerometer", "gyr": "Gyroscope", "mag": "Magnetometer"}
