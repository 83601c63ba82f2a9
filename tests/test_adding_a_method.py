"""Adding a method touches four places and nothing else (docs/methods.md#adding-a-method): the method table
(app/methods.py), its request model (app/calibration_requests.py), its handler (a module of app/workflows) and its
result class (a module of app/calibration).

The test copies the application's tree, adds a toy method through exactly those four places — the two files it
extends and the two modules it writes — and runs the copy in a subprocess (nothing of the toy leaks into this
process). There the toy calibrates a real recording (an MPU-6050's pose file, tests/data/real/mpu6050_pose_files)
and is seen in the API (POST /api/v1/calibrations, the stored body, GET of it, the list), the CLI (``trical
calibrate --method toy``, in-process through app.cli.main.main), the page's history (the words the page gets for
it from the server's tables) and the exports (every format its result offers, by the API and by ``trical
export``).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from tests.conftest import DATA

ROOT = Path(__file__).resolve().parents[1]
RECORDING = DATA / "real" / "mpu6050_pose_files" / "z_axis_pos.csv"
TOY_WORDS = "a toy offset along gravity (accelerometer)"

RESULT = '''\
"""A toy result: an offset along the mean reading, taking its magnitude to g (a = m - o)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .shared.result import CalibrationResult, gate_fields, parameter


@dataclass(frozen=True)
class ToyOffset(CalibrationResult):
    o: np.ndarray = parameter()
    gravity: float = 1.0
    metrics: dict = field(default_factory=dict)
    warnings: tuple = ()
    reasons: tuple = ()
    method: str = "toy"
    unit: str = "m/s^2"

    RESULT_TYPE = "toy_offset"
    MODEL_TYPE = "toy_offset"
    CORRECTION_SOURCE = "a = m - o (a toy)"

    def _calibrate(self, rows):
        return rows - self.o

    def uncertainty(self) -> dict:
        return {"o": None, "note": "a toy has no intervals"}

    def body_dict(self) -> dict:
        return {}

    @classmethod
    def _from_body(cls, data: dict) -> "ToyOffset":
        return cls(
            **cls.parameters_from(data["model"]),
            gravity=data["gravity"],
            method=data["method"],
            unit=data["unit"],
            **gate_fields(data),
        )


def fit_toy(acc, gravity: float) -> ToyOffset:
    mean = np.asarray(acc, dtype=float).mean(axis=0)
    norm = float(np.linalg.norm(mean))
    return ToyOffset(o=mean - gravity * mean / norm, gravity=gravity, metrics={"count": len(acc)})
'''

REQUEST = '''

class ToyIn(Strict):
    """A toy: an offset along the mean reading of an uploaded recording."""

    method: Literal["toy"]
    recording_id: str = Field(description="An uploaded recording (POST /api/v1/recordings).")
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None
'''

HANDLER = '''\
"""The toy method's handler."""

from __future__ import annotations

from app.calibration.shared.gravity import STANDARD_GRAVITY
from app.calibration.toy import fit_toy
from app.workflows.calibration import Calibration
from app.workflows.recordings import RecordingSource
from app.workflows.requests import Described


def toy(request: Described, recording: RecordingSource) -> Calibration:
    log = recording.read()
    unit = log.units["acc"]
    result = fit_toy(log.acc, STANDARD_GRAVITY if unit == "m/s^2" else 1.0)
    return Calibration.of(
        result,
        {},
        unit=unit,
        notes=[],
        device_id=request.device_id,
        label=request.label or recording.meta.get("filename"),
        **recording.source_fields,
    )
'''

ENTRY = f'''    Method(
        "toy",
        request=rq.ToyIn,
        handler=toy.toy,
        response=None,
        command="calibrate",
        formats=CORRECTION_EXPORTS,
        kind=ACCELEROMETER,
        words="{TOY_WORDS}",
        page_words="the toy calibration",
    ),
'''

CHECK = r"""
import contextlib, io, json, sys
from pathlib import Path

from fastapi.testclient import TestClient

from app import methods
from app.cli.main import main
from app.config import Settings
from app.main import create_app

recording, tmp = Path(sys.argv[1]), Path(sys.argv[2])
seen = {}
settings = Settings()  # the database and the recordings in the test's folder (TRICAL_ in the environment)
with TestClient(create_app(settings), raise_server_exceptions=False) as client:
    with open(recording, "rb") as f:
        up = client.post("/api/v1/recordings", files={"file": (recording.name, f, "text/csv")},
                         data={"acc_unit": "m/s^2"})
    assert up.status_code == 201, up.text
    made = client.post("/api/v1/calibrations", json={"method": "toy", "recording_id": up.json()["id"]})
    seen["post"] = [made.status_code, made.json()]
    cal = made.json().get("id")
    got = client.get(f"/api/v1/calibrations/{cal}")
    seen["get"] = [got.status_code, got.json()]
    seen["list"] = [item["method"] for item in client.get("/api/v1/calibrations").json()["items"]]
    spec = client.get("/openapi.json").json()["paths"]["/api/v1/calibrations"]["post"]
    seen["openapi"] = {
        "request": sorted(spec["requestBody"]["content"]["application/json"]["schema"]["discriminator"]["mapping"]),
        "response": sorted(
            spec["responses"]["201"]["content"]["application/json"]["schema"]["discriminator"]["mapping"]
        ),
    }
    seen["exports"] = {
        fmt: client.get(f"/api/v1/calibrations/{cal}/export", params={"format": fmt}).status_code
        for fmt in methods.BY_NAME["toy"].formats
    }
    history = client.get("/history")
    tables = history.text.split('id="trical-tables">', 1)[1].split("</script>", 1)[0]
    seen["history"] = [history.status_code, json.loads(tables)["methods"].get("toy")]

out = io.StringIO()
with contextlib.redirect_stdout(out):
    status = main(["calibrate", str(recording), "--method", "toy", "--unit", "m/s^2", "--json"])
seen["cli"] = [status, json.loads(out.getvalue())]
out = io.StringIO()
with contextlib.redirect_stdout(out):
    status = main(["calibrate", str(recording), "--method", "toy", "--unit", "m/s^2", "--no-store"])
seen["cli_words"] = [status, out.getvalue()]
stored = seen["cli"][1]["id"]
with contextlib.redirect_stdout(io.StringIO()):
    seen["cli_exports"] = {
        fmt: main(["export", stored, "--format", fmt, "-o", str(tmp / f"toy.{fmt}")])
        for fmt in methods.BY_NAME["toy"].formats
    }
print(json.dumps(seen))
"""


def add_the_toy(tree: Path) -> None:
    """Write the toy through the four places: a result module, a request model, a handler, a table entry."""
    (tree / "app" / "calibration" / "toy.py").write_text(RESULT, encoding="utf-8")
    requests = tree / "app" / "calibration_requests.py"
    requests.write_text(requests.read_text(encoding="utf-8") + REQUEST, encoding="utf-8")
    (tree / "app" / "workflows" / "toy.py").write_text(HANDLER, encoding="utf-8")
    table = tree / "app" / "methods.py"
    text = table.read_text(encoding="utf-8")
    end = "\n)\nTABLE: tuple"
    assert text.count(end) == 1 and text.count("from app.workflows import ") == 1
    text = text.replace(end, "\n" + ENTRY.rstrip("\n") + end).replace(
        "from app.workflows import ", "from app.workflows import toy, "
    )
    table.write_text(text, encoding="utf-8")


def test_a_toy_method_added_in_four_places_is_in_the_api_the_cli_the_history_and_the_exports(tmp_path):
    tree = tmp_path / "tree"
    skip = shutil.ignore_patterns("__pycache__", "*.pyc")
    for part in ("app", "static", "templates"):
        shutil.copytree(ROOT / part, tree / part, ignore=skip)
    add_the_toy(tree)
    changed = sorted(
        str(p.relative_to(tree))
        for p in (tree / "app").rglob("*.py")
        if not (ROOT / p.relative_to(tree)).is_file() or (ROOT / p.relative_to(tree)).read_bytes() != p.read_bytes()
    )
    assert changed == [
        "app/calibration/toy.py",
        "app/calibration_requests.py",
        "app/methods.py",
        "app/workflows/toy.py",
    ]

    run = subprocess.run(
        [sys.executable, "-c", CHECK, str(RECORDING), str(tmp_path)],
        check=False,
        cwd=tree,
        env={
            "PYTHONPATH": str(tree),
            "PATH": "/usr/bin:/bin",
            "HOME": str(tmp_path),
            "TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}",
        },
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    seen = json.loads(run.stdout.splitlines()[-1])

    status, body = seen["post"]
    assert status == 201, body
    assert body["method"] == "toy" and body["model"]["type"] == "toy_offset" and body["ok"], body
    assert body["label"] == RECORDING.name and body["verdict"]["words"]
    assert seen["get"] == [200, body]
    assert seen["list"] == ["toy"]
    assert "toy" in seen["openapi"]["request"] and "toy" in seen["openapi"]["response"]

    assert seen["exports"] and set(seen["exports"].values()) == {200}, seen["exports"]
    assert seen["history"] == [200, TOY_WORDS]

    status, cli_body = seen["cli"]
    assert status == 0 and cli_body["method"] == "toy" and cli_body["model"] == body["model"]
    status, words = seen["cli_words"]
    assert status == 0 and body["verdict"]["words"] in words, words
    assert set(seen["cli_exports"]) == set(seen["exports"]) and set(seen["cli_exports"].values()) == {0}
