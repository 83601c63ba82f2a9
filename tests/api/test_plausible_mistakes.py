"""Every mistake a person can make reading a real recording: never ok with an implausible figure
(issue 31, point 6).

Each real recording of tests/data/real that uploads as a log — the boards' and phones' files below, and
every corpus case (tests/data/real/corpus/*/case.json, picked up by glob) — is read once as it should be
(its baseline) and then with each mistake: each sensor's unit option set to each wrong value, a chip of
another range (or another part) for a sensor in counts, and its columns named for another sensor (acc
named gyr and the reverse, the compass named acc or gyr). Every answer must be one of: a 4xx naming the
problem; ``ok`` false with reasons; or ``ok`` true with figures that are plausible (the core's plausibility
gate, recomputed on the stored body) and, where they are in the baseline's unit, the baseline's own (the
data overruled the mistake). Every mistake is tried, one test per recording.
"""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration import registry
from app.io.log import UNITS_IN as UNITS
from tests.api.test_remedies import answer_problems
from tests.conftest import DATA
from tests.real_corpus import cases as corpus_cases

REAL = DATA / "real"
CHIPS = {
    "acc": ("mpu6050-2g", "mpu6050-4g", "mpu6050-8g", "mpu6050-16g"),
    "gyr": ("mpu6050-250dps", "mpu6050-500dps", "mpu6050-1000dps", "mpu6050-2000dps"),
    "mag": (
        "qmc5883l-2g",
        "qmc5883l-8g",
        "hmc5883l-1370",
        "hmc5883l-230",
        "ak8963-16bit",
        "lis3mdl-4g",
        "mmc5983ma-16bit",
    ),
}
SWAPS = (("acc", "gyr"), ("gyr", "acc"), ("mag", "acc"), ("mag", "gyr"), ("acc", "mag"), ("gyr", "mag"))


def _board_cases() -> list[dict]:
    """The real recordings kept outside the corpus that upload as logs, as the corpus states a case."""
    pose = sorted((REAL / "mpu6050_pose_files").glob("*.csv"))
    esp = sorted((REAL / "mpu6050_esp32_pose_files").glob("*.csv"))
    mag = REAL / "magnetometer"
    return [
        {
            "name": "mpu6050_session2_still_30s",
            "files": [REAL / "mpu6050_session2_still_30s.csv"],
            "form": {
                "columns": "acc_x,acc_y,acc_z",
                "acc_unit": "raw",
                "lsb_per_g": "16384",
                "sampling_rate_hz": "100",
            },
            "calibrate": {"method": "noise"},
        },
        {
            "name": "mpu6050_pose_files",
            "files": pose,
            "form": {},
            "calibrate": {"method": "six_position"},
            "columns": "t,acc_x,acc_y,acc_z,temp_c,gyr_x,gyr_y,gyr_z",
        },
        {
            "name": "mpu6050_esp32_pose_files",
            "files": esp,
            "form": {},
            "calibrate": {"method": "orientations"},
            "columns": "time_us,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z,-",
        },
        {
            "name": "qmc5883l_turn",
            "files": [mag / "tomisuarez2_qmc5883l_turn_every10.csv"],
            "form": {"columns": "mag_x,mag_y,mag_z", "mag_unit": "raw", "sampling_rate_hz": "5"},
            "calibrate": {"method": "magnetometer"},
        },
        {
            "name": "iphone13_magnetometer",
            "files": [mag / "jmandzak_iphone13_MagnetometerUncalibrated.csv"],
            "form": {},
            "calibrate": {"method": "magnetometer"},
        },
        {
            "name": "android_hard_iron",
            "files": [mag / "simorxb_android_hard_iron_MagnetometerUncalibrated.csv"],
            "form": {},
            "calibrate": {"method": "magnetometer"},
        },
    ]


def _corpus_cases() -> list[dict]:
    """Every corpus case that uploads and calibrates (its files, form and calibration as stated, both
    answered with 201: a case whose right answer is a refusal has no figure to get wrong)."""
    return [
        {"name": c.name, "files": c.files, "form": dict(c.form), "calibrate": dict(c.spec["calibrate"])}
        for c in corpus_cases()
        if "calibrate" in c.spec
        and c.spec["upload"].get("status", 201) == 201
        and c.spec["expect"].get("status", 201) == 201
    ]


def _post(client, case: dict, form: dict):
    files = [("file", (p.name, p.read_bytes(), "text/csv")) for p in case["files"]]
    r = client.post("/api/v1/recordings", files=files, data=form)
    if r.status_code != 201:
        return r, None
    return r, client.post("/api/v1/calibrations", json={**case["calibrate"], "recording_id": r.json()["id"]})


def _mistakes(case: dict, baseline: dict) -> list[tuple[str, dict]]:
    """Every wrong reading of a case: (what was done, the upload form)."""
    form, units, out = case["form"], baseline["units"], []
    for sensor, right in units.items():
        for unit in UNITS[sensor]:
            if unit != right and form.get(f"{sensor}_unit") != unit:
                wrong = {k: v for k, v in form.items() if k not in ("chip", "lsb_per_g") or unit == "raw"}
                out.append((f"{sensor}_unit={unit}", {**wrong, f"{sensor}_unit": unit}))
        if right == "raw" or form.get(f"{sensor}_unit") == "raw":
            for chip in CHIPS[sensor]:
                if chip != form.get("chip"):
                    wrong = {k: v for k, v in form.items() if k not in ("lsb_per_g", "chip")}
                    out.append((f"chip={chip}", {**wrong, f"{sensor}_unit": "raw", "chip": chip}))
    columns = case.get("columns") or form.get("columns") or ",".join(baseline["columns"])
    if all(c.split("_")[0] in ("t", "time", "temp", "acc", "gyr", "mag", "-") for c in columns.split(",")):
        for a, b in SWAPS:
            if f"{a}_x" in columns:
                swapped = columns.replace(f"{b}_", "tmp_").replace(f"{a}_", f"{b}_").replace("tmp_", f"{a}_")
                out.append(
                    (
                        f"columns {a} named {b}",
                        {**{k: v for k, v in form.items() if not k.endswith("_unit")}, "columns": swapped},
                    )
                )
    return out


def _figures(body: dict) -> dict:
    """The figures a mistake must not change when the data overruled it: the noise densities (SI) of
    each sensor, or the verdict's calibrated figure with its unit."""
    if body.get("method") == "noise":
        return {
            f"{s} noise density": (np.asarray([v for v in m["noise_density"] if v is not None]), m["unit"])
            for s, m in body["model"].items()
            if isinstance(m, dict) and "noise_density" in m
        }
    v = body.get("verdict") or {}
    return {} if v.get("after") is None else {"figure": (np.asarray([v["after"]]), v.get("unit"))}


CASES = _board_cases() + _corpus_cases()


@pytest.mark.parametrize("case", CASES, ids=[c["name"] for c in CASES])
def test_no_mistake_reading_a_real_recording_gives_ok_with_an_implausible_figure(client, case):
    r, c = _post(client, case, case["form"])
    assert r.status_code == 201 and c is not None and c.status_code == 201, (case["name"], r.text, c and c.text)
    baseline = {**r.json(), "body": c.json()}
    mistakes = _mistakes(case, baseline)
    outcomes = {"refused (4xx)": 0, "ok false with reasons": 0, "ok, overruled by the data": 0}
    for what, form in mistakes:
        r, c = _post(client, case, form)
        where = f"{case['name']}: {what}"
        # Its remedies are ones their places take (tests/api/test_remedies.py): the mistake's own answer too.
        problems = answer_problems(
            r, c, names=[p.name for p in case["files"]], form=form, method=case["calibrate"]["method"]
        )
        assert not problems, (where, problems)
        if c is None or c.status_code != 201:
            answer = r if c is None else c
            assert 400 <= answer.status_code < 500 and answer.json().get("detail"), (where, answer.text)
            outcomes["refused (4xx)"] += 1
            continue
        body = c.json()
        if not body["ok"]:
            assert body["reasons"], where
            outcomes["ok false with reasons"] += 1
            continue
        assert registry.from_dict(body).plausibility() == [], where
        right = _figures(baseline["body"])
        for name, (values, unit) in _figures(body).items():
            if name in right and right[name][1] == unit and len(right[name][0]) == len(values):
                np.testing.assert_allclose(values, right[name][0], rtol=0.5, atol=1e-9, err_msg=f"{where}: {name}")
        outcomes["ok, overruled by the data"] += 1
    print(f"\n{case['name']}: {len(mistakes)} mistakes: {outcomes}")
    assert mistakes and sum(outcomes.values()) == len(mistakes)


def test_the_mistakes_are_tried_on_every_recording_that_calibrates():
    """The board logs beside the corpus, and every corpus case whose answer is a calibration."""
    assert len(CASES) >= len(_board_cases()) + 10
