"""trical on real still-pose recordings of phones and IMU boards, through the API (issue 11).

The recordings (tests/data/real/README.md, loaded by tests/real_recordings.py): an MPU-6050 in ten
free poses and, in another session, one more pose; an MPU-9250 in the six axis-aligned poses in four
sessions; three phones of Georgieva et al. (ESGI'95) Tables 1–3 in 26–29 free poses, and runs of
10 or 11 of their poses (the issue's "a person putting the phone down in 9–11 poses").

- ``test_cv_error_*``: ``metrics.cv_error_mg`` is the leave-one-out error, recomputed here by
  refitting the core functions without each pose.
- ``test_figures_*``: the figures measured on these recordings (``python bench/real_recordings.py``).
- ``test_ok_*``: the truth conditions of issue 11.  They state what ``ok`` must mean; where today's
  gates let a calibration through that makes new poses worse, they fail, naming the recording.
"""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.still.affine import fit_orientations
from app.calibration.still.triangular import fit_triangular
from tests.real_recordings import MPU6050_LSB_PER_G, by_name, pose_subsets, raw_error_mg, recordings, tedaldi_apply

RECS = by_name()
MANY_POSES = [r.name for r in recordings() if len(r.means) >= 10]  # enough for a 9-parameter fit and its cv
AXIS_ALIGNED = [r.name for r in recordings() if r.ups is not None]
SUBSETS = [(rec.name, sl.start, sl.stop) for rec, sl in pose_subsets()]


def subset_id(case) -> str:
    name, start, stop = case
    return f"{name}[{start + 1}-{stop}]"


def post(client, rec, method: str, means, holdout=None) -> dict:
    """POST /api/v1/calibrations with still means (magnitude methods) or labelled readings."""
    body: dict = {"method": method, "unit": rec.unit}
    if rec.unit != "g":
        body["gravity"] = rec.gravity
    if method in ("triangular", "nonorthogonal"):
        body["means"] = np.asarray(means).tolist()
    else:
        body["readings"] = [{"mean": list(m), "up": u} for m, u in zip(np.asarray(means).tolist(), rec.ups)]
    if holdout is not None:
        body["holdout"] = np.asarray(holdout).tolist()
    r = client.post("/api/v1/calibrations", json=body)
    assert r.status_code == 201, r.text
    return r.json()


def leave_one_out_mg(fit, means, gravity: float) -> tuple[float, float]:
    """Mean and largest | |a_i| − g | / g in mg, a_i calibrated by ``fit`` on every other pose."""
    m = np.asarray(means, dtype=float)
    errors = []
    for i in range(len(m)):
        kept = np.delete(np.arange(len(m)), i)
        a = fit(kept).apply(m[i])
        errors.append(abs(np.linalg.norm(a) - gravity) / gravity)
    return 1000.0 * float(np.mean(errors)), 1000.0 * float(np.max(errors))


def other_sessions(rec) -> np.ndarray:
    return np.vstack([RECS[o].means for o in rec.other_sessions])


# -- (a) the cross-validated error is what it says ---------------------------------------------------


@pytest.mark.parametrize("name", MANY_POSES)
def test_cv_error_is_leave_one_out_of_fit_triangular(client, name):
    rec = RECS[name]
    body = post(client, rec, "triangular", rec.means)
    mean, worst = leave_one_out_mg(
        lambda idx: fit_triangular(rec.means[idx], gravity=rec.gravity), rec.means, rec.gravity
    )
    assert body["metrics"]["cv_scheme"] == "leave-one-out"
    assert body["metrics"]["cv_error_mg"] == pytest.approx(mean, rel=1e-9)
    assert body["metrics"]["cv_error_max_mg"] == pytest.approx(worst, rel=1e-9)


@pytest.mark.parametrize("case", SUBSETS, ids=subset_id)
def test_cv_error_of_a_person_s_ten_or_eleven_poses_is_leave_one_out(client, case):
    name, start, stop = case
    rec, m = RECS[name], RECS[name].means[start:stop]
    body = post(client, rec, "triangular", m)
    mean, worst = leave_one_out_mg(lambda idx: fit_triangular(m[idx], gravity=rec.gravity), m, rec.gravity)
    assert body["metrics"]["cv_error_mg"] == pytest.approx(mean, rel=1e-9)
    assert body["metrics"]["cv_error_max_mg"] == pytest.approx(worst, rel=1e-9)


@pytest.mark.parametrize("name", AXIS_ALIGNED)
def test_cv_error_is_leave_one_out_of_fit_orientations(client, name):
    rec = RECS[name]
    body = post(client, rec, "orientations", rec.means)
    mean, worst = leave_one_out_mg(
        lambda idx: fit_orientations(rec.means[idx], [rec.ups[i] for i in idx], gravity=rec.gravity),
        rec.means,
        rec.gravity,
    )
    assert body["metrics"]["cv_error_mg"] == pytest.approx(mean, rel=1e-9)
    assert body["metrics"]["cv_error_max_mg"] == pytest.approx(worst, rel=1e-9)
    six = post(client, rec, "six_position", rec.means)
    assert six["metrics"]["cv_error_mg"] is None and "add poses" in six["metrics"]["cv_note"]


# -- measured figures (python bench/real_recordings.py) ------------------------------------------------

# recording → (raw mg, triangular in-sample error_after_mg, cv_error_mg, cv_error_max_mg)
TRIANGULAR_FIGURES = {
    "mpu6050-session1": (62.32, 0.0212, 0.4655, 0.9035),
    "georgieva-table1": (74.05, 0.767, 1.204, 4.601),
    "georgieva-table2": (37.47, 1.044, 1.671, 4.905),
    "georgieva-table3": (19.40, 0.852, 1.365, 3.816),
}


@pytest.mark.parametrize("name", sorted(TRIANGULAR_FIGURES))
def test_figures_triangular(client, name):
    rec = RECS[name]
    raw, after, cv, cv_max = TRIANGULAR_FIGURES[name]
    body = post(client, rec, "triangular", rec.means)
    assert rec.raw_error_mg == pytest.approx(raw, abs=0.005)
    assert body["metrics"]["error_before_mg"] == pytest.approx(rec.raw_error_mg, rel=1e-9)
    # Solver tolerances move the in-sample figure in its last digits; the cv figures are rounded as printed.
    assert body["metrics"]["error_after_mg"] == pytest.approx(after, rel=0.02)
    assert body["metrics"]["cv_error_mg"] == pytest.approx(cv, rel=2e-3)
    assert body["metrics"]["cv_error_max_mg"] == pytest.approx(cv_max, rel=2e-3)
    # On every real recording the in-sample figure flatters: new poses are 1.6–22 times worse.
    assert body["metrics"]["cv_error_mg"] > 1.3 * body["metrics"]["error_after_mg"]


def test_figures_mpu6050_against_the_peer_and_the_next_session(client):
    """Ten poses of an MPU-6050: trical's fit beats the recording's own Tedaldi et al. fit on the
    fitted poses (0.021 against 0.311 mg) and takes the next session's pose from 87.9 to 1.6 mg."""
    rec = RECS["mpu6050-session1"]
    body = post(client, rec, "triangular", rec.means, holdout=other_sessions(rec))
    p = rec.peer["tedaldi"]
    peer_in_sample = raw_error_mg(tedaldi_apply(p, rec.means * MPU6050_LSB_PER_G), p["gravity"])
    peer_next = raw_error_mg(tedaldi_apply(p, other_sessions(rec) * MPU6050_LSB_PER_G), p["gravity"])
    assert peer_in_sample == pytest.approx(0.311, abs=0.001)
    assert peer_next == pytest.approx(1.65, abs=0.01)
    assert body["metrics"]["error_after_mg"] < peer_in_sample / 10
    assert body["metrics"]["holdout_error_before_mg"] == pytest.approx(87.94, abs=0.01)
    assert body["metrics"]["holdout_error_after_mg"] == pytest.approx(1.588, abs=0.005)


def test_figures_mpu9250_six_position_equals_the_author_s_fit(client):
    """The four sessions of an MPU-9250: six_position reproduces the author's own least-squares fit
    of trial_1 (m = S a + b) and each session's calibration takes the other three from ~127 to ≤ 1.8 mg."""
    rec = RECS["mpu9250-trial_1"]
    six = post(client, rec, "six_position", rec.means)
    np.testing.assert_allclose(six["model"]["X"], rec.peer["ward"]["S"], atol=1e-9)
    np.testing.assert_allclose(six["model"]["y"], rec.peer["ward"]["b"], atol=1e-9)
    for name in AXIS_ALIGNED:
        r = RECS[name]
        body = post(client, r, "orientations", r.means, holdout=other_sessions(r))
        assert 126 < body["metrics"]["holdout_error_before_mg"] < 128
        assert body["metrics"]["holdout_error_after_mg"] < 1.8
        assert 2.2 < body["metrics"]["cv_error_mg"] < 3.9


# -- (b) the truth conditions of issue 11 ----------------------------------------------------------------

TRUTH_CASES = [(name, 0, len(RECS[name].means)) for name in MANY_POSES] + SUBSETS


@pytest.mark.parametrize("case", TRUTH_CASES, ids=subset_id)
def test_ok_never_stands_on_a_calibration_worse_than_raw(client, case):
    """Issue 11: whenever a calibration calibrates new poses no better than the raw readings are
    (cv_error_mg ≥ mean | |m_i| − g |), ``ok`` is false.  Fails today on Georgieva Table 3's poses
    1–10 (cv 48.2 mg, raw 21.5 mg) and 1–11 (cv 65.4 mg, raw 19.9 mg)."""
    name, start, stop = case
    rec, m = RECS[name], RECS[name].means[start:stop]
    body = post(client, rec, "triangular", m)
    raw = raw_error_mg(m, rec.gravity)
    if body["metrics"]["cv_error_mg"] >= raw:
        assert not body["ok"], (
            f"{name} poses {start + 1}–{stop}: ok although new poses get "
            f"{body['metrics']['cv_error_mg']:.1f} mg against {raw:.1f} mg raw"
        )


@pytest.mark.parametrize(
    "name,method",
    [("mpu6050-session1", "triangular"), ("mpu6050-session1", "nonorthogonal")]
    + [(n, m) for n in AXIS_ALIGNED for m in ("orientations", "six_position")],
)
def test_ok_calibration_does_not_make_the_device_s_other_session_worse(client, name, method):
    """Issue 11: a calibration that says ok, applied to the same device's other session, does not
    make it worse (there: 8.5 → 13.1 mg on a phone).  Holds on both boards today."""
    rec = RECS[name]
    body = post(client, rec, method, rec.means, holdout=other_sessions(rec))
    if body["ok"]:
        assert body["metrics"]["holdout_error_after_mg"] <= body["metrics"]["holdout_error_before_mg"], name


@pytest.mark.parametrize("case", SUBSETS, ids=subset_id)
def test_ok_calibration_does_not_make_the_phone_s_unseen_poses_worse(client, case):
    """Issue 11: "three of the seven say ok although the calibration makes unseen poses worse than
    raw".  A person's 10 or 11 poses calibrated, the table's other poses held out: ok must not stand
    on a calibration that makes them worse.  Fails today on Georgieva Table 3's poses 1–10
    (ok; the other 16 poses 18.1 → 35.8 mg)."""
    name, start, stop = case
    rec = RECS[name]
    rest = np.delete(rec.means, np.arange(start, stop), axis=0)
    body = post(client, rec, "triangular", rec.means[start:stop], holdout=rest)
    if body["ok"]:
        before, after = body["metrics"]["holdout_error_before_mg"], body["metrics"]["holdout_error_after_mg"]
        assert after <= before, (
            f"{name} poses {start + 1}–{stop}: ok although unseen poses go {before:.1f} → {after:.1f} mg"
        )
