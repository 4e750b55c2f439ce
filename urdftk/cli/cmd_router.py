"""``urdftk router``: a Zenoh router, so that urdftk (and rmw_zenoh) processes on several machines meet."""

from __future__ import annotations

import argparse

__all__ = ["register", "run"]

DEFAULT_LISTEN = "tcp/127.0.0.1:7447"


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``router`` subcommand."""
    p = subparsers.add_parser(
        "router",
        help="run a Zenoh router (rendezvous for processes on other machines)",
        description=(
            "Run a Zenoh router until Ctrl-C. Other machines reach it with "
            "`--connect tcp/HOST:7447` or URDFTK_ZENOH_CONNECT=tcp/HOST:7447. It listens on "
            f"{DEFAULT_LISTEN} unless --listen says otherwise (e.g. tcp/0.0.0.0:7447 for the network)."
        ),
    )
    p.add_argument(
        "--listen", action="append", default=[], metavar="ENDPOINT", help=f"default {DEFAULT_LISTEN}"
    )
    p.add_argument("--connect", action="append", default=[], metavar="ENDPOINT", help="other routers to join")
    p.add_argument("--config", metavar="FILE", help="Zenoh json5 configuration used as the base")
    p.add_argument("--no-multicast", action="store_true", help="do not answer multicast scouting")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Open the router session and serve until interrupted."""
    import json
    import threading

    import zenoh

    from tf.transport._zconfig import session_config

    config = session_config(
        connect=args.connect, listen=args.listen or [DEFAULT_LISTEN], config_file=args.config, mode="router"
    )
    if args.no_multicast:
        config.insert_json5("scouting/multicast/enabled", json.dumps(False))
    try:
        session = zenoh.open(config)
    except zenoh.ZError as exc:
        raise OSError(f"cannot start the router: {exc}") from None
    try:
        endpoints = ", ".join(args.listen or [DEFAULT_LISTEN])
        print(f"urdftk router {session.info.zid()} listening on {endpoints} (Ctrl-C to stop)", flush=True)
        threading.Event().wait()
    finally:
        session.close()
    return 0
