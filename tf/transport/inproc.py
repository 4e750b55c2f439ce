"""The in-process transport: publishers hand message objects directly to subscribers' callbacks.

Delivery is synchronous, in the publishing thread, outside the transport's lock (messages are
immutable, so they are shared, not copied). A latched publisher's last message is delivered to
subscribers that join later, in the subscribing thread.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from typing import Any, TypeVar

from ._base import Publisher, Subscription, Transport

__all__ = ["InProcessTransport"]

M = TypeVar("M")
_log = logging.getLogger("tf.transport")
_WARN_INTERVAL_S = 5.0


class _Sub(Subscription):
    def __init__(
        self, bus: InProcessTransport, topic: str, msg_type: type, callback: Callable[[Any], Any]
    ) -> None:
        self.topic = topic
        self.msg_type = msg_type
        self.callback = callback
        self._bus = bus
        self.closed = False

    def close(self) -> None:
        if not self.closed:
            self.closed = True
            self._bus._remove_subscription(self)


class _Pub(Publisher[M]):
    def __init__(self, bus: InProcessTransport, topic: str, msg_type: type[M], latched: bool) -> None:
        self.topic = topic
        self.msg_type = msg_type
        self.latched = latched
        self.last: M | None = None
        self._bus = bus
        self.closed = False

    def publish(self, msg: M) -> None:
        if self.closed:
            return
        if not isinstance(msg, self.msg_type):
            raise TypeError(
                f"publisher on {self.topic} sends {self.msg_type.__name__}, got {type(msg).__name__}"
            )
        self._bus._deliver(self, msg)

    def close(self) -> None:
        if not self.closed:
            self.closed = True
            self._bus._remove_publisher(self)


class InProcessTransport(Transport):
    """A message bus inside one process: any number of publishers, subscribers and threads."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._subs: dict[str, tuple[_Sub, ...]] = {}
        self._latched: dict[str, list[_Pub[Any]]] = {}
        self._closed = False
        self._last_warning = 0.0

    def publisher(self, topic: str, msg_type: type[M], *, latched: bool = False) -> Publisher[M]:
        """Create a publisher on ``topic`` (``latched``: late subscribers get its last message)."""
        pub: _Pub[M] = _Pub(self, topic, msg_type, latched)
        with self._lock:
            if self._closed:
                pub.closed = True
            elif latched:
                self._latched.setdefault(topic, []).append(pub)
        return pub

    def subscribe(self, topic: str, msg_type: type[M], callback: Callable[[M], Any]) -> Subscription:
        """Call ``callback(msg)`` for every ``msg_type`` message on ``topic``, latched ones first."""
        sub = _Sub(self, topic, msg_type, callback)
        with self._lock:
            if self._closed:
                sub.closed = True
                return sub
            self._subs[topic] = (*self._subs.get(topic, ()), sub)
            backlog = [p.last for p in self._latched.get(topic, ()) if p.last is not None]
        for msg in backlog:
            if isinstance(msg, msg_type):
                self._call(sub, msg)
        return sub

    def close(self) -> None:
        """Close every publisher and subscription; later calls do nothing."""
        with self._lock:
            self._closed = True
            subs = [s for group in self._subs.values() for s in group]
            pubs = [p for group in self._latched.values() for p in group]
            self._subs.clear()
            self._latched.clear()
        for s in subs:
            s.closed = True
        for p in pubs:
            p.closed = True

    # -------------------------------------------------------------- internals
    def _deliver(self, pub: _Pub[Any], msg: Any) -> None:
        with self._lock:
            if pub.latched:
                pub.last = msg
            subs = self._subs.get(pub.topic, ())
        for sub in subs:
            if not sub.closed and isinstance(msg, sub.msg_type):
                self._call(sub, msg)

    def _call(self, sub: _Sub, msg: Any) -> None:
        try:
            sub.callback(msg)
        except Exception:
            now = time.monotonic()
            if now - self._last_warning >= _WARN_INTERVAL_S:
                self._last_warning = now
                _log.warning("subscriber callback on %s raised; delivery continues", sub.topic, exc_info=True)

    def _remove_subscription(self, sub: _Sub) -> None:
        with self._lock:
            remaining = tuple(s for s in self._subs.get(sub.topic, ()) if s is not sub)
            if remaining:
                self._subs[sub.topic] = remaining
            else:
                self._subs.pop(sub.topic, None)

    def _remove_publisher(self, pub: _Pub[Any]) -> None:
        with self._lock:
            group = self._latched.get(pub.topic)
            if group and pub in group:
                group.remove(pub)
