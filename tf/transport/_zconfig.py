"""Zenoh session configuration for urdftk: zero-config on one machine, explicit endpoints otherwise.

Zero configuration (nothing given): a *peer* that listens on ``tcp/127.0.0.1:<any free port>``
and finds the other urdftk processes of this machine by UDP multicast scouting on the loopback
interface (group 224.0.0.224:7446, Zenoh's default). Gossip then lets every peer connect to every
other one directly. Nothing is reachable from another machine: listeners bind 127.0.0.1.

Across machines: start ``urdftk router`` on one of them (it listens on ``tcp/0.0.0.0:7447`` only
when asked; by default on 127.0.0.1) and give the others ``connect=["tcp/HOST:7447"]``, or set
``URDFTK_ZENOH_CONNECT=tcp/HOST:7447`` (comma-separated), or write a Zenoh json5 configuration file
and point ``URDFTK_ZENOH_CONFIG`` at it (used as the base; explicit endpoints are added on top).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping

import zenoh

__all__ = [
    "ENV_CONFIG",
    "ENV_CONNECT",
    "ENV_DOMAIN",
    "ENV_LISTEN",
    "LOCAL_LISTEN",
    "domain_id_from",
    "session_config",
    "split_endpoints",
]

ENV_CONNECT = "URDFTK_ZENOH_CONNECT"
ENV_LISTEN = "URDFTK_ZENOH_LISTEN"
ENV_CONFIG = "URDFTK_ZENOH_CONFIG"
ENV_DOMAIN = "ROS_DOMAIN_ID"
LOCAL_LISTEN = "tcp/127.0.0.1:0"
_LOOPBACK_INTERFACE = "127.0.0.1"


def split_endpoints(text: str | None) -> list[str]:
    """Endpoints from a comma- or space-separated string (an environment variable)."""
    if not text:
        return []
    return [part for part in text.replace(",", " ").split() if part]


def domain_id_from(domain_id: int | None, environ: Mapping[str, str]) -> int:
    """The ROS domain id: the argument, else ``ROS_DOMAIN_ID``, else 0.

    Raises:
        ValueError: The value is not a non-negative integer.
    """
    if domain_id is None:
        text = environ.get(ENV_DOMAIN, "").strip() or "0"
        try:
            domain_id = int(text)
        except ValueError:
            raise ValueError(f"{ENV_DOMAIN}={text!r} is not an integer (e.g. ROS_DOMAIN_ID=0)") from None
    if domain_id < 0:
        raise ValueError(f"the domain id must be >= 0, got {domain_id}")
    return domain_id


def _insert(config: zenoh.Config, key: str, value: object) -> None:
    config.insert_json5(key, json.dumps(value))


def session_config(
    *,
    connect: Iterable[str] = (),
    listen: Iterable[str] | None = None,
    config_file: str | os.PathLike[str] | None = None,
    environ: Mapping[str, str] | None = None,
    mode: str = "peer",
) -> zenoh.Config:
    """Build the Zenoh configuration of a urdftk session.

    Args:
        connect: Endpoints to connect to (``tcp/HOST:7447``); ``URDFTK_ZENOH_CONNECT`` adds more.
        listen: Endpoints to listen on; None: ``URDFTK_ZENOH_LISTEN`` or ``tcp/127.0.0.1:0``.
        config_file: A Zenoh json5 file used as the base; None: ``URDFTK_ZENOH_CONFIG`` if set.
        environ: Environment to read (``os.environ`` when None).
        mode: ``peer`` (nodes) or ``router``.

    Raises:
        ValueError: The configuration file cannot be read or an endpoint is invalid.
    """
    env = os.environ if environ is None else environ
    path = config_file if config_file is not None else (env.get(ENV_CONFIG) or None)
    connects = [*connect, *split_endpoints(env.get(ENV_CONNECT))]
    listens = list(listen) if listen is not None else split_endpoints(env.get(ENV_LISTEN))
    try:
        if path is not None:
            config = zenoh.Config.from_file(str(path))
        else:
            config = zenoh.Config()
            _insert(config, "mode", mode)
            _insert(config, "scouting/multicast/enabled", True)
            _insert(config, "scouting/multicast/interface", _LOOPBACK_INTERFACE)
            _insert(config, "scouting/gossip/enabled", True)
            if not listens:
                listens = ["tcp/127.0.0.1:7447" if mode == "router" else LOCAL_LISTEN]
        # AdvancedPublisher caches (latched topics) need timestamps.
        _insert(config, "timestamping/enabled", True)
        if listens:
            _insert(config, "listen/endpoints", listens)
        if connects:
            _insert(config, "connect/endpoints", connects)
    except (zenoh.ZError, OSError) as exc:
        where = f" (configuration file {path})" if path is not None else ""
        raise ValueError(f"invalid Zenoh configuration{where}: {exc}") from None
    return config
