"""All settings in one place, read from TRICAL_* environment variables (docs/rest.md)."""

from __future__ import annotations

import os
import re
from collections.abc import Mapping
from pathlib import Path

from pydantic import Field, ValidationError, field_validator
from pydantic_settings import BaseSettings, EnvSettingsSource, SettingsConfigDict
from pydantic_settings import SettingsError as SourceError

PROJECT_ROOT = Path(__file__).resolve().parent.parent
"""The checkout (or image) root holding static/ and templates/."""

SQLITE_PREFIX = "sqlite:///"
POSTGRES_PREFIXES = ("postgresql://", "postgres://", "postgresql+psycopg://")
"""The TRICAL_DATABASE_URL forms trical opens (app.store.engine)."""


def database_url_problem(database_url: str) -> str | None:
    """Why ``database_url`` cannot be used, or None when it can."""
    if database_url.startswith(POSTGRES_PREFIXES) or (
        database_url.startswith(SQLITE_PREFIX) and len(database_url) > len(SQLITE_PREFIX)
    ):
        return None
    return "must be sqlite:///path/to/trical.db or postgresql://user:password@host/db"


def sqlite_path(database_url: str) -> Path | None:
    """The file of a ``sqlite:///path`` URL, or None for PostgreSQL."""
    return Path(database_url[len(SQLITE_PREFIX) :]) if database_url.startswith(SQLITE_PREFIX) else None


class SettingsError(ValueError):
    """An environment variable holds a value that cannot be used."""


HINTS = {
    "database_url": database_url_problem(""),
    "max_upload_mb": "must be a positive number of MiB",
    "max_json_mb": "must be a positive number of MiB",
    "rate_limit_per_minute": "must be 0 (off) or a positive number of requests per minute",
    "port": "must be an integer",
    "public_url": "must be an http:// or https:// address",
    "phone_port": "must be a TCP port, or 0 for no phone's door",
}
"""What each setting must be, for the one-line message of a bad value."""


class Settings(BaseSettings):
    """trical's configuration.

    ``Settings.from_env()`` reads it from the environment (empty variables count as unset);
    ``Settings(field=value, …)`` builds it from the values given and the defaults only.

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
        When non-empty, every API call needs ``Authorization: Bearer <key>`` (TRICAL_API_KEYS,
        comma-separated).
    host, port : str or None, int
        Where ``trical serve`` and ``make run`` listen (HOST, PORT); without HOST, on 127.0.0.1 (over TLS too with
        ``--https``): the desktop's listener. A phone comes in through the phone's door (``phone_port``).
    data_dir : pathlib.Path
        Where uploaded recordings and the generated TLS certificate are kept (TRICAL_DATA_DIR;
        default: beside the database).
    public_url : str or None
        The address the start page shows as a QR code for a phone (TRICAL_PUBLIC_URL, e.g. a reverse proxy's);
        unset, the phone's door's.
    phone_port : int
        Where ``trical serve`` opens the phone's door (TRICAL_PHONE_PORT): HTTPS on every interface for the phone
        that scanned the start page's code only (app.reach.phone_door); 0 opens none, and so does a
        TRICAL_PUBLIC_URL.
    free_target_mg : float
        The cross-validated error (mg of g) that ends a free wizard session (TRICAL_FREE_TARGET_MG),
        unless the session sets its own ``target_mg``.
    link_ttl_min : float
        How long a calibration's short link, sent from the phone to a computer, reads it
        (TRICAL_LINK_TTL_MIN).
    """

    model_config = SettingsConfigDict(
        env_prefix="TRICAL_", env_ignore_empty=True, frozen=True, populate_by_name=True, extra="forbid"
    )

    database_url: str = "sqlite:///./var/trical.db"
    max_upload_mb: float = Field(512.0, gt=0)
    # The largest legitimate JSON bodies, measured with full-precision doubles as browsers send them:
    # a cube24 capture whose motion log spans a 4-minute session at 100 Hz, 3.2 MiB; six_position with
    # 10 000 readings and a holdout of 100 000, 6.7 MiB; triangular with 100 000 means and a holdout of
    # 100 000 (both at the schema's caps), 11.2 MiB. 16 MiB leaves room above all of them.
    max_json_mb: float = Field(16.0, gt=0, allow_inf_nan=False)
    rate_limit_per_minute: float = Field(0.0, ge=0)
    api_keys: tuple[str, ...] = ()
    host: str | None = Field(None, validation_alias="HOST")
    port: int = Field(8000, validation_alias="PORT")
    data_dir: Path | None = None
    public_url: str | None = None
    phone_port: int = Field(8443, ge=0, le=65535)
    free_target_mg: float = Field(2.0, gt=0, le=1000, allow_inf_nan=False)
    link_ttl_min: float = Field(60.0, gt=0, le=7 * 24 * 60, allow_inf_nan=False)
    static_dir: Path = PROJECT_ROOT / "static"
    templates_dir: Path = PROJECT_ROOT / "templates"

    @classmethod
    def settings_customise_sources(
        cls, settings_cls, init_settings, env_settings, dotenv_settings, file_secret_settings
    ):
        # The environment is read by from_env alone, so that Settings(...) is what it says.
        return (init_settings,)

    @field_validator("database_url")
    @classmethod
    def _known_database(cls, value: str) -> str:
        problem = database_url_problem(value)
        if problem is not None:
            raise ValueError(problem)
        return value

    @field_validator("public_url")
    @classmethod
    def _web_address(cls, value: str | None) -> str | None:
        if value is not None:
            value = value.strip()
            if not re.match(r"https?://[^\s/]+", value):
                raise ValueError(HINTS["public_url"])
        return value

    @property
    def is_sqlite(self) -> bool:
        return sqlite_path(self.database_url) is not None

    @property
    def database_path(self) -> Path | None:
        """Filesystem path of the SQLite database, or None for PostgreSQL."""
        return sqlite_path(self.database_url)

    @property
    def data_base(self) -> Path:
        """TRICAL_DATA_DIR, else the SQLite file's directory, else ``./var``."""
        if self.data_dir is not None:
            return Path(self.data_dir)
        path = self.database_path  # the SQLite file's, None for PostgreSQL
        return path.parent if path is not None else Path("var")

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
        return (
            str(self.database_path)
            if self.is_sqlite
            else re.sub(r"//([^:@/]+):[^@]*@", r"//\1:***@", self.database_url)
        )

    @property
    def max_upload_bytes(self) -> int:
        return int(self.max_upload_mb * 1024 * 1024)

    @property
    def max_json_bytes(self) -> int:
        return int(self.max_json_mb * 1024 * 1024)

    @classmethod
    def from_env(cls, environ: Mapping[str, str] | None = None) -> Settings:
        """Build the settings from the environment (``os.environ`` by default).

        Raises
        ------
        SettingsError
            A variable holds a value that cannot be used; the message is one line naming it.
        """
        try:
            return cls(**_Environment(cls, os.environ if environ is None else environ)())
        except ValidationError as exc:
            raise SettingsError(_one_line(exc)) from None
        except SourceError as exc:
            raise SettingsError(str(exc)) from None


class _Environment(EnvSettingsSource):
    """pydantic-settings' reading of TRICAL_* (and HOST, PORT) from a given mapping; TRICAL_API_KEYS
    is comma-separated rather than JSON."""

    def __init__(self, settings_cls: type[Settings], environ: Mapping[str, str]):
        super().__init__(settings_cls)
        self.env_vars = {(k if self.case_sensitive else k.lower()): v for k, v in environ.items() if v != ""}

    def prepare_field_value(self, field_name, field, value, value_is_complex):
        if field_name == "api_keys" and isinstance(value, str):
            return tuple(k.strip() for k in value.split(",") if k.strip())
        return super().prepare_field_value(field_name, field, value, value_is_complex)


def _variable(field: str) -> str:
    alias = Settings.model_fields[field].validation_alias if field in Settings.model_fields else None
    return alias if isinstance(alias, str) else f"TRICAL_{field.upper()}"


def _one_line(exc: ValidationError) -> str:
    """The first problem of a ValidationError as ``VARIABLE must be …; got '…'``."""
    problems = []
    for error in exc.errors():
        field = str(error["loc"][0]) if error["loc"] else ""
        field = next((name for name, info in Settings.model_fields.items() if info.validation_alias == field), field)
        hint = HINTS.get(field, error["msg"].lower())
        problems.append(f"{_variable(field)} {hint}; got {error.get('input')!r}")
    return "; ".join(problems)
