"""What a person uses a calibration with, the one file that fits it, and how to apply that file.

The result's "Use this calibration" offers the file of the use the person picks (remembered by the
page), with one line on how to apply it; the other formats are listed under it. The keys are the
export formats of app.io (FORMAT_NAMES, NOISE_FORMATS, TEMPERATURE_FORMATS).
"""

from __future__ import annotations

from app.io.exports.compass import FLIGHT_COMPASS_FORMATS
from app.io.exports.exporters import COMPASS_FORMAT_NAMES, FORMAT_NAMES, NOISE_FORMATS, TEMPERATURE_FORMATS

CALIBRATION_USES = (
    {
        "key": "app",
        "name": "a phone app",
        "format": "json",
        "snippet": "javascript",
        "how": "Read correction (M and o) from the JSON in your app and calibrate every reading as "
        "M · (reading − o), as in these lines:",
    },
    {
        "key": "python",
        "name": "my own Python code",
        "format": "json",
        "snippet": "python",
        "how": "Load the JSON with numpy and calibrate every reading as M @ (reading − o), as in these lines:",
    },
    {
        "key": "ardupilot",
        "name": "ArduPilot",
        "format": "ardupilot",
        "how": "In Mission Planner: Config → Full Parameter List → Load from file, then Write Params and reboot the "
        "board.",
    },
    {
        "key": "px4",
        "name": "PX4",
        "format": "px4",
        "how": "In QGroundControl: Analyze Tools → MAVLink Console, paste the param set lines, then run param save "
        "and reboot.",
    },
    {
        "key": "betaflight",
        "name": "Betaflight",
        "format": "betaflight",
        "how": "In Betaflight Configurator's CLI tab, paste the lines: save stores them and reboots the board "
        "(Betaflight takes the accelerometer's offsets only, as the file's header says).",
    },
    {
        "key": "inav",
        "name": "INAV",
        "format": "inav",
        "how": "In INAV Configurator's CLI tab, paste the lines: save stores them and reboots the board.",
    },
    {
        "key": "firmware",
        "name": "my own firmware",
        "format": "c",
        "snippet": "c",
        "how": "Put the header beside your code and these lines at file scope in one of your .c files (C89 or "
        "later); call the function on each reading, f = M (m − o), as their comment shows:",
    },
)
"""A correction of a sensor (every method but noise). ``snippet`` names the lines of
``GET /api/v1/calibrations/{id}/use`` (app/io/use.py) shown under the file."""

COMPASS_USES = tuple(u for u in CALIBRATION_USES if u["format"] in COMPASS_FORMAT_NAMES)
"""A compass's correction: the uses of :data:`CALIBRATION_USES` whose file carries a compass (not Betaflight's or
INAV's, which hold only the accelerometer's)."""

NOISE_USES = (
    {
        "key": "kalibr",
        "name": "Kalibr",
        "format": "kalibr",
        "how": "Pass it to Kalibr's camera–IMU calibration as --imu imu.yaml (set rostopic to your IMU's topic).",
    },
    {
        "key": "openvins",
        "name": "OpenVINS",
        "format": "openvins",
        "how": "Replace imu0's noise values in your OpenVINS configuration's kalibr_imu_chain.yaml with these.",
    },
    {
        "key": "vins",
        "name": "VINS-Fusion",
        "format": "vins",
        "how": "Copy acc_n, gyr_n, acc_w and gyr_w into your VINS-Fusion configuration file.",
    },
    {
        "key": "filter",
        "name": "my own filter",
        "format": "json",
        "how": "Read each sensor's noise density N, random walk K and bias instability B from the JSON into your "
        "filter's noise model.",
    },
)
"""A noise characterisation: figures for a filter, not a correction."""


TEMPERATURE_USES = (
    {
        "key": "px4",
        "name": "PX4",
        "format": "px4",
        "how": "In QGroundControl: Vehicle Setup → Parameters → Tools → Load from file, then reboot. A PX4 log gives "
        "the sensors' device ids in TC_A0_ID and TC_G0_ID; where they are 0, set them to CAL_ACC0_ID and "
        "CAL_GYRO0_ID first.",
    },
    {
        "key": "ardupilot",
        "name": "ArduPilot",
        "format": "ardupilot",
        "how": "In Mission Planner: Config → Full Parameter List → Load from file, Write Params, reboot; ArduPilot "
        "corrects relative to INS_ACC1_CALTEMP and INS_GYR1_CALTEMP, the temperature of its last calibration.",
    },
    {
        "key": "filter",
        "name": "my own firmware",
        "format": "json",
        "how": "Each axis's offset is X0 + X1·dT + X2·dT² + X3·dT³ with dT = T − T_ref (T clamped to the range): "
        "subtract it from the reading at that temperature (the JSON's model).",
    },
)
"""A temperature calibration: the firmwares' thermal compensation parameters, or the polynomials."""


FLIGHT_COMPASS_USES = (
    {
        "key": "ardupilot",
        "name": "ArduPilot",
        "format": "ardupilot",
        "how": "In Mission Planner: Config → Full Parameter List → Load from file, then Write Params and reboot. The "
        "file sets the compass's offsets, soft iron, motor compensation (COMPASS_MOT, COMPASS_MOTCT) and, when "
        "the compass is mounted otherwise than set, its orientation.",
    },
    {
        "key": "px4",
        "name": "PX4",
        "format": "px4",
        "how": "In QGroundControl: Analyze Tools → MAVLink Console, paste the param set lines, then run param save and "
        "reboot. They set CAL_MAGn's offsets, scales, the power compensation (CAL_MAG_COMP_TYP) and, when it "
        "is wrong, the rotation.",
    },
    {
        "key": "filter",
        "name": "my own firmware",
        "format": "json",
        "how": "Correct every reading as h = M (Q m − b − k p) with p the battery current in A (or the throttle, 0–1): "
        "Q, M, b and k are in the JSON's correction.",
    },
)
"""A compass calibrated from a flight: its firmware's parameters (only the firmware the log came from)."""


DEFAULT_USES = {"board": ("firmware", "filter"), "px4": ("px4",), "ardupilot": ("ardupilot",), "phone": ("app",)}
"""The use offered first by where the calibration's readings came from (its ``source``,
app.io.readers.SOURCES), the first of these keys its kind offers: a board's goes into its own firmware (the C
header; a temperature calibration's polynomials), a flight log's into that firmware's parameters, a phone's into
a phone app. The one rule: the page (static/js/use_calibration.js) looks it up here; the person's own choice,
once made, is remembered per source over it. A calibration with no source offers its kind's first use."""


USE_SETS = {
    "calibration": (CALIBRATION_USES, FORMAT_NAMES),
    "compassCalibration": (COMPASS_USES, COMPASS_FORMAT_NAMES),
    "noiseFigures": (NOISE_USES, NOISE_FORMATS),
    "thermalCompensation": (TEMPERATURE_USES, TEMPERATURE_FORMATS),
    "flightCompass": (FLIGHT_COMPASS_USES, FLIGHT_COMPASS_FORMATS),
}
"""Each set of uses a result offers, with its export formats, by the name its result class gives
(:attr:`app.web.result_pages.PageFacts.uses`); the page remembers the person's choice under that name and the
calibration's source (static/js/use_calibration.js)."""


def uses_table() -> dict:
    """The page's table of uses: ``defaults`` (:data:`DEFAULT_USES`) and ``sets``, by the name of each set of
    :data:`USE_SETS`: its ``uses`` (each a key, name, format, how, and for a correction the ``snippet`` shown)
    and its ``formats``, every export as ``[key, name]`` in the order the page lists them (pairs, since the
    template's JSON sorts an object's keys)."""
    return {
        "defaults": {source: list(keys) for source, keys in DEFAULT_USES.items()},
        "sets": {
            name: {"uses": [dict(u) for u in uses], "formats": [list(f) for f in formats.items()]}
            for name, (uses, formats) in USE_SETS.items()
        },
    }
