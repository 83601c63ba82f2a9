"""Settings from the environment (pydantic-settings): names, defaults, and one-line errors."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from app.config import Settings, SettingsError
from tests.live_server import ROOT


def test_defaults():
    s = Settings.from_env({})
    assert (
        s.database_url,
        s.max_upload_mb,
        s.max_json_mb,
        s.rate_limit_per_minute,
        s.api_keys,
        s.host,
        s.port,
        s.data_dir,
        s.public_url,
    ) == ("sqlite:///./var/trical.db", 512.0, 16.0, 0.0, (), None, 8000, None, None)
    assert s.is_sqlite and s.database_path == Path("var/trical.db") and s.recordings_dir == Path("var/recordings")
    assert s.tls_dir == Path("var/tls") and s.max_upload_bytes == 512 << 20 and s.max_json_bytes == 16 << 20


def test_every_variable_is_read():
    s = Settings.from_env(
        {
            "TRICAL_DATABASE_URL": "postgresql://trical:secret@db:5432/trical",
            "TRICAL_MAX_UPLOAD_MB": "2.5",
            "TRICAL_MAX_JSON_MB": "0.5",
            "TRICAL_RATE_LIMIT_PER_MINUTE": "60",
            "TRICAL_API_KEYS": " k1, k2,,",
            "HOST": "0.0.0.0",
            "PORT": "9000",
            "TRICAL_DATA_DIR": "/srv/data",
            "TRICAL_PUBLIC_URL": " https://x.lan ",
            "DATABASE_URL": "sqlite:///ignored.db",  # only the TRICAL_ names count
        }
    )
    assert s.database_path is None and not s.is_sqlite and s.database_label == "postgresql://trical:***@db:5432/trical"
    assert s.max_upload_bytes == int(2.5 * 2**20) and s.max_json_bytes == 2**19 and s.rate_limit_per_minute == 60
    assert s.api_keys == ("k1", "k2") and (s.host, s.port) == ("0.0.0.0", 9000)
    assert s.recordings_dir == Path("/srv/data/recordings") and s.public_url == "https://x.lan"


def test_empty_variables_count_as_unset():
    s = Settings.from_env(
        {"TRICAL_API_KEYS": "", "HOST": "", "PORT": "", "TRICAL_PUBLIC_URL": "", "TRICAL_MAX_JSON_MB": ""}
    )
    assert (s.api_keys, s.host, s.port, s.public_url, s.max_json_mb) == ((), None, 8000, None, 16.0)


def test_settings_built_in_code_ignore_the_environment(monkeypatch):
    monkeypatch.setenv("TRICAL_API_KEYS", "from-env")
    monkeypatch.setenv("PORT", "1234")
    s = Settings(api_keys=("k",), host="h")
    assert (s.api_keys, s.host, s.port) == (("k",), "h", 8000)
    assert Settings.from_env().api_keys == ("from-env",) and Settings.from_env().port == 1234


@pytest.mark.parametrize(
    "env, message",
    [
        ({"TRICAL_MAX_UPLOAD_MB": "lots"}, "TRICAL_MAX_UPLOAD_MB must be a positive number of MiB; got 'lots'"),
        ({"TRICAL_MAX_UPLOAD_MB": "0"}, "TRICAL_MAX_UPLOAD_MB must be a positive number of MiB; got '0'"),
        ({"TRICAL_MAX_JSON_MB": "-1"}, "TRICAL_MAX_JSON_MB must be a positive number of MiB; got '-1'"),
        ({"TRICAL_RATE_LIMIT_PER_MINUTE": "-5"}, "TRICAL_RATE_LIMIT_PER_MINUTE must be 0 (off) or a positive number"),
        ({"PORT": "eighty"}, "PORT must be an integer; got 'eighty'"),
        ({"TRICAL_PUBLIC_URL": "phone.local"}, "TRICAL_PUBLIC_URL must be an http:// or https:// address"),
        ({"TRICAL_DATABASE_URL": "mysql://db/trical"}, "TRICAL_DATABASE_URL must be sqlite:///path/to/trical.db or"),
    ],
)
def test_a_bad_value_is_one_line_naming_the_variable(env, message):
    with pytest.raises(SettingsError) as caught:
        Settings.from_env(env)
    assert str(caught.value).startswith(message) and "\n" not in str(caught.value)


def test_the_cli_prints_a_bad_setting_without_traceback(tmp_path):
    env = {
        "TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}",
        "TRICAL_MAX_JSON_MB": "big",
        "PATH": "/usr/bin:/bin",
    }
    out = subprocess.run(
        [sys.executable, "-m", "app.cli", "export", "cal_x"],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert out.stderr == "trical: error: TRICAL_MAX_JSON_MB must be a positive number of MiB; got 'big'\n"
