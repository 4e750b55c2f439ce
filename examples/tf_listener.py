#!/usr/bin/env python
"""Listening to tf: print where the course's frame is in ``world``, like ``tf_echo world my_FrameName``.

Run it next to ``examples/tf_broadcaster.py``, in another terminal (the default transport is
Zenoh, so the two processes find each other with no configuration):

    python examples/tf_broadcaster.py &
    python examples/tf_listener.py --count 5
"""

from __future__ import annotations

import argparse
import math
import sys

import tf
from tf.transformations import euler_from_quaternion


def listen(target="world", source="my_FrameName", count=None, timeout=5.0, transport=None, out=sys.stdout):
    """Print ``count`` transforms (None: until Ctrl-C) at 2 Hz; returns how many were printed."""
    buffer = tf.Buffer()
    printed = 0
    rate = tf.Rate(2)
    with tf.TransformListener(buffer, transport):
        while count is None or printed < count:
            try:
                t = buffer.lookup_transform(target, source, tf.Time(), timeout=tf.Duration.from_sec(timeout))
            except tf.TransformException as exc:
                print(f"Waiting for {source} in {target}: {exc}", file=sys.stderr)
                return printed
            p, q = t.transform.translation, t.transform.rotation
            rpy = euler_from_quaternion((q.x, q.y, q.z, q.w))
            print(f"At time {t.header.stamp.to_sec():.3f}", file=out)
            print(f"- Translation: [{p.x:.3f}, {p.y:.3f}, {p.z:.3f}]", file=out)
            print(f"- Rotation: in Quaternion [{q.x:.3f}, {q.y:.3f}, {q.z:.3f}, {q.w:.3f}]", file=out)
            print(f"            in RPY (radian) [{rpy[0]:.3f}, {rpy[1]:.3f}, {rpy[2]:.3f}]", file=out)
            degrees = ", ".join(f"{math.degrees(a):.3f}" for a in rpy)
            print(f"            in RPY (degree) [{degrees}]", file=out, flush=True)
            printed += 1
            if count is None or printed < count:
                rate.sleep()
    return printed


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("target", nargs="?", default="world", help="frame to express the pose in")
    parser.add_argument("source", nargs="?", default="my_FrameName", help="frame whose pose is printed")
    parser.add_argument("--count", type=int, default=None, help="stop after this many transforms")
    parser.add_argument("--timeout", type=float, default=5.0, help="seconds to wait for each transform")
    args = parser.parse_args(argv)
    try:
        printed = listen(args.target, args.source, count=args.count, timeout=args.timeout)
    except KeyboardInterrupt:
        return 0
    return 0 if args.count is None or printed == args.count else 1


if __name__ == "__main__":
    sys.exit(main())
