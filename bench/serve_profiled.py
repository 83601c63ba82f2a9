"""``trical serve`` in one process under cProfile, every thread of it: where a server's CPU time goes.

    python bench/serve_profiled.py --port 8765 --out server.prof

Serves ``app.main:app`` with uvicorn as ``trical serve`` does (one process, its event loop in the main
thread, the sync routes in AnyIO's worker threads). Each thread gets its own profiler that counts the
thread's CPU time (``time.thread_time``), so a thread waiting for the GIL or for work is not counted.
On SIGTERM or Ctrl-C uvicorn stops, the threads' profiles are merged and written to ``--out``
(read it with ``python -m pstats`` or bench/load_six.py's ``--profile``). The profiler slows the
server several times over: its figures are shares, never timings.
"""

from __future__ import annotations

import argparse
import cProfile
import signal
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

PROFILES: list[cProfile.Profile] = []


def _profile_thread(frame, event, arg):
    # Called once, on a new thread's first event: the thread's own profiler replaces this hook.
    profile = cProfile.Profile(time.thread_time)
    PROFILES.append(profile)
    profile.enable()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()

    import uvicorn

    from app.main import create_app

    # uvicorn stops on SIGTERM, then raises it again under the handler found before it: a handler that
    # does nothing lets uvicorn.run return, and the profile be written.
    signal.signal(signal.SIGTERM, lambda _signum, _frame: None)
    application = create_app()  # built before profiling: startup is not a request's cost
    threading.setprofile(_profile_thread)
    main_profile = cProfile.Profile(time.thread_time)
    PROFILES.append(main_profile)
    main_profile.enable()
    try:
        uvicorn.run(application, host=args.host, port=args.port, log_level="info")
    finally:
        main_profile.disable()
        threading.setprofile(None)  # type: ignore[arg-type]  # None removes the hook
        first, *rest = PROFILES
        first.create_stats()
        import pstats

        stats = pstats.Stats(first)
        for profile in rest:
            profile.create_stats()
            stats.add(profile)
        stats.dump_stats(args.out)


if __name__ == "__main__":
    main()
