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

ULOG_TYPES = {
    "uint64_t": "<u8",
    "int64_t": "<i8",
    "uint32_t": "<u4",
    "int32_t": "<i4",
    "uint16_t": "<u2",
    "int16_t": "<i2",
    "uint8_t": "u1",
    "int8_t": "i1",
    "float": "<f4",
    "double": "<f8",
}


ULOG_STRUCT = {"int32_t": "<i", "float": "<f", "uint32_t": "<I", "uint64_t": "<Q"}


def _ulog_message(kind: str, body: bytes) -> bytes:
    return struct.pack("<HB", len(body), ord(kind)) + body


def _ulog_keyed(kind: str, type_: str, key: str, value) -> bytes:
    """An information (``I``) or parameter (``P``) message: uint8 key length, ``"type name"``, the value."""
    k = f"{type_} {key}".encode()
    v = value.encode() if type_.startswith("char") else struct.pack(ULOG_STRUCT[type_], value)
    return _ulog_message(kind, bytes([len(k)]) + k + v)


def _ulog_field(type_: str):
    """numpy type of a ULog field type, arrays (``float[4]``) included."""
    if "[" in type_:
        base, n = type_[:-1].split("[")
        return ULOG_TYPES[base], (int(n),)
    return ULOG_TYPES[type_], ()


def ulog_bytes(topics: list[dict], *, start_us: int = 0, params: dict | None = None, info: dict | None = None) -> bytes:
    """A ULog file of ``topics``: each ``{"name", "multi_id", "fields": [(type, name), ...], "data": {name: array}}``,
    the first field ``uint64_t timestamp``; the same name shares one format.  ``params`` (name → int or float)
    are written as the initial parameters (``P`` messages of the definitions section, ``int32_t`` for an int,
    ``float`` else), ``info`` (name → (type, value)) as information messages (``I``)."""
    out = [b"ULog\x01\x12\x35", bytes([1]), struct.pack("<Q", start_us)]
    out.append(_ulog_message("B", bytes(40)))
    for key, (type_, value) in (info or {}).items():
        out.append(_ulog_keyed("I", type_, key, value))
    for key, value in (params or {}).items():
        out.append(_ulog_keyed("P", "int32_t" if isinstance(value, (int, np.integer)) else "float", key, value))
    formats = {}
    for t in topics:
        formats.setdefault(t["name"], t["fields"])
    for name, fields in formats.items():
        out.append(_ulog_message("F", (name + ":" + "".join(f"{ty} {n};" for ty, n in fields)).encode()))
    for msg_id, t in enumerate(topics):
        out.append(_ulog_message("A", struct.pack("<BH", t["multi_id"], msg_id) + t["name"].encode()))
    for msg_id, t in enumerate(topics):
        dtype = np.dtype(
            [("size", "<u2"), ("type", "u1"), ("msg_id", "<u2")] + [(n, *_ulog_field(ty)) for ty, n in t["fields"]]
        )
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


SENSOR_FIELDS = [
    ("uint64_t", "timestamp"),
    ("uint64_t", "timestamp_sample"),
    ("uint32_t", "device_id"),
    ("float", "x"),
    ("float", "y"),
    ("float", "z"),
    ("float", "temperature"),
    ("uint32_t", "error_count"),
]
"""PX4's sensor_accel / sensor_gyro / sensor_mag fields (msg/SensorAccel.msg and the others), without the
clip counters and sample count, which trical does not read."""


def px4_sensor(name: str, multi_id: int, time_us, xyz, temperature=None, device_id: int = 0) -> dict:
    """A ``sensor_accel``/``sensor_gyro``/``sensor_mag`` topic of one instance (xyz in m/s², rad/s or gauss)."""
    time_us = np.asarray(time_us, dtype=np.uint64)
    xyz = np.asarray(xyz, dtype=float)
    temp = np.zeros(len(time_us)) if temperature is None else np.broadcast_to(temperature, (len(time_us),))
    return {
        "name": name,
        "multi_id": multi_id,
        "fields": SENSOR_FIELDS,
        "data": {
            "timestamp": time_us,
            "timestamp_sample": time_us,
            "device_id": np.full(len(time_us), device_id),
            "x": xyz[:, 0],
            "y": xyz[:, 1],
            "z": xyz[:, 2],
            "temperature": temp,
            "error_count": np.zeros(len(time_us)),
        },
    }


# -- DataFlash ---------------------------------------------------------------------------------------

DF_TYPES = {
    "Q": "<u8",
    "q": "<i8",
    "I": "<u4",
    "i": "<i4",
    "H": "<u2",
    "h": "<i2",
    "B": "u1",
    "b": "i1",
    "f": "<f4",
    "d": "<f8",
    "N": "S16",
    "n": "S4",
    "Z": "S64",
    "L": "<i4",
    "c": "<i2",
    "C": "<u2",
    "e": "<i4",
    "E": "<u4",
}
"""ArduPilot's format characters (libraries/AP_Logger/README or LogStructure.h): ``L`` int32 degrees × 1e7,
``c``/``C`` int16/uint16 × 100, ``e``/``E`` int32/uint32 × 100 — written here as the stored integers."""
FMT_TYPE = 128


def _df_dtype(fmt: str, columns: list[str]) -> np.dtype:
    return np.dtype([("h1", "u1"), ("h2", "u1"), ("type", "u1")] + [(c, DF_TYPES[f]) for f, c in zip(fmt, columns)])


def dataflash_bytes(messages: list[dict]) -> bytes:
    """A DataFlash log of ``messages``: each ``{"name", "type", "format", "columns": [...], "data": {col: array}}``
    (format characters as ArduPilot's: Q uint64, B uint8, f float, h int16, N char[16] …), written
    after the FMT messages describing them."""
    fmt_columns = ["Type", "Length", "Name", "Format", "Columns"]
    fmt_dtype = _df_dtype("BBnNZ", fmt_columns)
    described = [{"name": "FMT", "type": FMT_TYPE, "format": "BBnNZ", "columns": fmt_columns}] + [
        m for i, m in enumerate(messages) if m["type"] not in {x["type"] for x in messages[:i]}
    ]
    fmts = np.zeros(len(described), dtype=fmt_dtype)
    for i, m in enumerate(described):
        fmts[i] = (
            0xA3,
            0x95,
            FMT_TYPE,
            m["type"],
            _df_dtype(m["format"], m["columns"]).itemsize,
            m["name"].encode(),
            m["format"].encode(),
            ",".join(m["columns"]).encode(),
        )
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
    return {
        "name": "IMU",
        "type": 140,
        "format": "QBffffffIIfBBHH",
        "columns": [
            "TimeUS",
            "I",
            "GyrX",
            "GyrY",
            "GyrZ",
            "AccX",
            "AccY",
            "AccZ",
            "EG",
            "EA",
            "T",
            "GH",
            "AH",
            "GHz",
            "AHz",
        ],
        "data": {
            "TimeUS": np.asarray(time_us, dtype=np.uint64),
            "I": np.full(n, instance),
            "GyrX": gyr[:, 0],
            "GyrY": gyr[:, 1],
            "GyrZ": gyr[:, 2],
            "AccX": acc[:, 0],
            "AccY": acc[:, 1],
            "AccZ": acc[:, 2],
            "EG": np.zeros(n),
            "EA": np.zeros(n),
            "T": np.broadcast_to(temperature, (n,)),
            "GH": np.ones(n),
            "AH": np.ones(n),
            "GHz": np.full(n, 1000),
            "AHz": np.full(n, 1000),
        },
    }


def ardupilot_batch(name: str, instance: int, time_us, xyz) -> dict:
    """The batch sampler's ``ACC`` or ``GYR`` of one instance (full rate)."""
    xyz = np.asarray(xyz, dtype=float)
    prefix = "Acc" if name == "ACC" else "Gyr"
    n = len(xyz)
    return {
        "name": name,
        "type": 141 if name == "ACC" else 142,
        "format": "QBQfff",
        "columns": ["TimeUS", "I", "SampleUS", f"{prefix}X", f"{prefix}Y", f"{prefix}Z"],
        "data": {
            "TimeUS": np.asarray(time_us, dtype=np.uint64),
            "I": np.full(n, instance),
            "SampleUS": np.asarray(time_us, dtype=np.uint64),
            f"{prefix}X": xyz[:, 0],
            f"{prefix}Y": xyz[:, 1],
            f"{prefix}Z": xyz[:, 2],
        },
    }


def ardupilot_mag(instance: int, time_us, milligauss, *, numbered: bool = False) -> dict:
    """``MAG`` of one instance in milligauss (int16, as ArduPilot logs it); ``numbered``: the ``MAG2`` of older
    logs, without the ``I`` field."""
    m = np.round(np.asarray(milligauss, dtype=float)).astype(np.int16)
    n = len(m)
    data = {
        "TimeUS": np.asarray(time_us, dtype=np.uint64),
        "MagX": m[:, 0],
        "MagY": m[:, 1],
        "MagZ": m[:, 2],
        "Health": np.ones(n),
    }
    if numbered:
        name = "MAG" if instance == 0 else f"MAG{instance + 1}"
        return {
            "name": name,
            "type": 150 + instance,
            "format": "QhhhB",
            "columns": ["TimeUS", "MagX", "MagY", "MagZ", "Health"],
            "data": data,
        }
    return {
        "name": "MAG",
        "type": 150,
        "format": "QBhhhB",
        "columns": ["TimeUS", "I", "MagX", "MagY", "MagZ", "Health"],
        "data": {**data, "I": np.full(n, instance)},
    }


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
    from simulations.logs import simulate_static_log

    out = []
    for k, (X, y) in enumerate(TRUTH):
        sim = simulate_static_log(
            np.random.default_rng(seed),
            orientations=orientations,
            sampling_rate_hz=rate_hz,
            X=X,
            y=y,
            noise_std=0.02,
            rest_s=rest_s,
        )
        n = len(sim.samples)
        time_us = (1_000_000 + np.round(np.arange(n) * 1e6 / rate_hz)).astype(np.uint64)
        gyr = np.random.default_rng(seed + 100 + k).normal(GYR_BIAS[k], 0.002, (n, 3))
        out.append(
            {
                "time_us": time_us,
                "acc": sim.samples,
                "gyr": gyr,
                "temperature": 30.0 + k + 4.0 * np.arange(n) / n,
                "segments": sim.segments,
            }
        )
    return out


def compass_tumble(seed: int, *, rate_hz: float = 50.0, duration_s: float = 20.0, imu_rate_hz: float = 200.0):
    """A board turned through all directions: two compass instances (µT, hard iron :data:`HARD_IRON_UT`, a
    little soft iron) at ``rate_hz``, and the IMU moving at ``imu_rate_hz``. Returns ``(imus, mags, Ms)``."""
    from simulations.magnetometer import random_soft_iron, simulate_turn

    rng = np.random.default_rng(seed)
    n = int(duration_s * rate_hz)
    mags, Ms = [], []
    for k in range(2):
        M = random_soft_iron(rng, 0.04)
        Ms.append(M)
        mags.append(
            {
                "time_us": (1_000_000 + np.round(np.arange(n) * 1e6 / rate_hz)).astype(np.uint64),
                "mag": simulate_turn(rng, M, HARD_IRON_UT[k], field_ut=48.0, noise_ut=0.2, n=n),
            }
        )
    m = int(duration_s * imu_rate_hz) + 1
    t = np.arange(m) / imu_rate_hz
    up = np.column_stack([np.sin(0.7 * t) * np.cos(0.3 * t), np.sin(0.7 * t) * np.sin(0.3 * t), np.cos(0.7 * t)])
    imus = [
        {
            "time_us": (1_000_000 + np.round(t * 1e6)).astype(np.uint64),
            "acc": 9.80665 * up + rng.normal(0, 0.3, (m, 3)),
            "gyr": rng.normal(0, 0.5, (m, 3)),
            "temperature": np.full(m, 31.0 + k),
        }
        for k in range(2)
    ]
    return imus, mags, Ms


def still_board(seed: int, *, rate_hz: float = 400.0, duration_s: float = 60.0) -> list[dict]:
    """Two IMU instances resting flat (z down, FRD: −g on z), their gyroscopes with :data:`GYR_BIAS` and white
    noise of 2e-3 rad/s/√Hz, the accelerometers' of 3e-3 m/s²/√Hz."""
    from simulations.noise import simulate_still

    rng = np.random.default_rng(seed)
    n = int(duration_s * rate_hz)
    time_us = (1_000_000 + np.round(np.arange(n) * 1e6 / rate_hz)).astype(np.uint64)
    return [
        {
            "time_us": time_us,
            "acc": simulate_still(
                rng, n_samples=n, sampling_rate_hz=rate_hz, N=3e-3, B=0.0, K=0.0, bias=[0.05, -0.03, -9.80665]
            ),
            "gyr": simulate_still(rng, n_samples=n, sampling_rate_hz=rate_hz, N=2e-3, B=0.0, K=0.0, bias=GYR_BIAS[k]),
            "temperature": np.full(n, 40.0 + k),
        }
        for k in range(2)
    ]


def px4_file(path: Path, imus: list[dict], mags: list[dict] = (), *, gyro_lag_us: int = 150) -> Path:
    """A ULog of the IMU instances (sensor_accel, sensor_gyro ``gyro_lag_us`` later) and compasses (sensor_mag
    in gauss)."""
    topics = []
    for k, imu in enumerate(imus):
        topics.append(px4_sensor("sensor_accel", k, imu["time_us"], imu["acc"], imu["temperature"], 2424842 + k))
        topics.append(
            px4_sensor("sensor_gyro", k, imu["time_us"] + gyro_lag_us, imu["gyr"], imu["temperature"], 2424842 + k)
        )
    for k, mag in enumerate(mags):
        topics.append(px4_sensor("sensor_mag", k, mag["time_us"], mag["mag"] / 100.0, None, 592905 + k))
    return write_ulog(path, topics)


def ardupilot_file(path: Path, imus: list[dict], mags: list[dict] = (), *, numbered_mags: bool = False) -> Path:
    """A DataFlash log of the IMU instances (``IMU`` with ``I``) and compasses (``MAG`` in milligauss)."""
    messages = [
        ardupilot_imu(k, imu["time_us"], imu["acc"], imu["gyr"], imu["temperature"]) for k, imu in enumerate(imus)
    ]
    messages += [
        ardupilot_mag(k, mag["time_us"], mag["mag"] * 10.0, numbered=numbered_mags) for k, mag in enumerate(mags)
    ]
    return write_dataflash(path, messages)


# -- a simulated flight written as both firmwares' logs -----------------------------------------------------


def _c_nb_to_rpy_deg(c):
    """Roll, pitch, yaw (degrees, yaw 0..360 as ArduPilot logs it) of body → NED matrices, ZYX."""
    roll = np.degrees(np.arctan2(c[:, 2, 1], c[:, 2, 2]))
    pitch = np.degrees(-np.arcsin(np.clip(c[:, 2, 0], -1, 1)))
    yaw = np.degrees(np.arctan2(c[:, 1, 0], c[:, 0, 0])) % 360.0
    return roll, pitch, yaw


def _c_nb_to_quaternion(c):
    """Unit quaternions ``w, x, y, z`` of body → NED matrices (Shepperd's method, w ≥ 0 branch made safe)."""
    tr = np.trace(c, axis1=1, axis2=2)
    q = np.empty((len(c), 4))
    for i, (m, t) in enumerate(zip(c, tr)):
        k = int(np.argmax([t, m[0, 0], m[1, 1], m[2, 2]]))
        if k == 0:
            s = 2 * np.sqrt(1 + t)
            q[i] = [s / 4, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
        elif k == 1:
            s = 2 * np.sqrt(1 + m[0, 0] - m[1, 1] - m[2, 2])
            q[i] = [(m[2, 1] - m[1, 2]) / s, s / 4, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
        elif k == 2:
            s = 2 * np.sqrt(1 + m[1, 1] - m[0, 0] - m[2, 2])
            q[i] = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, s / 4, (m[1, 2] + m[2, 1]) / s]
        else:
            s = 2 * np.sqrt(1 + m[2, 2] - m[0, 0] - m[1, 1])
            q[i] = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, s / 4]
    return q * np.sign(q[:, :1] + (q[:, :1] == 0))


GPS_LEAP_S = 18
"""GPS − UTC since 2017 (the simulated flights' dates are later)."""


def _gps_week_ms(utc):
    import datetime as dt

    gps = utc + dt.timedelta(seconds=GPS_LEAP_S) - dt.datetime(1980, 1, 6, tzinfo=dt.UTC)
    week = gps.days // 7
    ms = ((gps.days % 7) * 86400 + gps.seconds) * 1000 + gps.microseconds // 1000
    return week, ms


def _power_of(flight, kind):
    return {"current": flight["current_a"], "throttle": flight["throttle"]}.get(kind)


def _specific_force(flight: dict) -> np.ndarray:
    """(N, 3) m/s²: what the accelerometer of a vehicle flying without accelerating reads, gravity's opposite in
    the body frame, ``C_nbᵀ (0, 0, −g)`` (the axis pointing up reads +g)."""
    return np.einsum("nji,j->ni", np.asarray(flight["attitude_c_nb"], dtype=float), np.array([0.0, 0.0, -9.80665]))


def ardupilot_flight_messages(flight: dict, *, generation: str = "new", instance: int = 0) -> list[dict]:
    """The messages of an ArduPilot log of ``flight`` (see :func:`write_flight_logs`).

    ``generation="new"``: ``TimeUS``, MAG with ``I``, BAT (A), CTUN ThO 0..1, GPS GWk/GMS, PARM with TimeUS and
    COMPASS_SCALE; the firmware's order ``h = D s (m + O) + MOfs``.  ``"old"`` (Copter 3.3): ``TimeMS``, MAG/MAG2
    named per instance, CURR in centi-amps (int16), CTUN ThrOut 0..1000, GPS Week/TimeMS with the board's time in
    ``T``, PARM without time; the order ``h = D (m + O + MOfs)``.  MagX…, OfsX…, MOfsX… are written as floats
    (real logs hold int16 mG) so that the raw field reads back exactly.
    """
    cal = flight["stored"]["ardupilot"]
    new = generation == "new"
    t = np.asarray(flight["time_s"], dtype=float)
    n = len(t)
    stamp = {"TimeUS": np.round(t * 1e6).astype(np.uint64)} if new else {"TimeMS": np.round(t * 1e3).astype(np.uint32)}
    tname, tfmt = ("TimeUS", "Q") if new else ("TimeMS", "I")
    m_mg = np.asarray(flight["mag_raw_ut"], dtype=float) * 10.0
    ofs = np.asarray(cal["offsets_ut"], dtype=float) * 10.0
    D = np.asarray(cal["matrix"], dtype=float)
    kind = cal.get("motor_kind")
    mot = np.asarray(cal.get("motor", np.zeros(3)), dtype=float) * 10.0
    mofs = np.zeros((n, 3)) if kind is None else np.outer(_power_of(flight, kind), mot)
    h = (m_mg + ofs) @ D.T + mofs if new else (m_mg + ofs + mofs) @ D.T
    mag = {
        **stamp,
        **{f"Mag{a}": h[:, k] for k, a in enumerate("XYZ")},
        **{f"Ofs{a}": np.full(n, ofs[k]) for k, a in enumerate("XYZ")},
        **{f"MOfs{a}": mofs[:, k] for k, a in enumerate("XYZ")},
        "Health": np.ones(n),
    }
    mag_cols = (
        [tname] + ([] if not new else ["I"]) + [f"{p}{a}" for p in ("Mag", "Ofs", "MOfs") for a in "XYZ"] + ["Health"]
    )
    if new:
        mag["I"] = np.full(n, instance)
    name = "MAG" if new or instance == 0 else f"MAG{instance + 1}"
    messages = [
        {
            "name": "MSG",
            "type": 91,
            "format": "Z",
            "columns": ["Message"],
            "data": {
                "Message": np.array([b"ArduCopter V4.5.0 (simulated)" if new else b"APM:Copter V3.3-dev (simulated)"])
            },
        }
    ]
    k = ("", "2", "3")[instance]
    params = {f"COMPASS_OFS{k}_{a}": ofs[i] for i, a in enumerate("XYZ")}
    params |= {f"COMPASS_DIA{k}_{a}": D[i, i] for i, a in enumerate("XYZ")}
    params |= {f"COMPASS_ODI{k}_X": D[0, 1], f"COMPASS_ODI{k}_Y": D[0, 2], f"COMPASS_ODI{k}_Z": D[1, 2]}
    params |= {f"COMPASS_MOT{k}_{a}": mot[i] for i, a in enumerate("XYZ")}
    params |= {
        "COMPASS_MOTCT": {None: 0, "throttle": 1, "current": 2}[kind],
        f"COMPASS_ORIENT{k}": cal.get("orientation") or 0,
    }
    if new:
        params[f"COMPASS_SCALE{k}"] = 1.0
    names = np.array([p.encode() for p in params])
    parm = {"Name": names, "Value": np.array(list(params.values()), dtype=float)}
    if new:
        parm["TimeUS"] = np.zeros(len(names), dtype=np.uint64)
    messages.append(
        {
            "name": "PARM",
            "type": 92,
            "format": "QNf" if new else "Nf",
            "columns": (["TimeUS"] if new else []) + ["Name", "Value"],
            "data": parm,
        }
    )
    messages.append(
        {
            "name": name,
            "type": 150 + (0 if new else instance),
            "format": tfmt + ("B" if new else "") + "fffffffffB",
            "columns": mag_cols,
            "data": mag,
        }
    )
    acc = _specific_force(flight)
    imu = {**stamp, **{f"Gyr{a}": np.zeros(n) for a in "XYZ"}, **{f"Acc{a}": acc[:, k] for k, a in enumerate("XYZ")}}
    if new:
        messages.append(
            {
                "name": "IMU",
                "type": 159,
                "format": "QBfffffff",
                "columns": ["TimeUS", "I", "GyrX", "GyrY", "GyrZ", "AccX", "AccY", "AccZ", "T"],
                "data": {**imu, "I": np.zeros(n), "T": np.full(n, 35.0)},
            }
        )
    else:
        messages.append(
            {
                "name": "IMU",
                "type": 159,
                "format": "Ifffffff",
                "columns": ["TimeMS", "GyrX", "GyrY", "GyrZ", "AccX", "AccY", "AccZ", "Temp"],
                "data": {**imu, "Temp": np.full(n, 35.0)},
            }
        )
    roll, pitch, yaw = _c_nb_to_rpy_deg(np.asarray(flight["attitude_c_nb"], dtype=float))
    messages.append(
        {
            "name": "ATT",
            "type": 160,
            "format": tfmt + "ffffff",
            "columns": [tname, "DesRoll", "Roll", "DesPitch", "Pitch", "DesYaw", "Yaw"],
            "data": {
                **stamp,
                "DesRoll": roll,
                "Roll": roll,
                "DesPitch": pitch,
                "Pitch": pitch,
                "DesYaw": yaw,
                "Yaw": yaw,
            },
        }
    )
    cur, thr = np.asarray(flight["current_a"], dtype=float), np.asarray(flight["throttle"], dtype=float)
    if new:
        messages.append(
            {
                "name": "BAT",
                "type": 161,
                "format": "QBff",
                "columns": ["TimeUS", "Inst", "Volt", "Curr"],
                "data": {**stamp, "Inst": np.zeros(n), "Volt": np.full(n, 16.0), "Curr": cur},
            }
        )
        messages.append(
            {
                "name": "CTUN",
                "type": 162,
                "format": "Qff",
                "columns": ["TimeUS", "ThI", "ThO"],
                "data": {**stamp, "ThI": thr, "ThO": thr},
            }
        )
    else:
        messages.append(
            {
                "name": "CURR",
                "type": 161,
                "format": "Ihhh",
                "columns": ["TimeMS", "Throttle", "Volt", "Curr"],
                "data": {
                    **stamp,
                    "Throttle": np.round(thr * 1000),
                    "Volt": np.full(n, 1600),
                    "Curr": np.round(cur * 100),
                },
            }
        )
        messages.append(
            {
                "name": "CTUN",
                "type": 162,
                "format": "Ihh",
                "columns": ["TimeMS", "ThrIn", "ThrOut"],
                "data": {**stamp, "ThrIn": np.round(thr * 1000), "ThrOut": np.round(thr * 1000)},
            }
        )
    week, ms = _gps_week_ms(flight["utc"])
    lat, lon = round(flight["lat"] * 1e7), round(flight["lon"] * 1e7)
    status = np.full(n, 3)
    status[:2] = 1  # no fix at first: the first 3-D fix is read
    gps_ms = ms + np.round((t - t[2]) * 1000).astype(np.int64)
    if new:
        messages.append(
            {
                "name": "GPS",
                "type": 163,
                "format": "QBBIHBLLf",
                "columns": ["TimeUS", "I", "Status", "GMS", "GWk", "NSats", "Lat", "Lng", "Alt"],
                "data": {
                    **stamp,
                    "I": np.zeros(n),
                    "Status": status,
                    "GMS": gps_ms,
                    "GWk": np.full(n, week),
                    "NSats": np.full(n, 12),
                    "Lat": np.full(n, lat),
                    "Lng": np.full(n, lon),
                    "Alt": np.full(n, flight["alt_m"]),
                },
            }
        )
    else:
        messages.append(
            {
                "name": "GPS",
                "type": 163,
                "format": "BIHBLLeI",
                "columns": ["Status", "TimeMS", "Week", "NSats", "Lat", "Lng", "Alt", "T"],
                "data": {
                    "Status": status,
                    "TimeMS": gps_ms,
                    "Week": np.full(n, week),
                    "NSats": np.full(n, 12),
                    "Lat": np.full(n, lat),
                    "Lng": np.full(n, lon),
                    "Alt": np.full(n, round(flight["alt_m"] * 100)),
                    "T": np.round(t * 1e3).astype(np.uint32),
                },
            }
        )
    return messages


def px4_flight_topics(flight: dict, *, device_id: int = 396809, slot: int = 0):
    """The topics, initial parameters and information of a PX4 (≥ 1.12) ULog of ``flight``: sensor_mag raw
    (gauss), vehicle_attitude, battery_status, actuator_controls_0, vehicle_gps_position, CAL_MAG{slot}_*."""
    cal = flight["stored"]["px4"]
    t_us = np.round(np.asarray(flight["time_s"], dtype=float) * 1e6).astype(np.uint64)
    n = len(t_us)
    topics = [
        px4_sensor("sensor_mag", 0, t_us, np.asarray(flight["mag_raw_ut"]) / 100.0, 35.0, device_id),
        px4_sensor("sensor_accel", 0, t_us, _specific_force(flight), 35.0, 2424842),
        px4_sensor("sensor_gyro", 0, t_us, np.zeros((n, 3)), 35.0, 2424842),
    ]
    q = _c_nb_to_quaternion(np.asarray(flight["attitude_c_nb"], dtype=float))
    topics.append(
        {
            "name": "vehicle_attitude",
            "multi_id": 0,
            "fields": [("uint64_t", "timestamp"), ("uint64_t", "timestamp_sample"), ("float[4]", "q")],
            "data": {"timestamp": t_us, "timestamp_sample": t_us, "q": q},
        }
    )
    topics.append(
        {
            "name": "battery_status",
            "multi_id": 0,
            "fields": [("uint64_t", "timestamp"), ("float", "voltage_v"), ("float", "current_a")],
            "data": {"timestamp": t_us, "voltage_v": np.full(n, 16.0), "current_a": flight["current_a"]},
        }
    )
    controls = np.zeros((n, 8))
    controls[:, 3] = flight["throttle"]
    topics.append(
        {
            "name": "actuator_controls_0",
            "multi_id": 0,
            "fields": [("uint64_t", "timestamp"), ("uint64_t", "timestamp_sample"), ("float[8]", "control")],
            "data": {"timestamp": t_us, "timestamp_sample": t_us, "control": controls},
        }
    )
    fix = np.full(n, 3)
    fix[:2] = 0
    utc_us = int(round(flight["utc"].timestamp() * 1e6))
    topics.append(
        {
            "name": "vehicle_gps_position",
            "multi_id": 0,
            "fields": [
                ("uint64_t", "timestamp"),
                ("uint64_t", "time_utc_usec"),
                ("int32_t", "lat"),
                ("int32_t", "lon"),
                ("int32_t", "alt"),
                ("uint8_t", "fix_type"),
            ],
            "data": {
                "timestamp": t_us,
                "time_utc_usec": utc_us + (t_us - t_us[2]).astype(np.int64),
                "lat": np.full(n, round(flight["lat"] * 1e7)),
                "lon": np.full(n, round(flight["lon"] * 1e7)),
                "alt": np.full(n, round(flight["alt_m"] * 1000)),
                "fix_type": fix,
            },
        }
    )
    M = np.asarray(cal["matrix"], dtype=float)
    kind = cal.get("motor_kind")
    comp = np.asarray(cal.get("motor", np.zeros(3)), dtype=float) / 100.0
    if kind == "current":
        comp = comp / 1e-3  # per kA
    p = f"CAL_MAG{slot}_"
    params = {
        p + "ID": int(device_id),
        p + "ROT": int(-1 if cal.get("orientation") is None else cal["orientation"]),
        p + "PRIO": 50,  # PX4 1.12 on: enabled at the default priority
        "CAL_MAG_COMP_TYP": {None: 0, "throttle": 1, "current": 2}[kind],
        "SENS_BOARD_ROT": 0,
    }
    params |= {p + f"{a}OFF": float(cal["offsets_ut"][i] / 100.0) for i, a in enumerate("XYZ")}
    params |= {p + f"{a}SCALE": float(M[i, i]) for i, a in enumerate("XYZ")}
    params |= {p + "XODIAG": float(M[0, 1]), p + "YODIAG": float(M[0, 2]), p + "ZODIAG": float(M[1, 2])}
    params |= {p + f"{a}COMP": float(comp[i]) for i, a in enumerate("XYZ")}
    info = {"ver_sw_release": ("uint32_t", (1 << 24) | (14 << 16) | (0 << 8) | 255), "sys_name": ("char[3]", "PX4")}
    return topics, params, info


def write_flight_logs(directory, flight: dict, *, ardupilot_generation: str = "new") -> tuple[Path, Path]:
    """A simulated flight written as an ArduPilot DataFlash log and a PX4 ULog: ``(bin_path, ulg_path)``.

    ``flight`` holds ``time_s`` (N,), ``attitude_c_nb`` (N, 3, 3) body → NED, ``mag_raw_ut`` (N, 3) raw in the
    compass's frame L (ArduPilot: the body frame; PX4: sensor_mag's frame, turned into the body by
    CAL_MAG0_ROT), ``current_a`` (N,), ``throttle`` (N,) 0..1, ``lat``, ``lon``, ``alt_m``, ``utc`` (an aware
    datetime), and ``stored`` = ``{"ardupilot": {...}, "px4": {...}}``, each with the fields of
    ``FirmwareCompassCal`` (``offsets_ut``, ``matrix``, ``motor``, ``motor_kind``, ``orientation``).  Every
    series is sampled on ``time_s``.  Each firmware's log holds the field as that firmware logs it: ArduPilot's
    MAG corrected by its stored calibration (its formula of that generation), PX4's sensor_mag raw.
    """
    directory = Path(directory)
    bin_path = write_dataflash(
        directory / "flight.bin", ardupilot_flight_messages(flight, generation=ardupilot_generation)
    )
    topics, params, info = px4_flight_topics(flight)
    ulg_path = directory / "flight.ulg"
    ulg_path.write_bytes(ulog_bytes(topics, params=params, info=info))
    return bin_path, ulg_path


def simulated_flight(seed: int, *, n: int = 600, rate_hz: float = 10.0) -> dict:
    """A seeded flight for the writers' tests: turning through headings with some roll and pitch, current and
    throttle rising together, both firmwares' stored calibrations with offsets, soft iron and motor terms."""
    import datetime as dt

    rng = np.random.default_rng(seed)
    t = 5.0 + np.arange(n) / rate_hz
    yaw = np.cumsum(rng.normal(0, 4.0, n))
    roll, pitch = 15 * np.sin(t / 3.0), 10 * np.cos(t / 5.0)
    r, p, y = np.radians(roll), np.radians(pitch), np.radians(yaw)
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    c = np.stack(
        [
            np.stack([cp * cy, sr * sp * cy - cr * sy, cr * sp * cy + sr * sy], -1),
            np.stack([cp * sy, sr * sp * sy + cr * cy, cr * sp * sy - sr * cy], -1),
            np.stack([-sp, sr * cp, cr * cp], -1),
        ],
        -2,
    )
    b_ned = np.array([20.0, 1.5, 45.0])
    field_body = np.einsum("nji,j->ni", c, b_ned)
    mag = field_body + rng.normal(0, 0.3, (n, 3)) + np.array([8.0, -5.0, 12.0])
    throttle = np.clip(0.4 + 0.2 * np.sin(t / 7.0), 0, 1)
    soft = np.array([[1.02, 0.01, -0.005], [0.01, 0.98, 0.002], [-0.005, 0.002, 1.01]])
    return {
        "time_s": t,
        "attitude_c_nb": c,
        "mag_raw_ut": mag,
        "current_a": 30.0 * throttle,
        "throttle": throttle,
        "lat": 47.3977419,
        "lon": 8.5455939,
        "alt_m": 488.0,
        "utc": dt.datetime(2024, 3, 18, 14, 49, 19, 500000, tzinfo=dt.UTC),
        "stored": {
            "ardupilot": {
                "offsets_ut": np.array([-8.1, 5.2, -11.9]),
                "matrix": soft,
                "motor": np.array([0.05, -0.03, 0.12]),
                "motor_kind": "current",
                "orientation": 0,
            },
            "px4": {
                "offsets_ut": np.array([8.1, -5.2, 11.9]),
                "matrix": soft,
                "motor": np.array([0.02, 0.01, -0.04]),
                "motor_kind": "current",
                "orientation": 2,
            },
        },
    }
