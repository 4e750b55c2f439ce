"""``urdftk tf echo|frames|static``: tf2_echo, view_frames and static_transform_publisher over the network."""

from __future__ import annotations

import argparse
import sys

from urdftk.cli._transport import add_transport_args, open_transport

__all__ = ["register", "run_echo", "run_frames", "run_static"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``tf`` and its three subcommands."""
    p = subparsers.add_parser(
        "tf", help="tf tools: echo, frames, static", description="tf tools over the network."
    )
    sub = p.add_subparsers(dest="tf_command", metavar="TOOL")
    sub.required = True

    echo = sub.add_parser(
        "echo",
        help="print a transform like tf2_echo",
        description="Print the pose of TARGET in "
        "SOURCE (lookup_transform(SOURCE, TARGET)) at --rate Hz, in tf2_echo's format.",
    )
    echo.add_argument("source", metavar="SOURCE")
    echo.add_argument("target", metavar="TARGET")
    echo.add_argument("--rate", type=float, default=1.0, help="prints per second (default 1)")
    echo.add_argument("--count", type=int, default=0, help="exit after this many prints (default: never)")
    echo.add_argument(
        "--timeout", type=float, default=None, help="give up after this many seconds without data"
    )
    add_transport_args(echo)
    echo.set_defaults(func=run_echo)

    frames = sub.add_parser("frames", help="draw the live frame tree (view_frames)")
    frames.add_argument(
        "-o", "--output", default="frames.pdf", help="frames.pdf | .png | .svg | .gv (dot text)"
    )
    frames.add_argument("--duration", type=float, default=5.0, help="seconds to listen (default 5)")
    add_transport_args(frames)
    frames.set_defaults(func=run_frames)

    static = sub.add_parser(
        "static",
        help="publish a static transform (static_transform_publisher)",
        description="x y z yaw pitch roll PARENT CHILD | x y z qx qy qz qw PARENT CHILD | ROS 2 flags.",
    )
    static.add_argument("values", nargs="*", metavar="ARG")
    for name in ("x", "y", "z", "roll", "pitch", "yaw", "qx", "qy", "qz", "qw"):
        static.add_argument(f"--{name}", type=float, default=None)
    static.add_argument("--frame-id", default=None)
    static.add_argument("--child-frame-id", default=None)
    static.add_argument("--once", action="store_true", help="exit once a listener could fetch it (1 s)")
    add_transport_args(static)
    static.set_defaults(func=run_static)


def run_echo(args: argparse.Namespace) -> int:
    """Print the transform at ``--rate`` until interrupted (or ``--count`` prints)."""
    import threading
    import time

    import tf
    from urdftk.tftools import format_echo

    if not args.rate > 0:
        raise ValueError(f"--rate must be > 0, got {args.rate}")
    with open_transport(args, "tf2_echo") as bus:
        buffer = tf.Buffer()
        tf.TransformListener(buffer, bus)
        if not buffer.can_transform(args.source, args.target, tf.Time(), timeout=0.5):
            why = buffer.why_not(args.source, args.target)
            print(
                f"Waiting for transform {args.source} ->  {args.target}: {why}", file=sys.stderr, flush=True
            )
            timeout = args.timeout if args.timeout is not None else 1e9
            if not buffer.can_transform(args.source, args.target, tf.Time(), timeout=timeout):
                raise tf.TimeoutException(
                    f"no transform {args.source} -> {args.target} within {args.timeout} s: "
                    f"{buffer.why_not(args.source, args.target)}"
                )
        stop = threading.Event()
        printed = 0
        while True:
            try:
                t = buffer.lookup_transform(args.source, args.target, tf.Time())
                print(format_echo(t), flush=True)
            except tf.TransformException as exc:
                print(f"Failure at {time.time():.9f}\nException thrown:{exc}", flush=True)
                print(f"The current list of frames is:\n{buffer.all_frames_as_string()}", flush=True)
            printed += 1
            if args.count and printed >= args.count:
                return 0
            stop.wait(1.0 / args.rate)


def run_frames(args: argparse.Namespace) -> int:
    """Listen for ``--duration`` seconds, then write the frame graph."""
    import threading
    from pathlib import Path

    import yaml

    import tf
    from tf.messages import TFMessage
    from urdftk._atomic import write_atomic
    from urdftk.tftools import frames_dot, render_dot

    out = Path(args.output)
    fmt = out.suffix.lower().lstrip(".")
    if fmt not in ("pdf", "png", "svg", "gv", "dot"):
        raise ValueError(f"{out}: the output must end in .pdf, .png, .svg or .gv")
    with open_transport(args, "view_frames") as bus:
        buffer = tf.Buffer()

        def authority(info) -> str:
            return info.attachment.gid.hex() if info.attachment is not None else "unknown"

        def on_tf(msg: TFMessage, info) -> None:
            for t in msg.transforms:
                buffer.set_transform(t, authority(info))

        def on_static(msg: TFMessage, info) -> None:
            for t in msg.transforms:
                buffer.set_transform_static(t, authority(info))

        bus.subscribe_info("/tf", TFMessage, on_tf)
        bus.subscribe_info("/tf_static", TFMessage, on_static)
        print(f"Listening to /tf for {args.duration:g} seconds", file=sys.stderr, flush=True)
        threading.Event().wait(args.duration)
        names = {t.gid.hex(): t.node_name for t in bus.graph(timeout=1.0) if t.kind == "MP"}
        now = tf.Time.now()
        frames = yaml.safe_load(buffer.all_frames_as_yaml(now)) or {}
    for info in frames.values():
        info["broadcaster"] = names.get(str(info["broadcaster"]), info["broadcaster"])
    if not frames:
        print("warning: no frames received; writing an empty graph", file=sys.stderr)
    dot = frames_dot(frames, now)
    write_atomic(out, dot if fmt in ("gv", "dot") else render_dot(dot, fmt))
    print(f"wrote {out} ({len(frames)} frames)", flush=True)
    return 0


def run_static(args: argparse.Namespace) -> int:
    """Publish one static transform on latched /tf_static until interrupted."""
    import threading

    import tf
    from urdftk.tftools import parse_static_args

    transform = parse_static_args(
        args.values,
        xyz=(args.x, args.y, args.z),
        rpy=(args.roll, args.pitch, args.yaw),
        quaternion=(args.qx, args.qy, args.qz, args.qw),
        frame_id=args.frame_id,
        child_frame_id=args.child_frame_id,
    )
    with open_transport(args, "static_transform_publisher") as bus:
        broadcaster = tf.StaticTransformBroadcaster(bus)
        broadcaster.send_transform(transform)
        print(
            f"publishing static transform from {transform.header.frame_id} to {transform.child_frame_id}",
            flush=True,
        )
        threading.Event().wait(1.0 if args.once else None)
        broadcaster.close()
    return 0
