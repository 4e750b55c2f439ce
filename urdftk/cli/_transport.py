"""Transport options shared by the networked subcommands (nodes, tf tools, topics, recording)."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["add_transport_args", "open_transport"]


def add_transport_args(parser: argparse.ArgumentParser) -> None:
    """Add ``--connect``, ``--listen``, ``--zenoh-config`` and ``--domain-id``."""
    group = parser.add_argument_group("network (Zenoh)")
    group.add_argument(
        "--connect",
        action="append",
        default=[],
        metavar="ENDPOINT",
        help="Zenoh endpoint to connect to, e.g. tcp/10.0.0.2:7447 (repeatable; env URDFTK_ZENOH_CONNECT)",
    )
    group.add_argument(
        "--listen",
        action="append",
        default=None,
        metavar="ENDPOINT",
        help="endpoint to listen on (default tcp/127.0.0.1:0; env URDFTK_ZENOH_LISTEN)",
    )
    group.add_argument(
        "--zenoh-config", metavar="FILE", help="Zenoh json5 configuration (env URDFTK_ZENOH_CONFIG)"
    )
    group.add_argument(
        "--domain-id", type=int, default=None, help="ROS domain id (default: env ROS_DOMAIN_ID or 0)"
    )


def open_transport(args: argparse.Namespace, node_name: str) -> Any:
    """Open the Zenoh transport the options describe (a ``tf.transport.zenoh.ZenohTransport``)."""
    from tf.transport.zenoh import ZenohTransport

    return ZenohTransport(
        connect=args.connect,
        listen=args.listen,
        config_file=args.zenoh_config,
        domain_id=args.domain_id,
        node_name=node_name,
    )
