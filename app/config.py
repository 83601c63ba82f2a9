"""All settings in one place, read from TRICAL_* environment variables (DESIGN.md section 3)."""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

PROJECT_ROOT = Path(__file__).resolve().parent.parent
"""The checkout (or image) root holding static/ and templates/."""


class SettingsError(ValueError):
    """An environment variable holds a value that cannot be used."""


@dataclass(frozen=True)
class Settings:
    """trical's configuration.

    Attributes
    ----------
    database_url : str
        ``sqlite:///relative/or/absolute/path.db`` or ``postgresql://user:password@host/db``
        (TRICAL_DATABASE_URL).
    max_upload_mb : float
        Largest accepted upload in MiB (TRICAL_MAX_UPLOAD_MB).
    max_json_mb : float
        Largest accepted JSON request body in MiB (TRICAL_MAX_JSON_MB); refused with 413 before it is parsed.
    rate_limit_per_minute : float
        Requests per minute one client may make to /api/ (TRICAL_RATE_LIMIT_PER_MINUTE; 0 = off).
    api_keys : tuple of str
        When non-empty, every API call needs ``Authorization: Bearer <key>`` (TRICAL_API_KEYS).
    host, port : str or None, int
        Where ``trical serve`` and ``make run`` listen (HOST, PORT).  Without HOST, ``trical serve``
        listens on 127.0.0.1, and ``trical serve --https`` on 0.0.0.0 (a phone on the LAN must reach it).
    data_dir : pathlib.Path
        Where uploaded recordings and the generated TLS certificate are kept (TRICAL_DATA_DIR;
        default: beside the database).
    public_url : str or None
        The address the start page shows as a QR code for a phone (TRICAL_PUBLIC_URL); ``trical serve
        --https`` sets it to its LAN wizard address when unset.
    """

    database_url: str = "sqlite:///./var/trical.db"
    max_upload_mb: float = 512.0
    # The largest legitimate JSON bodies, measured with full-precision doubles as browsers send them:
    # a cube24 capture whose motion log spans a 4-minute session at 100 Hz, 3.2 MiB; six_position with
    # 10 000 readings and a holdout of 100 000, 6.7 MiB; triangular with 100 000 means and a holdout of
    # 100 000 (both at the schema's caps), 11.2 MiB. 16 MiB leaves room above all of them.
    max_json_mb: float = 16.0
    rate_limit_per_minute: float = 0.0
    api_keys: tuple[str, ...] = ()
    host: str | None = None
    port: int = 8000
    data_dir: Path | None = None
    public_url: str | None = None
    static_dir: Path = field(default=PROJECT_ROOT / "static")
    templates_dir: Path = field(default=PROJECT_ROOT / "templates")

    @property
    def is_sqlite(self) -> bool:
        return self.database_url.startswith("sqlite:///")

    @property
    def database_path(self) -> Path | None:
        """Filesystem path of the SQLite database, or None for PostgreSQL."""
        if self.is_sqlite:
            return Path(self.database_url[len("sqlite:///"):])
        if self.database_url.startswith(("postgresql://", "postgres://")):
            return None
        raise SettingsError(
            "TRICAL_DATABASE_URL must be sqlite:///path/to/trical.db or postgresql://user:password@host/db; "
            f"got {self.database_url!r}"
        )

    @property
    def data_base(self) -> Path:
        """TRICAL_DATA_DIR, else the SQLite file's directory, else ``./var``."""
        if self.data_dir is not None:
            return Path(self.data_dir)
        return self.database_path.parent if self.is_sqlite else Path("var")

    @property
    def recordings_dir(self) -> Path:
        """Directory of uploaded recordings (with PostgreSQL, this replica's cache of them)."""
        return self.data_base / "recordings"

    @property
    def tls_dir(self) -> Path:
        """Directory of the self-signed certificate and key that ``trical serve --https`` makes."""
        return self.data_base / "tls"

    @property
    def database_label(self) -> str:
        """The database for messages, without its password."""
        return str(self.database_path) if self.is_sqlite else re.sub(r"//([^:@/]+):[^@]*@", r"//\1:***@", self.database_url)

    @property
    def max_upload_bytes(self) -> int:
        return int(self.max_upload_mb * 1024 * 1024)

    @property
    def max_json_bytes(self) -> int:
        return int(self.max_json_mb * 1024 * 1024)

    @classmethod
    def from_env(cls, environ=None) -> "Settings":
        """Build the settings from the environment (``os.environ`` by default)."""
        env = os.environ if environ is None else environ
        kwargs: dict = {}
        if env.get("TRICAL_DATABASE_URL"):
            kwargs["database_url"] = env["TRICAL_DATABASE_URL"]
        if env.get("TRICAL_MAX_UPLOAD_MB"):
            try:
                kwargs["max_upload_mb"] = float(env["TRICAL_MAX_UPLOAD_MB"])
            except ValueError:
                raise SettingsError(f"TRICAL_MAX_UPLOAD_MB must be a number of MiB; got {env['TRICAL_MAX_UPLOAD_MB']!r}") from None
            if not kwargs["max_upload_mb"] > 0:
                raise SettingsError("TRICAL_MAX_UPLOAD_MB must be positive")
        if env.get("TRICAL_MAX_JSON_MB"):
            try:
                kwargs["max_json_mb"] = float(env["TRICAL_MAX_JSON_MB"])
            except ValueError:
                raise SettingsError(f"TRICAL_MAX_JSON_MB must be a number of MiB; got {env['TRICAL_MAX_JSON_MB']!r}") from None
            if not 0 < kwargs["max_json_mb"] < float("inf"):
                raise SettingsError("TRICAL_MAX_JSON_MB must be a positive, finite number of MiB")
        if env.get("TRICAL_RATE_LIMIT_PER_MINUTE"):
            try:
                kwargs["rate_limit_per_minute"] = float(env["TRICAL_RATE_LIMIT_PER_MINUTE"])
            except ValueError:
                raise SettingsError("TRICAL_RATE_LIMIT_PER_MINUTE must be a number of requests per minute") from None
            if kwargs["rate_limit_per_minute"] < 0:
                raise SettingsError("TRICAL_RATE_LIMIT_PER_MINUTE must be 0 (off) or positive")
        if env.get("TRICAL_API_KEYS"):
            kwargs["api_keys"] = tuple(k.strip() for k in env["TRICAL_API_KEYS"].split(",") if k.strip())
        if env.get("TRICAL_DATA_DIR"):
            kwargs["data_dir"] = Path(env["TRICAL_DATA_DIR"])
        if env.get("TRICAL_PUBLIC_URL"):
            kwargs["public_url"] = env["TRICAL_PUBLIC_URL"].strip()
            if not re.match(r"https?://[^\s/]+", kwargs["public_url"]):
                raise SettingsError(f"TRICAL_PUBLIC_URL must be an http:// or https:// address; "
                                    f"got {env['TRICAL_PUBLIC_URL']!r}")
        if env.get("HOST"):
            kwargs["host"] = env["HOST"]
        if env.get("PORT"):
            try:
                kwargs["port"] = int(env["PORT"])
            except ValueError:
                raise SettingsError(f"PORT must be an integer; got {env['PORT']!r}") from None
        settings = cls(**kwargs)
        settings.database_path  # validate the URL early
        return settings
