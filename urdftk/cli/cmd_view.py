"""``urdftk view ROBOT [name:=value ...]``: the robot, its joints and TF in the browser.

What a ROS launch file with joint_state_publisher_gui, robot_state_publisher and rviz gives, in
one command. Prints the URL, then serves until Ctrl-C (or, with ``--screenshot``, renders one
frame in headless Chromium, writes the PNG and exits).
"""

from __future__ import annotations

import argparse

from urdftk.cli._common import add_robot_args, split_mappings

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``view`` subcommand."""
    parser = subparsers.add_parser(
        "view",
        help="show a robot with joint sliders and TF frames in the browser",
        description=(
            "Serve a page showing the robot (meshes and colours), joint sliders, TF axes/names/arrows and a "
            "fixed-frame choice. Binds 127.0.0.1 unless --host is given."
        ),
    )
    add_robot_args(parser)
    parser.add_argument(
        "--backend", choices=("viser", "meshcat"), default="viser", help="display (default viser)"
    )
    parser.add_argument("--host", default="127.0.0.1", help="interface to bind (default 127.0.0.1)")
    parser.add_argument(
        "--port", type=int, default=None, help="TCP port (default 8080 viser, 7000 meshcat; 0: any)"
    )
    parser.add_argument(
        "--listen",
        action="store_true",
        help="take /tf, /tf_static and /joint_states from the network (Zenoh) instead of the sliders",
    )
    parser.add_argument(
        "--publish",
        action="store_true",
        help="also publish /joint_states (10 Hz) and the robot's /tf, /tf_static on the network (Zenoh)",
    )
    parser.add_argument(
        "--watch", action="store_true", help="reload when the file or any included file changes"
    )
    parser.add_argument("--fixed-frame", metavar="NAME", default=None, help="frame the scene is expressed in")
    parser.add_argument(
        "--screenshot",
        metavar="PNG",
        default=None,
        help="render one frame in headless Chromium, save it, exit",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run ``urdftk view``; return the exit status."""
    import contextlib
    import signal
    import sys
    import threading

    from urdftk.errors import UrdftkError
    from urdftk.viewer import Viewer
    from urdftk.viewer._reload import FileWatcher, load_robot

    extra, mappings = split_mappings(args.mappings)
    if extra:
        raise ValueError(f"unexpected argument(s) {' '.join(extra)}; xacro arguments are written name:=value")
    if args.listen and args.publish:
        raise ValueError("--listen and --publish exclude each other (listen shows what others publish)")
    if args.port is not None and not 0 <= args.port <= 65535:
        raise ValueError(f"--port {args.port} is not a TCP port (0..65535)")
    robot, files = load_robot(args.robot, mappings, args.package_path, with_includes=args.watch)
    transport = None
    if args.listen or args.publish:
        from tf.transport.zenoh import ZenohTransport

        transport = ZenohTransport()
    port = args.port if args.port is not None else (8080 if args.backend == "viser" else 7000)
    stop = threading.Event()
    viewer = Viewer(
        robot,
        backend=args.backend,
        host=args.host,
        port=port,
        fixed_frame=args.fixed_frame,
        transport=transport,
        listen=args.listen,
        rate=10.0 if args.publish else None,
    )
    watcher = None
    try:
        print(f"urdftk view: {robot.name} at {viewer.url}", flush=True)
        if args.screenshot:
            from urdftk.viewer._screenshot import save_screenshot

            viewer.refresh()
            save_screenshot(viewer.url, args.screenshot)
            print(f"urdftk view: wrote {args.screenshot}", flush=True)
            return 0
        if args.watch:

            def reload() -> None:
                try:
                    new_robot, new_files = load_robot(
                        args.robot, mappings, args.package_path, with_includes=True
                    )
                except (UrdftkError, OSError, ValueError) as exc:
                    text = " ".join(str(exc).split())
                    print(
                        f"urdftk view: reload failed, keeping the previous robot: {text}",
                        file=sys.stderr,
                        flush=True,
                    )
                    viewer.show_status(f"Reload failed, showing the previous robot: {text}", error=True)
                    return
                viewer.load(new_robot)
                viewer.show_status("")
                watcher.set_files(new_files)  # type: ignore[union-attr]
                print(f"urdftk view: reloaded {args.robot}", flush=True)

            watcher = FileWatcher(files, reload)
        signal.signal(signal.SIGTERM, lambda *_: stop.set())
        with contextlib.suppress(KeyboardInterrupt):
            stop.wait()
        return 0
    finally:
        if watcher is not None:
            watcher.close()
        viewer.close()
        if transport is not None:
            transport.close()
