"""The external processes the tests start (Xvfb, WebKitWebDriver, PostgreSQL, trical servers): each
has a start timeout, a check that it still runs when it is used, and on failure a message with the
last lines it printed, so that nothing the suite starts can hang it or fail it in silence."""

from __future__ import annotations

import os
import select
import subprocess
import tempfile
import time
from pathlib import Path

TAIL_LINES = 25


class ProcessFailed(RuntimeError):
    """An external process did not start, or stopped while it was still needed."""


def tail(path: Path, lines: int = TAIL_LINES) -> str:
    """The last `lines` lines of a log file (empty when there is none)."""
    try:
        text = Path(path).read_text(errors="replace")
    except OSError:
        return ""
    return "\n".join(text.rstrip().splitlines()[-lines:])


def failure(name: str, what: str, log: Path) -> ProcessFailed:
    """An error naming the process and what went wrong, with the end of its output."""
    said = tail(log)
    return ProcessFailed(f"{name} {what}; its last output ({log}):\n{said or '(nothing)'}")


def check_alive(name: str, process: subprocess.Popen, log: Path, when: str) -> None:
    """Fail loudly, with the process's last output, when it has exited."""
    if process.poll() is not None:
        raise failure(name, f"exited with status {process.returncode} {when}", log)


def stop(process: subprocess.Popen, timeout_s: float = 10.0) -> None:
    """SIGTERM, then SIGKILL when it has not exited within `timeout_s`."""
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=timeout_s)


def read_line(fd: int, timeout_s: float) -> bytes:
    """Read from `fd` up to a newline or end of file, waiting at most `timeout_s` in all.

    A writer may send a line in several writes (Xvfb writes the display number and its newline
    separately): one read can return the first part only, and closing the pipe then makes the
    writer's next write fail. Returns what was read (without waiting further once the newline came).
    """
    deadline = time.monotonic() + timeout_s
    data = b""
    while not data.endswith(b"\n"):
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            break
        ready, _, _ = select.select([fd], [], [], remaining)
        if not ready:
            break
        chunk = os.read(fd, 64)
        if not chunk:  # end of file: the writer closed the pipe (or exited)
            break
        data += chunk
    return data


def start_xvfb(xvfb: str, timeout_s: float = 20.0) -> tuple[subprocess.Popen, str, Path]:
    """Start Xvfb on a display number it picks itself (``-displayfd``).

    Returns the process, the display (``":N"``) and the log file its output goes to. Raises
    :class:`ProcessFailed` with Xvfb's own last lines when it exits or writes no number in time.
    """
    log = Path(tempfile.mkstemp(prefix="trical-xvfb-", suffix=".log")[1])
    read, write = os.pipe()
    try:
        with open(log, "ab") as out:
            process = subprocess.Popen(
                [xvfb, "-displayfd", str(write), "-screen", "0", "1400x6000x24", "-nolisten", "tcp"],
                pass_fds=(write,),
                stdin=subprocess.DEVNULL,
                stdout=out,
                stderr=subprocess.STDOUT,
            )
        os.close(write)
        write = -1
        line = read_line(read, timeout_s)
    finally:
        if write >= 0:
            os.close(write)
        os.close(read)
    number = line.decode(errors="replace").strip()
    if not line.endswith(b"\n") or not number.isdigit():
        stop(process)
        raise failure("Xvfb", f"wrote no display number within {timeout_s:g} s (it wrote {line!r})", log)
    check_alive("Xvfb", process, log, "right after it wrote its display number")
    return process, f":{number}", log


def run_ok(command: list[str], *, timeout_s: float, **kwargs) -> subprocess.CompletedProcess:
    """Run `command` to its end within `timeout_s`, capturing its output as text; a non-zero status or
    a run past the bound raises :class:`ProcessFailed` with the end of what it wrote to stderr."""
    name = Path(str(command[0])).name
    try:
        out = subprocess.run(command, capture_output=True, text=True, timeout=timeout_s, **kwargs)
    except subprocess.TimeoutExpired as exc:
        said = exc.stderr.decode(errors="replace") if isinstance(exc.stderr, bytes) else (exc.stderr or "")
        raise ProcessFailed(
            f"{name} did not finish within {timeout_s:g} s; its stderr:\n{said[-3000:] or '(nothing)'}"
        ) from None
    if out.returncode != 0:
        raise ProcessFailed(
            f"{name} exited with status {out.returncode}; its stderr:\n{out.stderr[-3000:] or '(nothing)'}"
        )
    return out
