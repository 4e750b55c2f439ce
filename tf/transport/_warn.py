"""Rate-limited warnings: one log line per reason per interval, with a count of what was suppressed."""

from __future__ import annotations

import logging
import threading
import time

__all__ = ["RateLimitedWarning"]


class RateLimitedWarning:
    """Logs a warning for a reason at most once every ``interval_s`` seconds.

    Args:
        logger: Where to log.
        interval_s: Minimum time between two lines for the same reason.
    """

    def __init__(self, logger: logging.Logger, interval_s: float = 5.0) -> None:
        self._logger = logger
        self._interval_s = interval_s
        self._lock = threading.Lock()
        self._last: dict[str, float] = {}
        self._suppressed: dict[str, int] = {}

    def warn(self, reason: str, message: str, *args: object, exc_info: bool = False) -> None:
        """Log ``message % args`` unless ``reason`` was logged less than ``interval_s`` ago."""
        now = time.monotonic()
        with self._lock:
            last = self._last.get(reason)
            if last is not None and now - last < self._interval_s:
                self._suppressed[reason] = self._suppressed.get(reason, 0) + 1
                return
            self._last[reason] = now
            suppressed = self._suppressed.pop(reason, 0)
        if suppressed:
            message = f"{message} ({suppressed} similar suppressed)"
        self._logger.warning(message, *args, exc_info=exc_info)
