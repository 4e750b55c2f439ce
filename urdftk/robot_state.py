"""``RobotStatePublisher``: joint states in, the robot's frames out on ``/tf`` and ``/tf_static``.

As ROS 2's robot_state_publisher:

- fixed joints are published once, on latched ``/tf_static``;
- each ``/joint_states`` message moves the joints it names (mimic followers follow their masters),
  and their transforms go out on ``/tf`` stamped with the message's stamp;
- ``publish_frequency`` caps how often a joint's transform is republished (by stamp);
- unknown joint names are ignored with a rate-limited warning;
- ``frame_prefix`` is prepended to every frame id (``"robot1/"``).

Works on any transport: in one process (``InProcessTransport``) or across processes (Zenoh).
"""

from __future__ import annotations

import logging
import threading
from typing import TYPE_CHECKING, Any

import numpy as np

from tf import StaticTransformBroadcaster, TransformBroadcaster
from tf.messages import Header, JointState, Quaternion, Time, Transform, TransformStamped, Vector3
from tf.transformations import quaternion_from_matrix
from tf.transport import TOPIC_JOINT_STATES, Transport, default_transport
from tf.transport._warn import RateLimitedWarning

if TYPE_CHECKING:
    from urdftk.model import Robot

__all__ = ["RobotStatePublisher", "transform_stamped"]

_log = logging.getLogger("urdftk.robot_state")


def transform_stamped(T_parent_child: np.ndarray, stamp: Time, parent: str, child: str) -> TransformStamped:
    """A TransformStamped from a 4x4 homogeneous matrix (quaternion xyzw, ``w >= 0``)."""
    x, y, z, w = (float(v) for v in quaternion_from_matrix(T_parent_child))
    if w < 0.0:
        x, y, z, w = -x, -y, -z, -w
    t = T_parent_child[:3, 3]
    return TransformStamped(
        Header(stamp, parent),
        child,
        Transform(Vector3(float(t[0]), float(t[1]), float(t[2])), Quaternion(x, y, z, w)),
    )


class RobotStatePublisher:
    """Publishes a robot's frames from its joint states.

    Args:
        robot: The robot (``urdftk.load(...)``).
        transport: Where to listen and publish; None uses ``tf.transport.default_transport()``.
        frame_prefix: Prepended to every frame id.
        publish_frequency: Maximum rate (Hz) at which a joint's transform is republished on
            ``/tf``; messages stamped closer together than ``1/publish_frequency`` are absorbed
            into the state but not republished. 0 or less: publish every message.
    """

    def __init__(
        self,
        robot: Robot,
        transport: Transport | None = None,
        *,
        frame_prefix: str = "",
        publish_frequency: float = 50.0,
    ) -> None:
        self.robot = robot
        self.frame_prefix = frame_prefix
        self._period_ns = int(1e9 / publish_frequency) if publish_frequency > 0 else 0
        self._transport = transport if transport is not None else default_transport()
        self._warn = RateLimitedWarning(_log)
        self._lock = threading.Lock()
        self._q = robot.neutral()
        self._index = {name: i for i, name in enumerate(robot.joint_names)}
        # URDF joint name of each movable joint, by child link (a link has one parent joint).
        joint_map = robot.description.joint_map
        self._joint_of_child = {j.child: name for name, j in joint_map.items() if j.type != "fixed"}
        self._followers: dict[str, list[str]] = {}
        for follower, (master, _mult, _off) in robot.mimic.items():
            self._followers.setdefault(master, []).append(follower)
        self._last_ns: dict[str, int] = {}
        self._tf = TransformBroadcaster(self._transport)
        self._static = StaticTransformBroadcaster(self._transport)
        self.publish_fixed()
        self._sub = self._transport.subscribe(TOPIC_JOINT_STATES, JointState, self.on_joint_state)

    def publish_fixed(self, stamp: Time | None = None) -> list[TransformStamped]:
        """Publish every fixed joint on ``/tf_static`` (latched); returns what was sent."""
        stamp = Time.now() if stamp is None else stamp
        p = self.frame_prefix
        items = [transform_stamped(T, stamp, p + a, p + b) for a, b, T in self.robot.fixed_transforms()]
        if items:
            self._static.send_transform(items)
        return items

    def on_joint_state(self, msg: JointState) -> list[TransformStamped]:
        """Apply one joint-state message and publish the moved joints; returns what was sent."""
        stamp = msg.header.stamp
        stamp_ns = stamp.nanoseconds
        mimic = self.robot.mimic
        moved: set[str] = set()
        unknown: list[str] = []
        with self._lock:
            q = self._q.copy()
            for name, value in zip(msg.name, msg.position, strict=False):
                i = self._index.get(name)
                if i is not None:
                    q[i] = value
                    moved.add(name)
                    moved.update(self._followers.get(name, ()))
                elif name not in mimic:
                    unknown.append(name)
            finite = bool(np.isfinite(q).all())
            due = set()
            if finite:
                self._q = q
                for name in moved:
                    last = self._last_ns.get(name)
                    if last is None or stamp_ns - last >= self._period_ns or stamp_ns < last:
                        due.add(name)
                        self._last_ns[name] = stamp_ns
        for name in unknown:
            self._warn.warn(
                f"unknown:{name}",
                "robot_state_publisher: ignoring unknown joint %r (robot %s has: %s)",
                name,
                self.robot.name,
                ", ".join(self.robot.joint_names),
            )
        if not finite:
            self._warn.warn("nan", "robot_state_publisher: ignoring a joint state with NaN or inf")
        if not due:
            return []
        p = self.frame_prefix
        items = [
            transform_stamped(T, stamp, p + parent, p + child)
            for parent, child, T in self.robot.joint_transforms(q)
            if self._joint_of_child.get(child) in due
        ]
        if items:
            self._tf.send_transform(items)
        return items

    @property
    def positions(self) -> dict[str, float]:
        """The current value of every movable joint (mimic followers included)."""
        with self._lock:
            q = self._q.copy()
        return self.robot.joint_positions(q)

    def close(self) -> None:
        """Stop listening and publishing (the latched statics are withdrawn)."""
        self._sub.close()
        self._tf.close()
        self._static.close()

    def __enter__(self) -> RobotStatePublisher:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
