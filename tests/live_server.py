"""A real trical server in a subprocess on a free loopback port (real HTTP, real SQLite file)."""

from __future__ import annotations

import os
import signal
import socket
import ssl
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

import httpx

from tests.processes import ProcessFailed

ROOT = Path(__file__).resolve().parent.parent


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LiveServer:
    """``trical serve`` as a child process; ``kill()`` sends SIGKILL, ``start()`` starts it again.

    With ``https_ca`` (the PEM certificate the server will present, possibly written only once it runs)
    the server is polled over HTTPS and verified against that certificate.
    """

    def __init__(
        self, env: dict, port: int | None = None, command: list[str] | None = None, https_ca: Path | None = None
    ):
        self.port = port or free_port()
        self.https_ca = https_ca
        self.url = f"{'https' if https_ca else 'http'}://127.0.0.1:{self.port}"
        # No phone's door unless a test opens one (TRICAL_PHONE_PORT): parallel servers would share its port.
        self.env = {**os.environ, "TRICAL_PHONE_PORT": "0", **env}
        self.command = command or [
            sys.executable,
            "-m",
            "app.cli",
            "serve",
            "--host",
            "127.0.0.1",
            "--port",
            str(self.port),
        ]
        self.process: subprocess.Popen | None = None
        self.log = Path(tempfile.mkstemp(prefix="trical-server-", suffix=".log")[1])

    def start(self, timeout_s: float = 60.0) -> LiveServer:
        with open(self.log, "ab") as out:
            self.process = subprocess.Popen(self.command, cwd=ROOT, env=self.env, stdout=out, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + timeout_s
        # One client for the polls (a new one each poll built its TLS context again, loading the CA bundle: tens of
        # ms of CPU a poll, some 20 polls a start); over HTTPS made again after a failed poll, as the certificate
        # the server presents may be written or replaced meanwhile.
        client: httpx.Client | None = None
        try:
            while time.monotonic() < deadline:
                if self.process.poll() is not None:
                    raise RuntimeError(f"the server exited with status {self.process.returncode}:\n{self.output()}")
                if self.https_ca and not Path(self.https_ca).exists():
                    time.sleep(0.1)
                    continue
                try:
                    client = client or httpx.Client(timeout=1.0, verify=self.verify())
                    if client.get(f"{self.url}/healthz").status_code == 200:
                        return self
                except (httpx.HTTPError, ssl.SSLError):  # not listening yet, or the certificate half written
                    if self.https_ca and client is not None:  # the certificate may be another by the next poll
                        client.close()
                        client = None
                    time.sleep(0.1)
        finally:
            if client is not None:
                client.close()
        self.stop()
        raise RuntimeError(f"the server did not answer /healthz within {timeout_s} s:\n{self.output()}")

    def verify(self) -> ssl.SSLContext | bool:
        """What httpx should verify the server with: its certificate for HTTPS."""
        return ssl.create_default_context(cafile=str(self.https_ca)) if self.https_ca else True

    def output(self) -> str:
        """The tail of what the server printed."""
        return self.log.read_text(errors="replace")[-4000:]

    def check_alive(self, when: str) -> None:
        """Fail loudly, with the end of the server's log, when it is no longer running."""
        if self.process is None or self.process.poll() is not None:
            status = "never started" if self.process is None else f"exited with status {self.process.returncode}"
            raise ProcessFailed(f"the trical server on port {self.port} {status} {when}:\n{self.output()}")

    def kill(self) -> None:
        """SIGKILL, as a crash or power loss would end it."""
        if self.process and self.process.poll() is None:
            self.process.send_signal(signal.SIGKILL)
            self.process.wait(timeout=10)

    def stop(self) -> None:
        if self.process and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.kill()


@contextmanager
def live_server(env: dict, **kwargs):
    server = LiveServer(env, **kwargs).start()
    try:
        yield server
    finally:
        server.stop()
