"""Which compass of a log is lying: the compasses of one flight side by side, one action each, and the firmware's
consistency check between them.

Each compass is calibrated from the same flight (:func:`.flight.fit_flight_compass`); its row holds the heading
error before and after on flight segments left out, the orientation found, and the current's (or throttle's) pull
on it: ``k`` of a fit with the offsets and the motor term, in µT per A, and at the flight's top power (the 95th
percentile) in µT and in degrees of heading, ``atan(|k_xy| p₉₅ / H)`` with H the Earth's horizontal field (the
most a horizontal disturbance of that size turns a level compass). The firmware's consistency check compares each
compass's corrected field with the primary's as ArduPilot's ``Compass::consistent`` does (AP_Compass.cpp:
the angle between the fields over 90°, between their horizontal parts over 60°, or their horizontal parts more
than 200 mG apart makes the compasses "inconsistent", a pre-arm failure), taking the median over the flight.
"""

from __future__ import annotations

import numpy as np

XYZ_ANGLE_MAX_DEG = 90.0
"""ArduPilot's AP_COMPASS_MAX_XYZ_ANG_DIFF: the largest angle between two compasses' fields."""

XY_ANGLE_MAX_DEG = 60.0
"""ArduPilot's AP_COMPASS_MAX_XY_ANG_DIFF: the largest angle between their horizontal parts."""

XY_LENGTH_MAX_UT = 20.0
"""ArduPilot's AP_COMPASS_MAX_XY_LENGTH_DIFF, 200 mG: the largest difference of their horizontal parts."""

PULL_MAX_DEG = 5.0
"""A power's pull that turns the heading by more than 5° at the flight's top power asks for an action: its
compensation where the flight determines it, else the compass moved from the power wires (trical's choice: the
heading error a fit on a good flight leaves is 1–3°)."""

KEEP_BELOW_DEG = 3.0
"""A compass whose heading error with the firmware's own calibration is under 3° rms is kept as it is."""


def _angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    cos = np.sum(a * b, axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def consistency(primary, other) -> dict:
    """ArduPilot's consistency check between two compasses' corrected fields in the body frame (µT, same times).

    Parameters
    ----------
    primary, other : array_like, shape (N, 3)

    Returns
    -------
    dict
        ``xyz_angle_deg``, ``xy_angle_deg``, ``xy_length_diff_ut`` (medians over the samples) and ``consistent``
        (each within :data:`XYZ_ANGLE_MAX_DEG`, :data:`XY_ANGLE_MAX_DEG`, :data:`XY_LENGTH_MAX_UT`).
    """
    p, o = np.asarray(primary, dtype=float), np.asarray(other, dtype=float)
    xyz = float(np.median(_angle_deg(p, o)))
    xy = float(np.median(_angle_deg(p * [1, 1, 0], o * [1, 1, 0])))
    length = float(np.median(np.linalg.norm(p[:, :2] - o[:, :2], axis=1)))
    return {
        "xyz_angle_deg": xyz,
        "xy_angle_deg": xy,
        "xy_length_diff_ut": length,
        "consistent": bool(xyz <= XYZ_ANGLE_MAX_DEG and xy <= XY_ANGLE_MAX_DEG and length <= XY_LENGTH_MAX_UT),
    }


def pull(k, top_power: float, earth_ned) -> dict:
    """The power's pull on a compass: ``|k|`` per unit of power, and at ``top_power`` in µT and in degrees of
    heading (``atan(|k_xy| p / H)``, H the horizontal field of ``earth_ned``)."""
    k = np.asarray(k, dtype=float)
    horizontal = float(np.hypot(earth_ned[0], earth_ned[1]))
    return {
        "per_unit": float(np.linalg.norm(k)),
        "at_top_ut": float(np.linalg.norm(k) * top_power),
        "at_top_deg": float(np.degrees(np.arctan2(np.linalg.norm(k[:2]) * top_power, horizontal))),
    }


def action(row: dict) -> str:
    """The one thing to do with a compass, from its row (:mod:`app.workflows.flight_compasses` builds it): disable
    one that does not measure; re-orient one mounted otherwise than set; compensate (or move) one the power pulls
    by more than :data:`PULL_MAX_DEG`, where the flight determines the pull; apply a calibration that passed;
    calibrate or stop one inconsistent with the first compass (:func:`consistency`); keep one already good; else
    the remedy of the fit's first reason."""
    if not row["measures"]:
        return f"disable it ({row['switch']} = 0)" if row.get("switch") else "disable it"
    if row.get("orientation_setting"):
        return f"re-orient it ({row['orientation_setting']})"
    power = row.get("pull")
    if power and power.get("determined") and power["at_top_deg"] > PULL_MAX_DEG:
        pulled = f"the {row['power_kind']} pulls it {power['at_top_deg']:.0f}°"
        if row.get("motor_setting"):
            return f"set {row['motor_setting']} from this flight ({pulled})"
        return f"move it away from the power wires ({pulled})"
    if row["ok"]:
        return "apply this calibration"
    if row.get("consistent") is False and row.get("switch"):
        return (
            f"calibrate it or stop its use ({row['switch']} = 0): its field disagrees with the first compass's "
            "beyond the firmware's pre-arm consistency check"
        )
    before = row.get("before_deg")
    if before is not None and before < KEEP_BELOW_DEG:
        return "keep it as it is"
    return _remedy(row.get("reason")) or "fly again with turns through every heading, then calibrate it again"


def _remedy(reason: str | None) -> str | None:
    """The remedy of a fit's reason (its words after the cause: "…): fly turns through every heading (…) so that
    …"), without the why."""
    if not reason:
        return None
    cut = "): " if "): " in reason else ": "
    if cut not in reason:
        return None
    remedy = reason.split(cut, 1)[1]
    return remedy.split(" so that ", 1)[0].rstrip(".,; ")


__all__ = ["action", "consistency", "pull"]
