"""``urdftk joint-state-publisher`` and ``urdftk robot-state-publisher``: the state publisher nodes."""

from __future__ import annotations

import argparse

from urdftk.cli._common import add_robot_args, split_mappings
from urdftk.cli._transport import add_transport_args, open_transport

__all__ = ["register", "run_joint_state_publisher", "run_robot_state_publisher"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the two node subcommands."""
    jsp = subparsers.add_parser(
        "joint-state-publisher",
        help="publish joint positions on /joint_states",
        description="Publish every movable joint on /joint_states: zeros clamped into the limits, "
        "overridden by --zeros and by the --source-list topics; mimic joints follow their masters.",
    )
    add_robot_args(jsp)
    jsp.add_argument("--rate", type=float, default=10.0, help="publishing rate in Hz (default 10)")
    jsp.add_argument(
        "--source-list", nargs="+", default=[], metavar="TOPIC", help="JointState topics to merge"
    )
    jsp.add_argument(
        "--zeros", action="append", default=[], metavar="JOINT=VALUE", help="initial joint value (repeatable)"
    )
    add_transport_args(jsp)
    jsp.set_defaults(func=run_joint_state_publisher)

    rsp = subparsers.add_parser(
        "robot-state-publisher",
        help="turn /joint_states into /tf and /tf_static",
        description="Publish fixed joints once on latched /tf_static and moving joints on /tf, stamped "
        "with the joint-state stamp.",
    )
    add_robot_args(rsp)
    rsp.add_argument(
        "--frame-prefix", default="", metavar="P", help="prefix for every frame id, e.g. robot1/"
    )
    rsp.add_argument(
        "--publish-frequency", type=float, default=50.0, help="max /tf rate per joint in Hz (50)"
    )
    add_transport_args(rsp)
    rsp.set_defaults(func=run_robot_state_publisher)


def _load(args: argparse.Namespace):
    import urdftk

    plain, mappings = split_mappings([args.robot, *args.mappings])
    if len(plain) != 1:
        raise ValueError(f"expected one ROBOT file and name:=value arguments, got {' '.join(plain)}")
    return urdftk.load(plain[0], args=mappings, package_paths=args.package_path)


def _zeros(items: list[str]) -> dict[str, float]:
    out: dict[str, float] = {}
    for item in items:
        name, sep, value = item.partition("=")
        try:
            if not sep or not name:
                raise ValueError
            out[name] = float(value)
        except ValueError:
            raise ValueError(
                f"--zeros {item!r}: expected JOINT=VALUE, e.g. --zeros elbow_joint=0.5"
            ) from None
    return out


def _wait_forever(what: str) -> None:
    import threading

    print(f"{what} running (Ctrl-C to stop)", flush=True)
    threading.Event().wait()


def run_joint_state_publisher(args: argparse.Namespace) -> int:
    """Run the joint state publisher until interrupted."""
    from urdftk.joint_state import JointStatePublisher

    robot = _load(args)
    zeros = _zeros(args.zeros)
    with open_transport(args, "joint_state_publisher") as bus:
        node = JointStatePublisher(robot, bus, rate=args.rate, source_list=args.source_list, zeros=zeros)
        try:
            node.start()
            _wait_forever(f"joint_state_publisher for {robot.name} ({len(node.positions)} joints)")
        finally:
            node.close()
    return 0


def run_robot_state_publisher(args: argparse.Namespace) -> int:
    """Run the robot state publisher until interrupted."""
    from urdftk.robot_state import RobotStatePublisher

    robot = _load(args)
    with open_transport(args, "robot_state_publisher") as bus:
        node = RobotStatePublisher(
            robot, bus, frame_prefix=args.frame_prefix, publish_frequency=args.publish_frequency
        )
        try:
            _wait_forever(f"robot_state_publisher for {robot.name}")
        finally:
            node.close()
    return 0
