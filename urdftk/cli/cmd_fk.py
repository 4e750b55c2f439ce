"""``urdftk fk FILE [joint:=value ...] [--frame NAME] [--format table|json]``: link poses for a configuration.

Joint values are radians (revolute, continuous) or metres (prismatic); joints not given are at their
neutral value. Poses are ``T_root_frame``: translation in metres and an xyzw quaternion.
xacro arguments are passed with ``--arg name:=value``.
"""

from __future__ import annotations

import argparse

from urdftk.cli._common import add_package_path_arg, split_mappings

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``fk`` subcommand."""
    parser = subparsers.add_parser(
        "fk",
        help="forward kinematics: link poses for joint values given as joint:=value",
        description=(
            "Print T_root_frame for every link (or the --frame ones) at the configuration given by "
            "joint:=value (radians or metres; other joints neutral). Exit 2 on bad input."
        ),
    )
    parser.add_argument("robot", metavar="ROBOT", help=".urdf or .xacro file")
    parser.add_argument("joints", nargs="*", metavar="joint:=value", help="joint values (rad or m)")
    parser.add_argument(
        "--frame", action="append", default=[], metavar="NAME", help="frame to print; repeatable"
    )
    parser.add_argument("--format", choices=("table", "json"), default="table", help="output format")
    parser.add_argument("--clip", action="store_true", help="clip out-of-limit values instead of failing")
    parser.add_argument(
        "--arg", action="append", default=[], metavar="name:=value", help="xacro argument; repeatable"
    )
    add_package_path_arg(parser)
    parser.set_defaults(func=run)


def _float(name: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"joint value {name}:={text} is not a number") from None


def run(args: argparse.Namespace) -> int:
    """Run ``urdftk fk``; return the exit status."""
    import json
    import sys

    from urdftk.loading import load
    from urdftk.pose import Pose

    extra, joints = split_mappings(args.joints)
    if extra:
        raise ValueError(f"unexpected argument(s) {' '.join(extra)}; joint values are written joint:=value")
    bad_args, xacro_args = split_mappings(args.arg)
    if bad_args:
        raise ValueError(f"--arg {bad_args[0]}: xacro arguments are written name:=value")
    robot = load(args.robot, args=xacro_args, package_paths=args.package_path)
    q = robot.q({name: _float(name, text) for name, text in joints.items()}, clip=args.clip)
    names = list(args.frame) or list(robot.link_names)
    poses = {name: Pose(robot.frame_pose(name, q)) for name in names}
    if args.format == "json":
        doc = {
            "robot": robot.name,
            "root": robot.root_link,
            "joints": robot.joint_positions(q),
            "frames": {
                name: {
                    "translation": p.translation.tolist(),
                    "quaternion_xyzw": p.quaternion.tolist(),
                    "matrix": p.matrix.tolist(),
                }
                for name, p in poses.items()
            },
        }
        sys.stdout.write(json.dumps(doc, indent=2) + "\n")
        return 0
    width = max(len("frame"), *(len(n) for n in names))
    header = f"{'frame':<{width}}  {'x':>10} {'y':>10} {'z':>10}  {'qx':>9} {'qy':>9} {'qz':>9} {'qw':>9}"
    lines = [f"robot {robot.name}: poses in {robot.root_link}", header, "-" * len(header)]
    for name, p in poses.items():
        t, quat = p.translation, p.quaternion
        lines.append(
            f"{name:<{width}}  {t[0]:>10.6f} {t[1]:>10.6f} {t[2]:>10.6f}  "
            f"{quat[0]:>9.6f} {quat[1]:>9.6f} {quat[2]:>9.6f} {quat[3]:>9.6f}"
        )
    sys.stdout.write("\n".join(lines) + "\n")
    return 0
