"""Small writers of flight controllers' logs with known content, for the readers' tests and the bench.

pyulog reads ULog but does not write it, and pymavlink writes no DataFlash: these follow the formats'
public descriptions.

- ULog (PX4 "ULog File Format"): a 16-byte file header (``ULog`` 0x01 0x12 0x35, a version byte, a
  uint64 timestamp), a flag-bits message ``B`` (8 compatible, 8 incompatible flag bytes, three
  uint64 appended offsets), then messages of ``uint16 size, uint8 type, body``: ``F`` formats
  (``name:type field;…``), ``A`` subscriptions (uint8 multi_id, uint16 msg_id, name) and ``D`` data
  (uint16 msg_id, the fields packed in order).
- DataFlash (ArduPilot's logger, libraries/AP_Logger/LogStructure.h): messages of ``0xA3 0x95 type
  body``; the FMT message (type 128: uint8 type, uint8 length, char[4] name, char[16] format,
  char[64] columns) describes every other one, itself first.

Both writers pack whole columns at once with numpy records, so that a log of 100 MB is written in
seconds (bench/flight_logs.py).
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

ULOG_TYPES = {"uint64_t": "<u8", "int64_t": "<i8", "uint32_t": "<u4", "int32_t": "<i4", "uint16_t": "<u2",
              "int16_t": "<i2", "uint8_t": "u1", "int8_t": "i1", "float": "<f4", "double": "<f8"}


def _ulog_message(kind: str, body: bytes) -> bytes:
    return struct.pack("<HB", len(body), ord(kind)) + body


def ulog_bytes(topics: list[dict], *, start_us: int = 0) -> bytes:
    """A ULog file of ``topics``: each ``{"name", "multi_id", "fields": [(type, name), ...], "data": {name: array}}``,
    the first field ``uint64_t timestamp``; the same name shares one format."""
    out = [b"ULog\x01\x12\x35", bytes([1]), struct.pack("<Q", start_us)]
    out.append(_ulog_message("B", bytes(40)))
    formats = {}
    for t in topics:
        formats.setdefault(t["name"], t["fields"])
    for name, fields in formats.items():
        out.append(_ulog_message("F", (name + ":" + "".join(f"{ty} {n};" for ty, n in fields)).encode()))
    for msg_id, t in enumerate(topics):
        out.append(_ulog_message("A", struct.pack("<BH", t["multi_id"], msg_id) + t["name"].encode()))
    for msg_id, t in enumerate(topics):
        dtype = np.dtype([("size", "<u2"), ("type", "u1"), ("msg_id", "<u2")]
                         + [(n, ULOG_TYPES[ty]) for ty, n in t["fields"]])
        n = len(t["data"][t["fields"][0][1]])
        rows = np.zeros(n, dtype=dtype)
        rows["size"] = dtype.itemsize - 3
        rows["type"] = ord("D")
        rows["msg_id"] = msg_id
        for _, name in t["fields"]:
            rows[name] = t["data"][name]
        out.append(rows.tobytes())
    return b"".join(out)


def write_ulog(path: Path, topics: list[dict], **kw) -> Path:
    Path(path).write_bytes(ulog_bytes(topics, **kw))
    return Path(path)


SENSOR_FIELDS = [("uint64_t", "timestamp"), ("uint64_t", "timestamp_sample"), ("uint32_t", "device_id"),
                 ("float", "x"), ("float", "y"), ("float", "z"), ("float", "temperature"), ("uint32_t", "error_count")]
"""PX4's sensor_accel / sensor_gyro / sensor_mag fields (msg/SensorAccel.msg and the others), without the
clip counters and sample count, which trical does not read."""


def px4_sensor(name: str, multi_id: int, time_us, xyz, temperature=None, device_id: int = 0) -> dict:
    """A ``sensor_accel``/``sensor_gyro``/``sensor_mag`` topic of one instance (xyz in m/s², rad/s or gauss)."""
    time_us = np.asarray(time_us, dtype=np.uint64)
    xyz = np.asarray(xyz, dtype=float)
    temp = np.zeros(len(time_us)) if temperature is None else np.broadcast_to(temperature, (len(time_us),))
    return {"name": name, "multi_id": multi_id, "fields": SENSOR_FIELDS,
            "data": {"timestamp": time_us, "timestamp_sample": time_us, "device_id": np.full(len(time_us), device_id),
                     "x": xyz[:, 0], "y": xyz[:, 1], "z": xyz[:, 2], "temperature": temp,
                     "error_count": np.zeros(len(time_us))}}


# -- DataFlash ---------------------------------------------------------------------------------------

DF_TYPES = {"Q": "<u8", "q": "<i8", "I": "<u4", "i": "<i4", "H": "<u2", "h": "<i2", "B": "u1", "b": "i1",
            "f": "<f4", "d": "<f8", "N": "S16", "n": "S4", "Z": "S64"}
FMT_TYPE = 128


def _df_dtype(fmt: str, columns: list[str]) -> np.dtype:
    return np.dtype([("h1", "u1"), ("h2", "u1"), ("type", "u1")]
                    + [(c, DF_TYPES[f]) for f, c in zip(fmt, columns)])


def dataflash_bytes(messages: list[dict]) -> bytes:
    """A DataFlash log of ``messages``: each ``{"name", "type", "format", "columns": [...], "data": {col: array}}``
    (format characters as ArduPilot's: Q uint64, B uint8, f float, h int16, N char[16] …), written
    after the FMT messages describing them."""
    fmt_columns = ["Type", "Length", "Name", "Format", "Columns"]
    fmt_dtype = _df_dtype("BBnNZ", fmt_columns)
    described = [{"name": "FMT", "type": FMT_TYPE, "format": "BBnNZ", "columns": fmt_columns}] + [
        m for i, m in enumerate(messages) if m["type"] not in {x["type"] for x in messages[:i]}]
    fmts = np.zeros(len(described), dtype=fmt_dtype)
    for i, m in enumerate(described):
        fmts[i] = (0xA3, 0x95, FMT_TYPE, m["type"], _df_dtype(m["format"], m["columns"]).itemsize, m["name"].encode(),
                   m["format"].encode(), ",".join(m["columns"]).encode())
    out = [fmts.tobytes()]
    for m in messages:
        dtype = _df_dtype(m["format"], m["columns"])
        n = len(m["data"][m["columns"][0]])
        rows = np.zeros(n, dtype=dtype)
        rows["h1"], rows["h2"], rows["type"] = 0xA3, 0x95, m["type"]
        for c in m["columns"]:
            rows[c] = m["data"][c]
        out.append(rows.tobytes())
    return b"".join(out)


def write_dataflash(path: Path, messages: list[dict]) -> Path:
    Path(path).write_bytes(dataflash_bytes(messages))
    return Path(path)


def ardupilot_imu(instance: int, time_us, acc, gyr, temperature) -> dict:
    """An ``IMU`` message stream with the ``I`` field (libraries/AP_InertialSensor/LogStructure.h), the fields
    trical reads."""
    acc, gyr = np.asarray(acc, dtype=float), np.asarray(gyr, dtype=float)
    n = len(acc)
    return {"name": "IMU", "type": 140, "format": "QBffffffIIfBBHH",
            "columns": ["TimeUS", "I", "GyrX", "GyrY", "GyrZ", "AccX", "AccY", "AccZ", "EG", "EA", "T", "GH", "AH",
                        "GHz", "AHz"],
            "data": {"TimeUS": np.asarray(time_us, dtype=np.uint64), "I": np.full(n, instance),
                     "GyrX": gyr[:, 0], "GyrY": gyr[:, 1], "GyrZ": gyr[:, 2],
                     "AccX": acc[:, 0], "AccY": acc[:, 1], "AccZ": acc[:, 2], "EG": np.zeros(n), "EA": np.zeros(n),
                     "T": np.broadcast_to(temperature, (n,)), "GH": np.ones(n), "AH": np.ones(n),
                     "GHz": np.full(n, 1000), "AHz": np.full(n, 1000)}}


def ardupilot_batch(name: str, instance: int, time_us, xyz) -> dict:
    """The batch sampler's ``ACC`` or ``GYR`` of one instance (full rate)."""
    xyz = np.asarray(xyz, dtype=float)
    prefix = "Acc" if name == "ACC" else "Gyr"
    n = len(xyz)
    return {"name": name, "type": 141 if name == "ACC" else 142, "format": "QBQfff",
            "columns": ["TimeUS", "I", "SampleUS", f"{prefix}X", f"{prefix}Y", f"{prefix}Z"],
            "data": {"TimeUS": np.asarray(time_us, dtype=np.uint64), "I": np.full(n, instance),
                     "SampleUS": np.asarray(time_us, dtype=np.uint64),
                     f"{prefix}X": xyz[:, 0], f"{prefix}Y": xyz[:, 1], f"{prefix}Z": xyz[:, 2]}}


def ardupilot_mag(instance: int, time_us, milligauss, *, numbered: bool = False) -> dict:
    """``MAG`` of one instance in milligauss (int16, as ArduPilot logs it); ``numbered``: the ``MAG2`` of older
    logs, without the ``I`` field."""
    m = np.round(np.asarray(milligauss, dtype=float)).astype(np.int16)
    n = len(m)
    data = {"TimeUS": np.asarray(time_us, dtype=np.uint64), "MagX": m[:, 0], "MagY": m[:, 1], "MagZ": m[:, 2],
            "Health": np.ones(n)}
    if numbered:
        name = "MAG" if instance == 0 else f"MAG{instance + 1}"
        return {"name": name, "type": 150 + instance, "format": "QhhhB",
                "columns": ["TimeUS", "MagX", "MagY", "MagZ", "Health"], "data": data}
    return {"name": "MAG", "type": 150, "format": "QBhhhB", "columns": ["TimeUS", "I", "MagX", "MagY", "MagZ", "Health"],
            "data": {**data, "I": np.full(n, instance)}}


# -- boards with known content -------------------------------------------------------------------------

TRUTH = (
    (np.diag([1.01, 0.99, 1.0]), np.array([0.10, -0.05, 0.20])),
    (np.array([[0.98, 0.0, 0.0], [0.01, 1.02, 0.0], [0.005, -0.01, 1.0]]), np.array([-0.20, 0.15, -0.10])),
)
"""Each IMU instance's true error m = X a + y (m/s²); instance 1's X is lower triangular, so that the
triangular model (K = X⁻¹, o = −y) holds it exactly too."""
GYR_BIAS = (np.array([0.010, -0.020, 0.005]), np.array([-0.004, 0.012, -0.030]))
"""Each instance's gyroscope bias, rad/s."""
HARD_IRON_UT = (np.array([12.0, -8.0, 30.0]), np.array([-25.0, 40.0, 5.0]))
"""Each compass instance's hard iron, µT."""


def imu_instances(seed: int, *, rate_hz: float = 200.0, orientations=None, rest_s=(4.0, 5.0)) -> list[dict]:
    """Two IMU instances of one board rested in the poses asked (default the six, shuffled): the same motion
    and noise, each instance its own error :data:`TRUTH`, gyroscope bias, and a temperature warming 30 → 34 °C
    (instance 1 a degree warmer)."""
    from app.calibration.simulations.logs import simulate_static_log

    out = []
    for k, (X, y) in enumerate(TRUTH):
        sim = simulate_static_log(np.random.default_rng(seed), orientations=orientations, sampling_rate_hz=rate_hz,
                                  X=X, y=y, noise_std=0.02, rest_s=rest_s)
        n = len(sim.samples)
        time_us = (1_000_000 + np.round(np.arange(n) * 1e6 / rate_hz)).astype(np.uint64)
        gyr = np.random.default_rng(seed + 100 + k).normal(GYR_BIAS[k], 0.002, (n, 3))
        out.append({"time_us": time_us, "acc": sim.samples, "gyr": gyr,
                    "temperature": 30.0 + k + 4.0 * np.arange(n) / n, "segments": sim.segments})
    return out


def compass_tumble(seed: int, *, rate_hz: float = 50.0, duration_s: float = 20.0, imu_rate_hz: float = 200.0):
    """A board turned through all directions: two compass instances (µT, hard iron :data:`HARD_IRON_UT`, a
    little soft iron) at ``rate_hz``, and the IMU moving at ``imu_rate_hz``. Returns ``(imus, mags, Ms)``."""
    from app.calibration.simulations.magnetometer import random_soft_iron, simulate_turn

    rng = np.random.default_rng(seed)
    n = int(duration_s * rate_hz)
    mags, Ms = [], []
    for k in range(2):
        M = random_soft_iron(rng, 0.04)
        Ms.append(M)
        mags.append({"time_us": (1_000_000 + np.round(np.arange(n) * 1e6 / rate_hz)).astype(np.uint64),
                     "mag": simulate_turn(rng, M, HARD_IRON_UT[k], field_ut=48.0, noise_ut=0.2, n=n)})
    m = int(duration_s * imu_rate_hz) + 1
    t = np.arange(m) / imu_rate_hz
    up = np.column_stack([np.sin(0.7 * t) * np.cos(0.3 * t), np.sin(0.7 * t) * np.sin(0.3 * t), np.cos(0.7 * t)])
    imus = [{"time_us": (1_000_000 + np.round(t * 1e6)).astype(np.uint64),
             "acc": 9.80665 * up + rng.normal(0, 0.3, (m, 3)), "gyr": rng.normal(0, 0.5, (m, 3)),
             "temperature": np.full(m, 31.0 + k)} for k in range(2)]
    return imus, mags, Ms


def still_board(seed: int, *, rate_hz: float = 400.0, duration_s: float = 60.0) -> list[dict]:
    """Two IMU instances resting flat (z down, FRD: −g on z), their gyroscopes with :data:`GYR_BIAS` and white
    noise of 2e-3 rad/s/√Hz, the accelerometers' of 3e-3 m/s²/√Hz."""
    from app.calibration.simulations.noise import simulate_still

    rng = np.random.default_rng(seed)
    n = int(duration_s * rate_hz)
    time_us = (1_000_000 + np.round(np.arange(n) * 1e6 / rate_hz)).astype(np.uint64)
    return [{"time_us": time_us,
             "acc": simulate_still(rng, n_samples=n, sampling_rate_hz=rate_hz, N=3e-3, B=0.0, K=0.0,
                                   bias=[0.05, -0.03, -9.80665]),
             "gyr": simulate_still(rng, n_samples=n, sampling_rate_hz=rate_hz, N=2e-3, B=0.0, K=0.0, bias=GYR_BIAS[k]),
             "temperature": np.full(n, 40.0 + k)} for k in range(2)]


def px4_file(path: Path, imus: list[dict], mags: list[dict] = (), *, gyro_lag_us: int = 150) -> Path:
    """A ULog of the IMU instances (sensor_accel, sensor_gyro ``gyro_lag_us`` later) and compasses (sensor_mag
    in gauss)."""
    topics = []
    for k, imu in enumerate(imus):
        topics.append(px4_sensor("sensor_accel", k, imu["time_us"], imu["acc"], imu["temperature"], 2424842 + k))
        topics.append(px4_sensor("sensor_gyro", k, imu["time_us"] + gyro_lag_us, imu["gyr"], imu["temperature"],
                                 2424842 + k))
    for k, mag in enumerate(mags):
        topics.append(px4_sensor("sensor_mag", k, mag["time_us"], mag["mag"] / 100.0, None, 592905 + k))
    return write_ulog(path, topics)


def ardupilot_file(path: Path, imus: list[dict], mags: list[dict] = (), *, numbered_mags: bool = False) -> Path:
    """A DataFlash log of the IMU instances (``IMU`` with ``I``) and compasses (``MAG`` in milligauss)."""
    messages = [ardupilot_imu(k, imu["time_us"], imu["acc"], imu["gyr"], imu["temperature"])
                for k, imu in enumerate(imus)]
    messages += [ardupilot_mag(k, mag["time_us"], mag["mag"] * 10.0, numbered=numbered_mags)
                 for k, mag in enumerate(mags)]
    return write_dataflash(path, messages)
