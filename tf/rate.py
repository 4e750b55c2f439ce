"""``tf.Rate``: keep a loop at a fixed frequency, as ``rospy.Rate`` does."""

from __future__ import annotations

import time

__all__ = ["Rate"]


class Rate:
    """Sleep so that a loop runs at ``hz`` iterations per second.

    Each :meth:`sleep` waits until one period after the previous wake-up. A loop that falls more
    than one period behind starts counting again from now instead of bursting to catch up (as
    ``rospy.Rate`` does when time jumps).

    Args:
        hz: Frequency in Hz (> 0).

    Example:
        >>> rate = Rate(10)
        >>> rate.sleep()  # returns about 0.1 s after the Rate was made
    """

    def __init__(self, hz: float) -> None:
        if not hz > 0:
            raise ValueError(f"Rate needs a positive frequency, got {hz!r}")
        self.period = 1.0 / float(hz)
        self._last = time.monotonic()

    def sleep(self) -> None:
        """Sleep for the rest of the current period."""
        target = self._last + self.period
        now = time.monotonic()
        if now < target:
            time.sleep(target - now)
            self._last = target
        elif now - target > self.period:
            self._last = now
        else:
            self._last = target
