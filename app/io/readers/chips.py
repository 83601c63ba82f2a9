"""Sensitivities of common board sensors: what one count (LSB) of their output is worth.

A ``chip`` names a part at one range; it turns that sensor's counts into a physical unit at the
edge, as ``lsb_per_g`` does for the accelerometer. Each figure is the datasheet's nominal
sensitivity (typical value), cited by part and document:

- InvenSense MPU-6000/MPU-6050 Product Specification, rev. 3.4, section 6.2 (accelerometer
  sensitivity scale factor: 16384, 8192, 4096, 2048 LSB/g for AFS_SEL 0–3) and section 6.1
  (gyroscope: 131, 65.5, 32.8, 16.4 LSB/(°/s) for FS_SEL 0–3). The MPU-6500 and MPU-9250 product
  specifications and the TDK ICM-20948 datasheet (DS-000189, tables 1 and 2) give the same four
  scales for each sensor.
- Asahi Kasei AK8963 datasheet (in the MPU-9250): 0.15 µT/LSB at 16-bit output, 0.6 µT/LSB at 14-bit.
- Asahi Kasei AK09916 datasheet (in the ICM-20948): 0.15 µT/LSB.
- QST QMC5883L datasheet, magnetic sensor characteristics (sensitivity): 12000 LSB/G at the ±2 G
  range, 3000 LSB/G at ±8 G.
- Honeywell HMC5883L datasheet, table 9 (gain settings): 1370, 1090 (default), 820, 660, 440, 390,
  330, 230 LSB/gauss for ±0.88, ±1.3, ±1.9, ±2.5, ±4.0, ±4.7, ±5.6, ±8.1 G.
- ST LIS3MDL datasheet (DocID024204), sensor characteristics (magnetic sensitivity GN): 6842, 3421,
  2281, 1711 LSB/gauss at ±4, ±8, ±12, ±16 gauss.
- MEMSIC MMC5983MA datasheet, electrical characteristics: 16384 counts/G at 18-bit output, 4096
  counts/G at 16-bit. Its output is unsigned with the zero field at mid-scale (131072 or 32768
  counts): that constant is part of the offset the compass fit estimates.

1 gauss = 100 µT.

What a part can read once its counts are scaled — its largest offset and bias, its noise density —
is the core's (``app/calibration/shared/plausible.py``, which every result is judged by, and whose datasheet
figures of the common gyroscopes, ``GYR_PARTS``, also decide a gyroscope's unit at the edge:
``gyro_unit.py``); these are only the scales that turn counts into units at the edge.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...calibration.shared.headlines import SENSOR_WORDS
from ..errors import LogFormatError

GAUSS_UT = 100.0


@dataclass(frozen=True)
class Chip:
    """One part at one range: ``scale`` physical units per count, in ``unit``."""

    name: str
    sensor: str
    scale: float
    unit: str
    label: str


def _acc(name: str, lsb_per_g: float, part: str, rng: str) -> Chip:
    return Chip(name, "acc", 1.0 / lsb_per_g, "g", f"{part} accelerometer {rng} ({lsb_per_g:g} LSB/g)")


def _gyr(name: str, lsb_per_dps: float, part: str, rng: str) -> Chip:
    return Chip(name, "gyr", 1.0 / lsb_per_dps, "deg/s", f"{part} gyroscope {rng} ({lsb_per_dps:g} LSB/(°/s))")


def _mag_gauss(name: str, lsb_per_gauss: float, part: str, rng: str) -> Chip:
    return Chip(name, "mag", GAUSS_UT / lsb_per_gauss, "uT", f"{part} {rng} ({lsb_per_gauss:g} LSB/gauss)")


GYR_LSB_PER_DPS = (131.0, 65.5, 32.8, 16.4)
"""The gyroscope sensitivities of the common 16-bit parts (the four ranges of the MPU-6050 family and
the ICM-20948, section 6.1 / table 1; the same on the ICM-42688-P and, to within 5 %, the BMI160 and
LSM6DS3's 8.75–70 mdps/LSB)."""
GYR_RANGE = {131.0: "±250 °/s", 65.5: "±500 °/s", 32.8: "±1000 °/s", 16.4: "±2000 °/s"}

_MPU = "MPU-6050/6500/9250, ICM-20948"
_CHIPS = [
    # MPU-6050 Product Specification rev. 3.4, section 6.2; ICM-20948 DS-000189 table 2.
    _acc("mpu6050-2g", 16384, _MPU, "±2 g"),
    _acc("mpu6050-4g", 8192, _MPU, "±4 g"),
    _acc("mpu6050-8g", 4096, _MPU, "±8 g"),
    _acc("mpu6050-16g", 2048, _MPU, "±16 g"),
    # MPU-6050 Product Specification rev. 3.4, section 6.1; ICM-20948 DS-000189 table 1.
    *(_gyr(f"mpu6050-{rng[1:-4]}dps", lsb, _MPU, rng) for lsb, rng in GYR_RANGE.items()),
    # AK8963 datasheet: 0.15 µT/LSB (16-bit), 0.6 µT/LSB (14-bit).
    Chip("ak8963-16bit", "mag", 0.15, "uT", "AK8963 (MPU-9250) 16-bit (0.15 µT/LSB)"),
    Chip("ak8963-14bit", "mag", 0.6, "uT", "AK8963 (MPU-9250) 14-bit (0.6 µT/LSB)"),
    # AK09916 datasheet: 0.15 µT/LSB.
    Chip("ak09916", "mag", 0.15, "uT", "AK09916 (ICM-20948) (0.15 µT/LSB)"),
    # QMC5883L datasheet, magnetic sensor characteristics.
    _mag_gauss("qmc5883l-2g", 12000, "QMC5883L", "±2 G"),
    _mag_gauss("qmc5883l-8g", 3000, "QMC5883L", "±8 G"),
    # HMC5883L datasheet, table 9.
    *(
        _mag_gauss(f"hmc5883l-{lsb}", lsb, "HMC5883L", f"±{fs} G")
        for lsb, fs in (
            (1370, "0.88"),
            (1090, "1.3"),
            (820, "1.9"),
            (660, "2.5"),
            (440, "4.0"),
            (390, "4.7"),
            (330, "5.6"),
            (230, "8.1"),
        )
    ),
    # LIS3MDL datasheet (DocID024204), sensor characteristics, GN.
    *(
        _mag_gauss(f"lis3mdl-{fs}g", lsb, "LIS3MDL", f"±{fs} gauss")
        for lsb, fs in ((6842, 4), (3421, 8), (2281, 12), (1711, 16))
    ),
    # MMC5983MA datasheet, electrical characteristics.
    _mag_gauss("mmc5983ma-18bit", 16384, "MMC5983MA", "18-bit"),
    _mag_gauss("mmc5983ma-16bit", 4096, "MMC5983MA", "16-bit"),
]
CHIPS: dict[str, Chip] = {c.name: c for c in _CHIPS}
"""Every known part and range by its name (``mpu6050-4g``, ``ak8963-16bit``, ``hmc5883l-1090`` …)."""

ACC_LSB_PER_G = (16384.0, 8192.0, 4096.0, 2048.0, 1000.0)
"""The accelerometer sensitivities of the common 16-bit parts (MPU-6050 family, ICM-20948, and the
same four on LSM6DS and BMI160 to within their datasheet tolerance), and milli-g (1000 per g: the
Bosch BNO055 with UNIT_SEL bit 0 set, BST-BNO055-DS000 section 3.6.1, and the usual ADXL345 and
LIS3DH libraries): counts whose resting magnitude sits near one of them are read as g with it."""
ACC_RANGE = {16384.0: "±2 g", 8192.0: "±4 g", 4096.0: "±8 g", 2048.0: "±16 g", 1000.0: "mg"}


def parse_chips(chip: str | list[str] | None) -> dict[str, Chip]:
    """The chips of a ``chip`` field — one name, or several separated by commas, at most one per
    sensor — by sensor.

    Raises
    ------
    LogFormatError
        A name trical does not know (the message lists them), or two chips for one sensor.
    """
    if not chip:
        return {}
    names = [n.strip().lower() for n in (chip.split(",") if isinstance(chip, str) else chip) if n.strip()]
    out: dict[str, Chip] = {}
    for name in names:
        if name not in CHIPS:
            raise LogFormatError(
                f"chip {name!r} is not one trical knows: give one of {', '.join(CHIPS)} "
                "(several separated by commas, one per sensor), or lsb_per_g for another "
                "accelerometer"
            )
        c = CHIPS[name]
        if c.sensor in out:
            raise LogFormatError(
                f"chip names two parts for the {SENSOR_WORDS[c.sensor]} ({out[c.sensor].name}, "
                f"{name}): give one per sensor"
            )
        out[c.sensor] = c
    return out
