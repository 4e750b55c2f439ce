"""Transports carry tf messages between broadcasters and listeners.

``default_transport()`` returns one process-wide transport, created on first use and closed at
interpreter exit. It is chosen by the ``URDFTK_TRANSPORT`` environment variable: ``zenoh`` (the
default) or ``inproc``. This lazily created default is the package's single piece of global state,
like a ROS node; pass an explicit ``transport=`` to broadcasters and listeners to avoid it.
"""

from __future__ import annotations

import atexit
import importlib
import os
import threading

from ._base import Publisher, Subscription, Transport
from .inproc import InProcessTransport

__all__ = [
    "ENV_VAR",
    "TOPIC_JOINT_STATES",
    "TOPIC_TF",
    "TOPIC_TF_STATIC",
    "InProcessTransport",
    "Publisher",
    "Subscription",
    "Transport",
    "default_transport",
]

ENV_VAR = "URDFTK_TRANSPORT"
TOPIC_TF = "/tf"
TOPIC_TF_STATIC = "/tf_static"
TOPIC_JOINT_STATES = "/joint_states"

_default_lock = threading.Lock()
_default: list[Transport] = []  # holds at most one transport (the lazily created default)


def _create(kind: str) -> Transport:
    if kind == "inproc":
        return InProcessTransport()
    if kind == "zenoh":
        zenoh_module = importlib.import_module(".zenoh", __name__)
        return zenoh_module.ZenohTransport()
    raise ValueError(f"{ENV_VAR}={kind!r} is not a transport; use 'zenoh' (default) or 'inproc'")


def _close_default() -> None:
    with _default_lock:
        transports = list(_default)
        _default.clear()
    for transport in transports:
        transport.close()


def default_transport() -> Transport:
    """The process-wide transport, created on first call (thread-safe), closed at exit.

    Raises:
        ValueError: ``URDFTK_TRANSPORT`` names no known transport.
    """
    with _default_lock:
        if not _default:
            _default.append(_create(os.environ.get(ENV_VAR, "zenoh").strip().lower() or "zenoh"))
            atexit.register(_close_default)
        return _default[0]
