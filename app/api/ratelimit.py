"""A per-client request rate limit on /api/ (TRICAL_RATE_LIMIT_PER_MINUTE; off when 0).

A token bucket per client — its verified identity (a valid API key or wizard session token, see
app.api.deps.verified_identity), else its address — holding a minute's worth of requests and refilled
continuously. Each replica keeps its own buckets; nginx's limit_req (deploy/nginx.conf) caps each
address in front of them.
"""

from __future__ import annotations

import math
import threading
import time


class RateLimiter:
    """Token buckets of ``per_minute`` requests, refilled at ``per_minute / 60`` per second."""

    def __init__(self, per_minute: float, *, max_clients: int = 100_000):
        self.capacity = float(per_minute)
        self.refill_per_s = self.capacity / 60.0
        self.max_clients = max_clients
        self._buckets: dict[str, tuple[float, float]] = {}
        self._lock = threading.Lock()

    def acquire(self, client: str, now: float | None = None) -> float:
        """Take one token; returns 0 when allowed, else the seconds until a token is back."""
        now = time.monotonic() if now is None else now
        with self._lock:
            tokens, last = self._buckets.get(client, (self.capacity, now))
            tokens = min(self.capacity, tokens + (now - last) * self.refill_per_s)
            if tokens >= 1.0:
                self._buckets[client] = (tokens - 1.0, now)
                wait = 0.0
            else:
                self._buckets[client] = (tokens, now)
                wait = (1.0 - tokens) / self.refill_per_s
            if len(self._buckets) > self.max_clients:  # forget the fullest buckets first
                for key, _ in sorted(self._buckets.items(), key=lambda kv: -kv[1][0])[: self.max_clients // 10]:
                    del self._buckets[key]
        return wait


def retry_after(wait_s: float) -> str:
    return str(max(1, math.ceil(wait_s)))
