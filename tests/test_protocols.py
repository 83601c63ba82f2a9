"""The capture protocols' strategies (app.guided.protocols) one by one: what each asks for next after given captures,
how it checks a capture, when a session may be solved; the typed session read from and written to a real SQLite
store (app.guided.sessions); and what the terminal's capture (app.cli.board) asks of each."""

from __future__ import annotations

import typing

import numpy as np
import pytest

from app.api.deps import new_session_token
from app.api.schemas.sessions import SessionIn
from app.calibration import CANONICAL_SIX, STANDARD_GRAVITY, CalibrationError, InsufficientDataError, up_vector
from app.calibration.shared.capture import PoseTooCloseError
from app.calibration.still.advice import fibonacci_sphere
from app.guided import sessions
from app.guided.capture_rules import (
    CAPTURE_PROTOCOLS,
    FREE_FIT_FROM,
    FREE_MIN_ANGLE_DEG,
    FREE_TARGET_MIN_POSES,
    capture_thresholds,
)
from app.guided.protocols import BOARD_PROTOCOLS, CUBE24, FREE, SESSION_PROTOCOLS, SIX
from app.store import ConflictError, open_store
from tests.cube_phone import phone_cube
from tests.phone_poses import direction_samples, pose_samples

G = STANDARD_GRAVITY
PAGE_MAX_ANGLE_DEG = capture_thresholds()["maxAngleDeg"]


@pytest.fixture
def store(tmp_path):
    return open_store(f"sqlite:///{tmp_path / 'trical.db'}", tmp_path / "files")


def start(store, protocol: str, **fields) -> sessions.Session:
    request = {"protocol": protocol, "capture_s": 5.0, "unit": "m/s^2", "target_mg": 2.0, **fields}
    return sessions.create(store, request, new_session_token()[1], owner=None)


def captured(store, session: sessions.Session, *bodies: dict) -> sessions.Session:
    """The session after each body is captured through sessions.add_capture (checked, stored, read back)."""
    for body in bodies:
        sessions.add_capture(store, session, body)
        session = sessions.load(store, session.id)
    return session


def test_the_tables_name_the_protocols_the_api_and_the_command_take():
    assert set(SESSION_PROTOCOLS) == set(typing.get_args(SessionIn.model_fields["protocol"].annotation))
    assert tuple(BOARD_PROTOCOLS) == CAPTURE_PROTOCOLS
    for name, protocol in BOARD_PROTOCOLS.items():
        assert protocol.name == name and protocol.words
    assert SESSION_PROTOCOLS["six"] is BOARD_PROTOCOLS["six"] is SIX  # one strategy for the page and the terminal
    assert SESSION_PROTOCOLS["cube24"] is BOARD_PROTOCOLS["cube24"] is CUBE24
    assert SESSION_PROTOCOLS["free"] is BOARD_PROTOCOLS["free"] is FREE
    # The one list of the protocols' names (app.guided.capture_rules): each has its strategy, the sessions are
    # those it says a session runs, and every strategy is on it.
    from app.guided.capture_rules import WIZARD_PROTOCOLS

    assert {p.name for p in WIZARD_PROTOCOLS} == set(BOARD_PROTOCOLS)
    assert tuple(SESSION_PROTOCOLS) == tuple(p.name for p in WIZARD_PROTOCOLS if p.session)


def test_a_session_is_read_from_and_written_to_the_store_s_row(store):
    session = start(store, "free", device_id="phone-1", label="bench", gravity=9.81)
    again = sessions.load(store, session.id)
    assert again == session and again.protocol is FREE
    assert session.id.startswith("ses_") and session.created_at and session.calibration_id is None
    assert session.gravity == 9.81 and session.target_mg == 2.0 and session.positions == ()
    row = session.row()
    assert row == dict(store.get_session(session.id), captures=[])
    assert {k: row[k] for k in ("protocol", "device_id", "label", "source", "target_mg")} == {
        "protocol": "free",
        "device_id": "phone-1",
        "label": "bench",
        "source": "phone",
        "target_mg": 2.0,
    }
    six = start(store, "six", latitude_deg=45.0, height_m=0.0)
    assert "target_mg" not in six.row()  # only a protocol with a target keeps one
    assert six.gravity == pytest.approx(9.80620, abs=2e-5)  # WGS84 normal gravity at 45°, sea level
    view = sessions.view(six)
    assert view["remaining"] == list(CANONICAL_SIX) and "progress" not in view


def test_six_asks_for_the_flat_poses_first_and_accepts_any_remaining_one(store):
    rng = np.random.default_rng(1)
    session = start(store, "six")
    assert SIX.next_position(session) == "+z" and SIX.remaining(session) == list(CANONICAL_SIX)
    session = captured(store, session, pose_samples("+z", rng))
    assert SIX.next_position(session) == "-z"
    session = captured(store, session, pose_samples("+x", rng))  # not the one named next: any remaining pose is
    assert SIX.next_position(session) == "-z"
    assert SIX.remaining(session) == ["-x", "-y", "+y", "-z"]
    session = captured(store, session, pose_samples("-z", rng), pose_samples("+y", rng))
    assert SIX.next_position(session) == "-y"


def test_six_is_solvable_with_all_six_poses_and_not_before(store):
    rng = np.random.default_rng(2)
    session = captured(store, start(store, "six"), *[pose_samples(p, rng) for p in CANONICAL_SIX[:5]])
    assert not SIX.solvable(session)
    with pytest.raises(InsufficientDataError, match=r"capture \+z first: the session has 5 of 6 positions"):
        sessions.solve(store, session)
    session = captured(store, session, pose_samples("+z", rng))
    assert SIX.solvable(session) and SIX.next_position(session) is None
    body = sessions.solve(store, session)
    assert body["method"] == "six_position" and body["session_id"] == session.id
    assert [c["position"] for c in body["captures"]] == list(CANONICAL_SIX)


def test_six_checks_the_pose_against_the_data(store):
    rng = np.random.default_rng(3)
    session = start(store, "six")
    summary = SIX.check(session, dict(pose_samples("-y", rng), gyr_unit="deg/s"))
    assert summary["position"] == "-y" and summary["count"] == 300 and summary["gyr_count"] == 300
    with pytest.raises(CalibrationError, match="one of -x, \\+x"):
        SIX.check(session, dict(pose_samples("-y", rng), position="7"))
    with pytest.raises(CalibrationError):
        SIX.check(session, dict(pose_samples("-y", rng), position="+x"))  # the data show -y up


def test_free_numbers_its_poses_and_is_solvable_from_fit_from(store):
    directions = fibonacci_sphere(FREE_TARGET_MIN_POSES)
    rng = np.random.default_rng(4)
    session = start(store, "free")
    assert FREE.next_position(session) == "1" and FREE.remaining(session) == []
    session = captured(store, session, *[direction_samples(d, rng) for d in directions[: FREE_FIT_FROM - 1]])
    assert FREE.next_position(session) == str(FREE_FIT_FROM)
    assert not FREE.solvable(session)
    progress = sessions.view(session)["progress"]
    assert progress["cv_error_mg"] is None
    assert progress["message"] == f"{FREE_FIT_FROM - 1} poses captured: 1 more before the first estimate"
    assert len(progress["advice"]) > 0 and all(a["gain"] is None for a in progress["advice"])
    with pytest.raises(
        InsufficientDataError, match=f"capture 1 more poses first: a free session solves from {FREE_FIT_FROM}"
    ):
        sessions.solve(store, session)
    session = captured(store, session, direction_samples(directions[FREE_FIT_FROM - 1], rng))
    assert FREE.solvable(session)
    progress, fit = FREE.progress_and_fit(session)
    assert fit is not None and progress["cv_error_mg"] == fit[0].metrics["cv_error_mg"]
    assert not progress["target_reached"]  # fewer than FREE_TARGET_MIN_POSES poses
    body = sessions.solve(store, session)
    assert body["method"] == "triangular" and body["finish"]["reason"] == "stopped"
    assert [c["position"] for c in body["captures"]] == [str(k) for k in range(1, FREE_FIT_FROM + 1)]


def test_free_refuses_a_pose_near_one_taken_and_a_position_out_of_turn(store):
    rng = np.random.default_rng(5)
    session = captured(store, start(store, "free"), direction_samples(up_vector("+z"), rng))
    tilt = np.radians(FREE_MIN_ANGLE_DEG / 2)
    with pytest.raises(PoseTooCloseError, match="from pose 1, already captured"):
        FREE.check(session, direction_samples([np.sin(tilt), 0.0, np.cos(tilt)], rng))
    with pytest.raises(CalibrationError, match="this capture is pose 2"):
        FREE.check(session, dict(direction_samples(up_vector("+x"), rng), position="3"))
    assert FREE.check(session, direction_samples(up_vector("+x"), rng))["position"] == "2"


def test_cube24_asks_for_the_positions_in_order(store):
    phone = phone_cube(3)
    session = start(store, "cube24")
    assert CUBE24.next_position(session) == "1" and len(CUBE24.remaining(session)) == 24
    with pytest.raises(CalibrationError, match="goes in order: this capture is position 1"):
        CUBE24.check(session, {**phone.capture(1), "position": "2"})
    session = captured(store, session, phone.capture(1), phone.capture(2), phone.capture(3))
    assert CUBE24.next_position(session) == "4"
    assert CUBE24.remaining(session) == [str(k) for k in range(4, 25)]
    assert not CUBE24.solvable(session)
    with pytest.raises(InsufficientDataError, match=r"capture 4, 5, .*, 24 first: the session has 3 of 24 positions"):
        sessions.solve(store, session)
    redone = CUBE24.check(session, {**phone.capture(3), "redo": True})  # the last one again, by the same turn
    assert redone["position"] == "3" and redone["turn"]["ok"]
    with pytest.raises(CalibrationError, match="needs the gyroscope"):
        CUBE24.check(session, {**phone.capture(4), "gyr": None})


def test_cube24_refuses_a_25th_position(store):
    phone = phone_cube(1)
    session = captured(store, start(store, "cube24"), *[phone.capture(k) for k in range(1, 25)])
    assert CUBE24.solvable(session) and CUBE24.next_position(session) is None
    with pytest.raises(ConflictError):
        CUBE24.check(session, phone.capture(24))


def test_the_terminal_s_labels_are_the_protocols_own():
    """What a still mean reading would be captured as by ``trical capture``, given the captures done."""
    z, x = G * up_vector("+z"), G * up_vector("+x")
    assert SIX.label(z, [], PAGE_MAX_ANGLE_DEG) == "+z"
    assert SIX.label(z, [("+z", up_vector("+z"))], PAGE_MAX_ANGLE_DEG) is None  # done already
    tilted = G * np.array([np.sin(np.radians(30)), 0.0, np.cos(np.radians(30))])
    assert SIX.label(tilted, [], PAGE_MAX_ANGLE_DEG) is None  # near no axis within the page's angle
    done = [("pose 1", up_vector("+z"))]
    near = G * np.array([np.sin(np.radians(FREE_MIN_ANGLE_DEG - 1)), 0.0, np.cos(np.radians(FREE_MIN_ANGLE_DEG - 1))])
    far = G * np.array([np.sin(np.radians(FREE_MIN_ANGLE_DEG + 1)), 0.0, np.cos(np.radians(FREE_MIN_ANGLE_DEG + 1))])
    assert FREE.label(near, done, PAGE_MAX_ANGLE_DEG) is None
    assert FREE.label(far, done, PAGE_MAX_ANGLE_DEG) == "pose 2"
    assert FREE.label(x, [], PAGE_MAX_ANGLE_DEG) == "pose 1"
    assert CUBE24.label(z, [("position 1", up_vector("+z"))] * 3, PAGE_MAX_ANGLE_DEG) == "position 4"
    assert (SIX.poses, FREE.poses, CUBE24.poses) == (6, FREE_TARGET_MIN_POSES, 24)
    assert [p.from_captures for p in (SIX, FREE, CUBE24)] == [True, True, False]
    compass, noise = BOARD_PROTOCOLS["compass"], BOARD_PROTOCOLS["noise"]
    assert compass.poses is None and noise.poses is None  # they record for a time, no capture engine
    assert (compass.command, compass.method) == ("calibrate", "magnetometer")
    assert (noise.command, noise.method) == ("noise", "noise")
    assert [BOARD_PROTOCOLS[p].minutes for p in CAPTURE_PROTOCOLS] == [10.0, 15.0, 10.0, 1.0, 1.0]
    assert [BOARD_PROTOCOLS[p].method for p in CAPTURE_PROTOCOLS] == ["auto", "cube", "auto", "magnetometer", "noise"]
