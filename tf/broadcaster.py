"""Transform broadcasters: ``/tf`` for moving frames, latched ``/tf_static`` for fixed ones."""

from __future__ import annotations

import threading
from collections.abc import Iterable, Sequence

from .messages import Header, Quaternion, TFMessage, Time, Transform, TransformStamped, Vector3
from .transport import TOPIC_TF, TOPIC_TF_STATIC, Transport, default_transport

__all__ = ["StaticTransformBroadcaster", "TransformBroadcaster"]


def _as_list(transforms: TransformStamped | Iterable[TransformStamped]) -> list[TransformStamped]:
    if isinstance(transforms, TransformStamped):
        return [transforms]
    items = list(transforms)
    for item in items:
        if not isinstance(item, TransformStamped):
            raise TypeError(f"expected TransformStamped, got {type(item).__name__}")
    return items


def _stamped(
    translation: Sequence[float], rotation: Sequence[float], time: Time, child: str, parent: str
) -> TransformStamped:
    x, y, z = translation
    qx, qy, qz, qw = rotation
    return TransformStamped(
        Header(time, parent),
        child,
        Transform(
            Vector3(float(x), float(y), float(z)), Quaternion(float(qx), float(qy), float(qz), float(qw))
        ),
    )


class TransformBroadcaster:
    """Publishes transforms on ``/tf``.

    Args:
        transport: where to publish; None uses ``tf.transport.default_transport()``.
    """

    def __init__(self, transport: Transport | None = None) -> None:
        self._transport = transport if transport is not None else default_transport()
        self._pub = self._transport.publisher(TOPIC_TF, TFMessage)

    def send_transform(self, transform: TransformStamped | Iterable[TransformStamped]) -> None:
        """Publish one transform or several in one message (tf2_ros form)."""
        self._pub.publish(TFMessage(tuple(_as_list(transform))))

    def sendTransform(
        self,
        translation: Sequence[float] | TransformStamped | Iterable[TransformStamped],
        rotation: Sequence[float] | None = None,
        time: Time | None = None,
        child: str | None = None,
        parent: str | None = None,
    ) -> None:
        """ROS 1 ``tf`` form: ``sendTransform((x, y, z), (qx, qy, qz, qw), time, child, parent)``.

        Note the order: child frame, then parent frame. Called with a single TransformStamped (or
        a list of them) it behaves as :meth:`send_transform`.
        """
        if rotation is None and time is None and child is None and parent is None:
            self.send_transform(translation)  # type: ignore[arg-type]
            return
        if rotation is None or time is None or child is None or parent is None:
            raise TypeError(
                "sendTransform(translation, rotation, time, child, parent) needs all five arguments"
            )
        self.send_transform(_stamped(translation, rotation, time, child, parent))  # type: ignore[arg-type]

    def close(self) -> None:
        """Stop publishing."""
        self._pub.close()

    def __enter__(self) -> TransformBroadcaster:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class StaticTransformBroadcaster(TransformBroadcaster):
    """Publishes fixed transforms on latched ``/tf_static``.

    Keeps every transform it has sent (the latest per child frame) and republishes the whole set
    each time, so a listener that starts later still receives all of them.
    """

    def __init__(self, transport: Transport | None = None) -> None:
        self._transport = transport if transport is not None else default_transport()
        self._pub = self._transport.publisher(TOPIC_TF_STATIC, TFMessage, latched=True)
        self._lock = threading.Lock()
        self._by_child: dict[str, TransformStamped] = {}

    def send_transform(self, transform: TransformStamped | Iterable[TransformStamped]) -> None:
        """Add (or replace, by child frame) transforms and republish the accumulated set."""
        items = _as_list(transform)
        with self._lock:
            for item in items:
                self._by_child[item.child_frame_id] = item
            message = TFMessage(tuple(self._by_child.values()))
            self._pub.publish(message)

    @property
    def transforms(self) -> tuple[TransformStamped, ...]:
        """Every static transform sent so far (latest per child frame)."""
        with self._lock:
            return tuple(self._by_child.values())
