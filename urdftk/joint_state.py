"""``JointStatePublisher``: publishes a robot's joint positions on ``/joint_states``.

As ROS's joint_state_publisher:

- every independent joint starts at 0 clamped into its limits (``zeros`` overrides, by name);
- messages on the ``source_list`` topics override the joints they name (later messages win);
- mimic joints are published from their masters (``value = multiplier * master + offset``);
- continuous joints are published as one angle (radians), never as cos/sin;
- one ``sensor_msgs/JointState`` at ``rate`` Hz, stamped with the current time.

Call :meth:`start` to publish periodically in a background thread, or :meth:`publish` yourself.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from tf.messages import Header, JointState, Time
from tf.transport import TOPIC_JOINT_STATES, Subscription, Transport, default_transport
from tf.transport._warn import RateLimitedWarning
from urdftk.errors import JointNotFound

if TYPE_CHECKING:
    from urdftk.model import Robot

__all__ = ["JointStatePublisher"]

_log = logging.getLogger("urdftk.joint_state")


class JointStatePublisher:
    """Publishes the joint positions of ``robot``.

    Args:
        robot: The robot (``urdftk.load(...)``).
        transport: Where to publish; None uses ``tf.transport.default_transport()``.
        rate: Publishing rate in Hz for :meth:`start`.
        source_list: Topics whose JointState messages set joint values.
        zeros: Initial values by joint name (mimic followers are not settable).

    Raises:
        JointNotFound: ``zeros`` names a joint the robot does not have.
        ValueError: ``rate`` is not positive.
    """

    def __init__(
        self,
        robot: Robot,
        transport: Transport | None = None,
        *,
        rate: float = 10.0,
        source_list: Iterable[str] = (),
        zeros: Mapping[str, float] | None = None,
    ) -> None:
        if not rate > 0:
            raise ValueError(f"rate must be > 0 Hz, got {rate}")
        self.robot = robot
        self.rate = float(rate)
        self._transport = transport if transport is not None else default_transport()
        self._warn = RateLimitedWarning(_log)
        self._lock = threading.Lock()
        self._index = {name: i for i, name in enumerate(robot.joint_names)}
        q = robot.neutral()
        if zeros:
            q = robot.q(dict(zeros), clip=True)
        self._q = q
        self._pub = self._transport.publisher(TOPIC_JOINT_STATES, JointState)
        self._subs: list[Subscription] = [
            self._transport.subscribe(topic, JointState, self._on_source) for topic in source_list
        ]
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    # ------------------------------------------------------------------ state
    def set_positions(self, values: Mapping[str, float]) -> None:
        """Set independent joints by name (clamped into their limits).

        Raises:
            JointNotFound: An unknown joint name.
            ValueError: A value is NaN or infinite.
        """
        for name, value in values.items():
            if name not in self._index:
                raise JointNotFound(name, self.robot.joint_names)
            if not np.isfinite(value):
                raise ValueError(f"joint {name}: value must be finite, got {value}")
        lower, upper = self.robot.limits.lower, self.robot.limits.upper
        with self._lock:
            q = self._q.copy()
            for name, value in values.items():
                i = self._index[name]
                q[i] = min(max(float(value), lower[i]), upper[i])
            self._q = q

    @property
    def positions(self) -> dict[str, float]:
        """Every movable joint's current value, mimic followers included (what is published)."""
        with self._lock:
            q = self._q.copy()
        return self.robot.joint_positions(q)

    def _on_source(self, msg: JointState) -> None:
        lower, upper = self.robot.limits.lower, self.robot.limits.upper
        ignored = []
        with self._lock:
            q = self._q.copy()
            for name, value in zip(msg.name, msg.position, strict=False):
                i = self._index.get(name)
                if i is None:
                    if name not in self.robot.mimic:
                        ignored.append(name)
                elif np.isfinite(value):
                    q[i] = min(max(value, lower[i]), upper[i])
            self._q = q
        for name in ignored:
            self._warn.warn(
                f"unknown:{name}", "joint_state_publisher: ignoring unknown source joint %r", name
            )

    # ------------------------------------------------------------------ publishing
    def message(self, stamp: Time | None = None) -> JointState:
        """The JointState that would be published now."""
        positions = self.positions
        return JointState(
            Header(Time.now() if stamp is None else stamp, ""), positions.keys(), positions.values()
        )

    def publish(self, stamp: Time | None = None) -> JointState:
        """Publish one message now; returns it."""
        msg = self.message(stamp)
        self._pub.publish(msg)
        return msg

    def start(self) -> JointStatePublisher:
        """Publish at ``rate`` Hz in a background thread until :meth:`close`."""
        if self._thread is None:
            self._thread = threading.Thread(target=self._loop, name="joint_state_publisher", daemon=True)
            self._thread.start()
        return self

    def _loop(self) -> None:
        period = 1.0 / self.rate
        while True:
            try:
                self.publish()
            except Exception:
                self._warn.warn("publish", "joint_state_publisher: publishing failed", exc_info=True)
            if self._stop.wait(period):
                return

    def close(self) -> None:
        """Stop the thread, the subscriptions and the publisher."""
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(5.0)
        for sub in self._subs:
            sub.close()
        self._pub.close()

    def __enter__(self) -> JointStatePublisher:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
