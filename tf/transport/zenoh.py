"""The Zenoh transport: tf messages as ROS 2 CDR on rmw_zenoh key expressions.

``ZenohTransport()`` with no arguments finds the other urdftk processes of this machine by itself
(see :mod:`tf.transport._zconfig` for the zero-configuration rules and for crossing machines).
Each transport is one Zenoh session and one ROS-style node: it announces itself and each of its
publishers and subscriptions with rmw_zenoh liveliness tokens, and stamps every sample with the
33-byte rmw_zenoh attachment (sequence number, source time, publisher GID).

Latched publishers (``/tf_static``) keep their last message in a Zenoh AdvancedPublisher cache;
every subscription is an AdvancedSubscriber that asks late-detected publishers for their cache,
so a listener that starts later still receives it.

A payload on one of our keys that does not decode (garbage, a foreign type) is dropped with a
rate-limited warning on the ``tf.transport`` logger. So is an exception from a callback.

Example:
    >>> from tf.transport.zenoh import ZenohTransport
    >>> with ZenohTransport(connect=["tcp/192.168.1.10:7447"]) as bus:  # doctest: +SKIP
    ...     bus.subscribe("/tf", TFMessage, print)
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import os
import threading
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any, TypeVar

import zenoh
import zenoh.ext

from . import _cdr, _keys
from ._base import Publisher, Subscription, Transport
from ._warn import RateLimitedWarning
from ._zconfig import domain_id_from, session_config

__all__ = ["MessageInfo", "ZenohPublisher", "ZenohSubscription", "ZenohTransport"]

M = TypeVar("M")
_log = logging.getLogger("tf.transport")
_DEPTH = {"/tf": 100, "/tf_static": 1, "/joint_states": 10}
_PUT = zenoh.SampleKind.PUT


@dataclass(frozen=True)
class MessageInfo:
    """Metadata of one received sample.

    Attributes:
        key: The Zenoh key expression it arrived on.
        received_ns: Local wall-clock time of arrival (ns since the epoch).
        attachment: rmw_zenoh attachment (sequence number, source time, GID), None if absent.
    """

    key: str
    received_ns: int
    attachment: _keys.Attachment | None


class ZenohPublisher(Publisher[M]):
    """Publishes one message type on one topic; made by :meth:`ZenohTransport.publisher`."""

    def __init__(self, bus: ZenohTransport, topic: str, msg_type: type[M], latched: bool) -> None:
        self.topic = topic
        self.msg_type = msg_type
        self.latched = latched
        self._bus = bus
        info = _keys.type_info(msg_type)
        self.key = _keys.topic_key(bus.domain_id, topic, info)
        session = bus._session
        if latched:
            self._zpub: Any = zenoh.ext.declare_advanced_publisher(
                session,
                self.key,
                congestion_control=zenoh.CongestionControl.BLOCK,
                reliability=zenoh.Reliability.RELIABLE,
                cache=zenoh.ext.CacheConfig(1),
                publisher_detection=True,
            )
        else:
            self._zpub = session.declare_publisher(
                self.key,
                congestion_control=zenoh.CongestionControl.BLOCK,
                reliability=zenoh.Reliability.RELIABLE,
            )
        qos = _keys.qos_string(depth=_DEPTH.get(topic, 42), transient_local=latched)
        token_key = bus._entity_token("MP", topic, info, qos)
        self.gid = _keys.gid_of(token_key)
        self._token = session.liveliness().declare_token(token_key)
        self._sequence = itertools.count(1)
        self._encode = _cdr.encoder(msg_type)
        self._matching = threading.Condition()
        self._matched = False
        self._listener: Any = None
        self.closed = False

    def publish(self, msg: M) -> None:
        """Serialize ``msg`` as CDR and send it (does nothing once closed).

        Raises:
            TypeError: ``msg`` is not of this publisher's type.
            tf.transport._cdr.CdrError: A value does not fit its CDR type.
        """
        if msg.__class__ is self.msg_type:
            self.publish_cdr(self._encode(msg))
            return
        if not isinstance(msg, self.msg_type):
            raise TypeError(
                f"publisher on {self.topic} sends {self.msg_type.__name__}, got {type(msg).__name__}"
            )
        self.publish_cdr(_cdr.encode(msg))  # type: ignore[arg-type]

    def publish_cdr(self, payload: bytes) -> None:
        """Send an already serialized CDR payload (e.g. from a recording) with a fresh attachment."""
        if self.closed:
            return
        attachment = _keys.pack_attachment(next(self._sequence), time.time_ns(), self.gid)
        try:
            self._zpub.put(payload, attachment=attachment)
        except zenoh.ZError:
            if not self.closed:
                raise

    def wait_for_subscribers(self, timeout: float | None = None) -> bool:
        """Block until a subscriber matches this publisher; True if one did within ``timeout`` s.

        Latched publishers return True at once: late subscribers fetch their cached message.
        """
        if self.latched or self.closed:
            return not self.closed
        with self._matching:
            if self._listener is None:
                # indirect=False, as for subscriptions: an indirect callback runs on a non-daemon
                # thread, and a process that never closed its transport would hang at exit.
                self._listener = self._zpub.declare_matching_listener(
                    zenoh.handlers.Callback(self._on_matching, indirect=False)
                )
                self._matched = self._zpub.matching_status.matching
            return self._matching.wait_for(lambda: self._matched or self.closed, timeout) and not self.closed

    def _on_matching(self, status: Any) -> None:
        with self._matching:
            self._matched = bool(status.matching)
            self._matching.notify_all()

    def close(self) -> None:
        """Stop publishing; withdraws the latched message and the liveliness token."""
        if self.closed:
            return
        self.closed = True
        with self._matching:
            self._matching.notify_all()
        self._bus._forget(self)
        for entity in (self._listener, self._zpub, self._token):
            if entity is not None:
                with contextlib.suppress(zenoh.ZError):
                    entity.undeclare()


class ZenohSubscription(Subscription):
    """A live subscription; made by :meth:`ZenohTransport.subscribe` and its variants."""

    def __init__(
        self, bus: ZenohTransport, topic: str, msg_type: type, deliver: Callable[[bytes, zenoh.Sample], None]
    ) -> None:
        self.topic = topic
        self.msg_type = msg_type
        self._bus = bus
        self._deliver = deliver
        info = _keys.type_info(msg_type)
        self.key = _keys.topic_key(bus.domain_id, topic, info)
        self.closed = False
        # indirect=False: samples are handled on Zenoh's own threads. The default (indirect) runs
        # them on a non-daemon Python thread that lives until the subscriber is undeclared, and
        # Python joins such threads before atexit handlers run: a process that never closed its
        # transport would then hang at exit instead of closing it.
        self._zsub = zenoh.ext.declare_advanced_subscriber(
            bus._session,
            self.key,
            zenoh.handlers.Callback(self._on_sample, indirect=False),
            history=zenoh.ext.HistoryConfig(detect_late_publishers=True),
        )
        qos = _keys.qos_string(depth=_DEPTH.get(topic, 42))
        self._token = bus._session.liveliness().declare_token(bus._entity_token("MS", topic, info, qos))

    def _on_sample(self, sample: zenoh.Sample) -> None:
        if self.closed or sample.kind != _PUT:
            return
        try:
            self._deliver(sample.payload.to_bytes(), sample)
        except _cdr.CdrError as exc:
            self._bus._warn.warn(
                f"bad:{self.key}",
                "dropped a bad payload on %s (%d bytes): %s",
                self.key,
                len(sample.payload),
                exc,
            )
        except Exception:
            self._bus._warn.warn(
                f"cb:{self.key}",
                "subscriber callback on %s raised; delivery continues",
                self.topic,
                exc_info=True,
            )

    def close(self) -> None:
        """Stop receiving messages."""
        if self.closed:
            return
        self.closed = True
        self._bus._forget(self)
        for entity in (self._zsub, self._token):
            with contextlib.suppress(zenoh.ZError):
                entity.undeclare()


def _info(sample: zenoh.Sample) -> MessageInfo:
    raw = sample.attachment
    return MessageInfo(
        str(sample.key_expr),
        time.time_ns(),
        _keys.unpack_attachment(raw.to_bytes() if raw is not None else None),
    )


class ZenohTransport(Transport):
    """A Zenoh session speaking ROS 2 CDR with rmw_zenoh's key layout.

    Args:
        connect: Endpoints to connect to, e.g. ``["tcp/192.168.1.10:7447"]`` (a router or a peer);
            ``URDFTK_ZENOH_CONNECT`` adds more.
        listen: Endpoints to listen on; default ``tcp/127.0.0.1:0`` (``URDFTK_ZENOH_LISTEN``).
        config_file: A Zenoh json5 configuration used as the base (``URDFTK_ZENOH_CONFIG``).
        domain_id: ROS domain; default ``ROS_DOMAIN_ID`` or 0. Domains never see each other's data.
        node_name: Name announced in the liveliness tokens (``urdftk_<pid>`` by default).
        environ: Environment to read instead of ``os.environ``.

    Raises:
        ValueError: Bad configuration, endpoint or domain id.
        ConnectionError: The Zenoh session cannot be opened (e.g. a listen port is taken).
    """

    def __init__(
        self,
        *,
        connect: Iterable[str] = (),
        listen: Iterable[str] | None = None,
        config_file: str | os.PathLike[str] | None = None,
        domain_id: int | None = None,
        node_name: str | None = None,
        environ: Mapping[str, str] | None = None,
    ) -> None:
        env = os.environ if environ is None else environ
        self.domain_id = domain_id_from(domain_id, env)
        self.node_name = node_name or f"urdftk_{os.getpid()}"
        config = session_config(connect=connect, listen=listen, config_file=config_file, environ=env)
        try:
            self._session = zenoh.open(config)
        except zenoh.ZError as exc:
            raise ConnectionError(f"cannot open a Zenoh session: {exc}") from None
        self.zid = str(self._session.info.zid())
        self._warn = RateLimitedWarning(_log)
        self._lock = threading.Lock()
        self._entities: list[ZenohPublisher[Any] | ZenohSubscription] = []
        self._ids = itertools.count(1)
        self._node_id = 0
        self._closed = False
        self._node_token = self._session.liveliness().declare_token(
            _keys.node_token(self.domain_id, self.zid, self._node_id, self.node_name)
        )

    # ------------------------------------------------------------------ the Transport interface
    def publisher(self, topic: str, msg_type: type[M], *, latched: bool = False) -> ZenohPublisher[M]:
        """Create a publisher on ``topic`` (``latched``: late subscribers get its last message).

        Raises:
            ValueError: ``msg_type`` cannot travel over Zenoh or ``topic`` is not a valid name.
        """
        self._check_open()
        return self._keep(ZenohPublisher(self, topic, msg_type, latched))

    def subscribe(self, topic: str, msg_type: type[M], callback: Callable[[M], Any]) -> ZenohSubscription:
        """Call ``callback(msg)`` for every ``msg_type`` message on ``topic``.

        Raises:
            ValueError: ``msg_type`` cannot travel over Zenoh, ``topic`` is invalid, or the
                transport is closed.
        """
        self._check_open()
        _keys.type_info(msg_type)  # ValueError first for a type that cannot travel
        decode = _cdr.decoder(msg_type)

        def deliver(payload: bytes, _sample: zenoh.Sample) -> None:
            callback(decode(payload))

        return self._keep(ZenohSubscription(self, topic, msg_type, deliver))

    def close(self) -> None:
        """Close every publisher and subscription, then the session; later calls do nothing."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            entities = list(self._entities)
            self._entities.clear()
        for entity in entities:
            entity.close()
        with contextlib.suppress(zenoh.ZError):
            self._node_token.undeclare()
        self._session.close()

    # ------------------------------------------------------------------ Zenoh extras
    def subscribe_info(
        self, topic: str, msg_type: type[M], callback: Callable[[M, MessageInfo], Any]
    ) -> ZenohSubscription:
        """Like :meth:`subscribe`, with each sample's :class:`MessageInfo` as second argument."""
        self._check_open()
        _keys.type_info(msg_type)  # ValueError first for a type that cannot travel
        decode = _cdr.decoder(msg_type)

        def deliver(payload: bytes, sample: zenoh.Sample) -> None:
            callback(decode(payload), _info(sample))

        return self._keep(ZenohSubscription(self, topic, msg_type, deliver))

    def subscribe_raw(
        self, topic: str, msg_type: type, callback: Callable[[bytes, MessageInfo], Any]
    ) -> ZenohSubscription:
        """Receive the CDR payloads of ``topic`` undecoded (recorders); bad ones are still dropped."""
        self._check_open()
        check = _cdr.check

        def deliver(payload: bytes, sample: zenoh.Sample) -> None:
            check(msg_type, payload)  # validate: never record garbage
            callback(payload, _info(sample))

        return self._keep(ZenohSubscription(self, topic, msg_type, deliver))

    def graph(self, timeout: float = 1.0) -> list[_keys.EntityToken]:
        """Nodes, publishers and subscriptions alive in this domain (rmw_zenoh liveliness tokens).

        Listens for ``timeout`` seconds, so that peers still being connected are included.
        """
        self._check_open()
        lock = threading.Lock()
        alive: dict[str, _keys.EntityToken] = {}

        def on_token(sample: zenoh.Sample) -> None:
            token = _keys.parse_token(str(sample.key_expr))
            if token is None:
                return
            with lock:
                if sample.kind == zenoh.SampleKind.PUT:
                    alive[token.key] = token
                else:
                    alive.pop(token.key, None)

        sub = self._session.liveliness().declare_subscriber(
            f"{_keys.ADMIN_SPACE}/{self.domain_id}/**",
            zenoh.handlers.Callback(on_token, indirect=False),
            history=True,
        )
        try:
            threading.Event().wait(timeout)
        finally:
            sub.undeclare()
        with lock:
            found = list(alive.values())
        return sorted(found, key=lambda t: (t.topic, t.kind, t.node_name, t.entity_id))

    @property
    def closed(self) -> bool:
        """Whether :meth:`close` was called."""
        return self._closed

    # ------------------------------------------------------------------ internals
    def _check_open(self) -> None:
        if self._closed:
            raise ValueError("this Zenoh transport is closed; create a new one")

    def _entity_token(self, kind: str, topic: str, info: _keys.TypeInfo, qos: str) -> str:
        return _keys.entity_token(
            self.domain_id, self.zid, self._node_id, next(self._ids), kind, self.node_name, topic, info, qos
        )

    def _keep(self, entity: Any) -> Any:
        with self._lock:
            closed = self._closed
            if not closed:
                self._entities.append(entity)
        if closed:
            entity.close()
        return entity

    def _forget(self, entity: Any) -> None:
        with self._lock:
            if entity in self._entities:
                self._entities.remove(entity)
