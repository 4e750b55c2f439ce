"""``urdftk topic list|echo|hz``: rostopic for /tf, /tf_static and /joint_states over Zenoh."""

from __future__ import annotations

import argparse
import sys

from urdftk.cli._transport import add_transport_args, open_transport

__all__ = ["message_type", "register", "run_echo", "run_hz", "run_list"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``topic`` and its subcommands."""
    p = subparsers.add_parser(
        "topic", help="list, echo and measure topics", description="rostopic for our topics."
    )
    sub = p.add_subparsers(dest="topic_command", metavar="VERB")
    sub.required = True

    ls = sub.add_parser("list", help="topics with a publisher or subscriber in the domain")
    ls.add_argument("-t", "--show-types", action="store_true", help="print each topic's message type")
    ls.add_argument("--wait", type=float, default=1.0, help="seconds to gather discovery replies (default 1)")
    add_transport_args(ls)
    ls.set_defaults(func=run_list)

    echo = sub.add_parser("echo", help="print the messages of a topic (YAML)")
    echo.add_argument("topic", metavar="TOPIC")
    echo.add_argument("--once", action="store_true", help="print one message and exit")
    echo.add_argument("--count", type=int, default=0, help="exit after this many messages")
    echo.add_argument(
        "--timeout", type=float, default=None, help="fail after this many seconds without messages"
    )
    add_transport_args(echo)
    echo.set_defaults(func=run_echo)

    hz = sub.add_parser("hz", help="print the publishing rate of a topic")
    hz.add_argument("topic", metavar="TOPIC")
    hz.add_argument("--window", type=int, default=10000, help="number of intervals averaged (default 10000)")
    hz.add_argument(
        "--duration", type=float, default=0.0, help="exit after this many seconds (default: never)"
    )
    add_transport_args(hz)
    hz.set_defaults(func=run_hz)


def message_type(topic: str) -> type:
    """The message class carried by one of our topics.

    Raises:
        ValueError: Not a topic urdftk can decode.
    """
    from tf.messages import JointState, TFMessage

    name = "/" + topic.strip("/")
    if name.endswith(("/tf", "/tf_static")):
        return TFMessage
    if name.endswith("/joint_states"):
        return JointState
    raise ValueError(
        f"{topic}: urdftk decodes /tf, /tf_static and /joint_states (and namespaced variants) only"
    )


def run_list(args: argparse.Namespace) -> int:
    """Print every topic announced by a liveliness token in the domain."""
    from tf.transport._keys import type_info_by_dds

    with open_transport(args, "topic_list") as bus:
        tokens = bus.graph(timeout=args.wait)
        own = bus.zid
    topics: dict[str, str] = {}
    for token in tokens:
        if token.kind in ("MP", "MS") and token.zid != own:
            known = type_info_by_dds(token.dds_type)
            topics[token.topic] = known[1].ros_name if known else token.dds_type
    for topic in sorted(topics):
        print(f"{topic} [{topics[topic]}]" if args.show_types else topic)
    return 0


def _yaml(msg) -> str:
    import dataclasses

    import yaml

    def plain(value):
        if dataclasses.is_dataclass(value):
            return {f.name: plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
        if isinstance(value, tuple):
            return [plain(v) for v in value]
        return value

    return yaml.safe_dump(plain(msg), sort_keys=False, allow_unicode=True, default_flow_style=False)


def run_echo(args: argparse.Namespace) -> int:
    """Print messages as YAML documents separated by ``---``."""
    import queue

    msg_type = message_type(args.topic)
    limit = 1 if args.once else args.count
    inbox: queue.Queue = queue.Queue()
    with open_transport(args, "topic_echo") as bus:
        bus.subscribe(args.topic, msg_type, inbox.put)
        shown = 0
        while not limit or shown < limit:
            try:
                msg = inbox.get(timeout=args.timeout)
            except queue.Empty:
                raise TimeoutError(f"no message on {args.topic} within {args.timeout} s") from None
            sys.stdout.write(_yaml(msg) + "---\n")
            sys.stdout.flush()
            shown += 1
    return 0


def run_hz(args: argparse.Namespace) -> int:
    """Print the average rate, min/max interval and their standard deviation every second."""
    import itertools
    import statistics
    import threading
    import time
    from collections import deque

    msg_type = message_type(args.topic)
    arrivals: deque[float] = deque(maxlen=args.window + 1)
    lock = threading.Lock()

    def on_msg(_msg) -> None:
        with lock:
            arrivals.append(time.monotonic())

    stop = threading.Event()
    end = time.monotonic() + args.duration if args.duration > 0 else None
    with open_transport(args, "topic_hz") as bus:
        bus.subscribe(args.topic, msg_type, on_msg)
        while True:
            remaining = None if end is None else end - time.monotonic()
            if remaining is not None and remaining <= 0:
                return 0
            stop.wait(1.0 if remaining is None else min(1.0, remaining))
            with lock:
                stamps = list(arrivals)
            if len(stamps) < 2:
                print("no new messages", flush=True)
                continue
            gaps = [b - a for a, b in itertools.pairwise(stamps)]
            mean = sum(gaps) / len(gaps)
            std = statistics.pstdev(gaps)
            print(
                f"average rate: {1.0 / mean:.3f}\n\tmin: {min(gaps):.3f}s max: {max(gaps):.3f}s "
                f"std dev: {std:.5f}s window: {len(gaps)}",
                flush=True,
            )
