"""``urdftk record``, ``urdftk play`` and ``urdftk bag info|export``: rosbag2 (MCAP) recordings."""

from __future__ import annotations

import argparse

from urdftk.cli._transport import add_transport_args, open_transport

__all__ = ["register", "run_export", "run_info", "run_play", "run_record"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``record``, ``play`` and ``bag``."""
    rec = subparsers.add_parser(
        "record",
        help="record topics into a rosbag2 (MCAP) folder",
        description="Record /tf, /tf_static and /joint_states (or --topics) until Ctrl-C.",
    )
    rec.add_argument("-o", "--output", required=True, metavar="DIR", help="bag folder to create")
    rec.add_argument("--topics", nargs="+", default=None, metavar="TOPIC")
    rec.add_argument("--flush-interval", type=float, default=1.0, help="seconds between complete files (1)")
    rec.add_argument(
        "--duration", type=float, default=0.0, help="stop after this many seconds (default: never)"
    )
    add_transport_args(rec)
    rec.set_defaults(func=run_record)

    play = subparsers.add_parser("play", help="republish a recording with its original timing")
    play.add_argument("bag", metavar="BAG")
    play.add_argument("--rate", type=float, default=1.0, help="speed factor (default 1.0)")
    play.add_argument("--loop", action="store_true", help="start again at the end")
    play.add_argument("--topics", nargs="+", default=None, metavar="TOPIC")
    play.add_argument("--wait", type=float, default=1.0, help="seconds to wait for subscribers first (1)")
    add_transport_args(play)
    play.set_defaults(func=run_play)

    bag = subparsers.add_parser("bag", help="inspect and export recordings")
    sub = bag.add_subparsers(dest="bag_command", metavar="VERB")
    sub.required = True
    info = sub.add_parser("info", help="print a summary of a recording")
    info.add_argument("bag", metavar="BAG")
    info.set_defaults(func=run_info)
    export = sub.add_parser("export", help="write one topic as CSV (rostopic echo -b -p)")
    export.add_argument("bag", metavar="BAG")
    export.add_argument("topic", metavar="TOPIC")
    export.add_argument("-o", "--output", required=True, metavar="CSV")
    export.set_defaults(func=run_export)


def run_record(args: argparse.Namespace) -> int:
    """Record until Ctrl-C or ``--duration``."""
    import signal
    import threading

    from urdftk.recording import DEFAULT_TOPICS, Recorder

    with open_transport(args, "recorder") as bus:
        recorder = Recorder(
            args.output, bus, args.topics or DEFAULT_TOPICS, flush_interval=args.flush_interval
        )
        timer = None
        if args.duration > 0:
            timer = threading.Timer(args.duration, recorder.stop)
            timer.start()
        for signum in (signal.SIGINT, signal.SIGTERM):  # stop cleanly: write what was received
            signal.signal(signum, lambda *_: recorder.stop())
        print(f"recording {', '.join(recorder.topics)} to {args.output} (Ctrl-C to stop)", flush=True)
        try:
            count = recorder.run()
        except KeyboardInterrupt:  # run() has already written what it had
            count = recorder.count
        finally:
            if timer is not None:
                timer.cancel()
    print(f"recorded {count} messages to {args.output}", flush=True)
    return 0


def run_play(args: argparse.Namespace) -> int:
    """Republish a bag."""
    from urdftk.recording import play

    with open_transport(args, "player") as bus:
        sent = play(
            args.bag, bus, rate=args.rate, loop=args.loop, topics=args.topics, wait_for_subscribers=args.wait
        )
    print(f"played {sent} messages", flush=True)
    return 0


def run_info(args: argparse.Namespace) -> int:
    """Print the bag summary."""
    from urdftk.recording import bag_info

    print(bag_info(args.bag))
    return 0


def run_export(args: argparse.Namespace) -> int:
    """Write the CSV."""
    from urdftk.recording import export_csv

    rows = export_csv(args.bag, args.topic, args.output)
    print(f"wrote {rows} rows to {args.output}")
    return 0
