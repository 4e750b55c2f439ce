"""``TransformListener``: feeds ``/tf`` and ``/tf_static`` into a ``tf.Buffer``."""

from __future__ import annotations

from .buffer import DEFAULT_AUTHORITY, Buffer
from .messages import TFMessage
from .transport import TOPIC_TF, TOPIC_TF_STATIC, Transport, default_transport

__all__ = ["TransformListener"]


class TransformListener:
    """Subscribes to ``/tf`` and ``/tf_static`` and stores what arrives in ``buffer``.

    Static transforms go in with ``set_transform_static``. Messages carry no broadcaster identity,
    so every transform is recorded with ``authority`` (tf2_ros uses "default_authority" too).

    Args:
        buffer: where transforms are stored.
        transport: where to listen; None uses ``tf.transport.default_transport()``.
        static_only: listen to ``/tf_static`` only.
        authority: the broadcaster name recorded with each transform.
    """

    def __init__(
        self,
        buffer: Buffer,
        transport: Transport | None = None,
        *,
        static_only: bool = False,
        authority: str = DEFAULT_AUTHORITY,
    ) -> None:
        self.buffer = buffer
        self._authority = authority
        self._transport = transport if transport is not None else default_transport()
        self._subs = [self._transport.subscribe(TOPIC_TF_STATIC, TFMessage, self._on_static)]
        if not static_only:
            self._subs.append(self._transport.subscribe(TOPIC_TF, TFMessage, self._on_dynamic))

    def _on_dynamic(self, msg: TFMessage) -> None:
        set_transform = self.buffer.set_transform
        authority = self._authority
        for transform in msg.transforms:
            set_transform(transform, authority)

    def _on_static(self, msg: TFMessage) -> None:
        set_transform_static = self.buffer.set_transform_static
        authority = self._authority
        for transform in msg.transforms:
            set_transform_static(transform, authority)

    def close(self) -> None:
        """Stop listening (the buffer keeps what it has)."""
        for sub in self._subs:
            sub.close()
        self._subs = []

    def __enter__(self) -> TransformListener:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
