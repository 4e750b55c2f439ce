"""The transport interface: topics carrying message objects between publishers and subscribers.

A transport moves *message objects* (``tf.messages.TFMessage``, ``tf.messages.JointState``) on
named topics (``/tf``, ``/tf_static``, ``/joint_states``). The in-process transport hands the
objects over directly; the Zenoh transport serializes them as ROS 2 CDR.

Contract every implementation keeps:
- ``publisher(topic, msg_type, latched=...)`` returns a :class:`Publisher`. A *latched* publisher's
  last message is delivered to every subscriber that joins later (ROS "transient local"), which
  is how ``/tf_static`` reaches late listeners.
- ``subscribe(topic, msg_type, callback)`` returns a :class:`Subscription`. Callbacks receive one
  message object; they are never called while a transport lock is held. A callback that raises
  is reported (rate-limited warning) and does not stop delivery to other subscribers.
- ``close()`` releases everything; publishers and subscriptions of a closed transport do nothing.
- Transports are context managers.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import Any, Generic, TypeVar

__all__ = ["Publisher", "Subscription", "Transport"]

M = TypeVar("M")


class Publisher(ABC, Generic[M]):
    """Sends messages of one type on one topic."""

    topic: str

    @abstractmethod
    def publish(self, msg: M) -> None:
        """Send one message to every current (and, if latched, future) subscriber."""

    @abstractmethod
    def close(self) -> None:
        """Stop publishing; a latched message is withdrawn."""

    def __enter__(self) -> Publisher[M]:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class Subscription(ABC):
    """A live subscription; ``close()`` stops the callbacks."""

    topic: str

    @abstractmethod
    def close(self) -> None:
        """Stop receiving messages."""

    def __enter__(self) -> Subscription:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class Transport(ABC):
    """A message bus: the in-process one or the Zenoh one."""

    @abstractmethod
    def publisher(self, topic: str, msg_type: type[M], *, latched: bool = False) -> Publisher[M]:
        """Create a publisher on ``topic`` for messages of ``msg_type``."""

    @abstractmethod
    def subscribe(self, topic: str, msg_type: type[M], callback: Callable[[M], Any]) -> Subscription:
        """Call ``callback(msg)`` for every message of ``msg_type`` on ``topic``."""

    @abstractmethod
    def close(self) -> None:
        """Close every publisher and subscription of this transport."""

    def __enter__(self) -> Transport:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
