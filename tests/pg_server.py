"""A real, temporary PostgreSQL server (Debian's package) for the storage tests.

`make test` installs Debian's postgresql when it is missing; without it the tests that need it fail
loudly. The cluster lives in a temporary directory, listens on a free loopback port with trust
authentication, and is removed afterwards. PostgreSQL refuses to run as root, so as root the
server runs as the `postgres` user the package creates.
"""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

from tests.live_server import free_port
from tests.processes import ProcessFailed, failure, run_ok


def pg_bin() -> Path:
    found = sorted(glob.glob("/usr/lib/postgresql/*/bin/initdb"))
    if not found:
        raise RuntimeError(
            "PostgreSQL is not installed (no /usr/lib/postgresql/*/bin/initdb): "
            "run `make test`, which installs Debian's postgresql"
        )
    return Path(found[-1]).parent


def _as_server_user(cmd: list[str]) -> list[str]:
    return ["runuser", "-u", "postgres", "--", *cmd] if os.geteuid() == 0 else cmd


START_TIMEOUT_S = 60  # initdb, and pg_ctl's wait for the server to accept connections
CONNECT_TIMEOUT_S = 10


class PostgresServer:
    """A running temporary server; ``new_database()`` gives the URL of a fresh, empty database."""

    def __init__(self, base_url: str, log: Path):
        self.base_url = base_url
        self.log = log
        self._count = 0

    def new_database(self) -> str:
        import psycopg

        self._count += 1
        name = f"trical_{self._count}"
        try:
            with psycopg.connect(f"{self.base_url}/postgres", autocommit=True, connect_timeout=CONNECT_TIMEOUT_S) as db:
                db.execute(f"CREATE DATABASE {name}")
        except psycopg.OperationalError as exc:  # the server is gone or does not answer: say what it logged
            raise failure("PostgreSQL", f"refused a new database ({exc})", self.log) from None
        return f"{self.base_url}/{name}"


@contextmanager
def postgres_server():
    """Yield a :class:`PostgresServer` on a free loopback port, removed afterwards."""
    bindir = pg_bin()
    root = Path(tempfile.mkdtemp(prefix="trical-pg-"))
    data, sock = root / "data", root / "sock"
    sock.mkdir()
    if os.geteuid() == 0:
        shutil.chown(root, "postgres")
        shutil.chown(sock, "postgres")
    port = free_port()
    log = root / "server.log"
    try:
        run_ok(
            _as_server_user([str(bindir / "initdb"), "-D", str(data), "-A", "trust", "-U", "postgres", "-E", "UTF8"]),
            timeout_s=START_TIMEOUT_S,
        )
        try:
            run_ok(
                _as_server_user(
                    [
                        str(bindir / "pg_ctl"),
                        "-D",
                        str(data),
                        "-l",
                        str(log),
                        "-w",
                        "-t",
                        str(START_TIMEOUT_S),
                        "-o",
                        f"-p {port} -k {sock} -h 127.0.0.1 -c fsync=on -c synchronous_commit=on",
                        "start",
                    ]
                ),
                timeout_s=START_TIMEOUT_S + 10,
            )
        except ProcessFailed as exc:
            raise failure("PostgreSQL", f"did not start ({exc})", log) from None
        deadline = time.monotonic() + START_TIMEOUT_S
        while (
            subprocess.run(
                [str(bindir / "pg_isready"), "-h", "127.0.0.1", "-p", str(port)],
                capture_output=True,
                timeout=CONNECT_TIMEOUT_S + 5,
            ).returncode
            != 0
        ):
            if time.monotonic() > deadline:
                raise failure("PostgreSQL", f"did not accept connections within {START_TIMEOUT_S} s", log)
            time.sleep(0.2)
        yield PostgresServer(f"postgresql://postgres@127.0.0.1:{port}", log)
    finally:
        subprocess.run(
            _as_server_user([str(bindir / "pg_ctl"), "-D", str(data), "-m", "immediate", "stop"]),
            capture_output=True,
            timeout=60,
        )
        shutil.rmtree(root, ignore_errors=True)
