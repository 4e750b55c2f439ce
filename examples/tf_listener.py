#!/usr/bin/env python
"""Listening to tf: print where ``my_frame`` is in ``world``, like ``tf_echo world my_frame``.

Run it next to ``examples/tf_broadcaster.py`` (over Zenoh, the default transport), or alone with
``--broadcast``, which also runs the course broadcaster in this process (in-process transport
friendly):

    URDFTK_TRANSPORT=inproc python examples/tf_listener.py --broadcast --count 5
"""

from __future__ import annotations

import argparse
import math
import sys
import threading

import tf
from tf.transformations import euler_from_quaternion


def listen(target="world", source="my_frame", count=None, timeout=5.0, transport=None, out=sys.stdout):
    """Print ``count`` transforms (None: until Ctrl-C) at 2 Hz; returns how many were printed."""
    buffer = tf.Buffer()
    printed = 0
    stop = threading.Event()
    with tf.TransformListener(buffer, transport):
        while count is None or printed < count:
            try:
                t = buffer.lookup_transform(target, source, tf.Time(), timeout=timeout)
            except tf.TransformException as exc:
                print(f"Waiting for {source} in {target}: {exc}", file=sys.stderr)
                return printed
            p, q = t.transform.translation, t.transform.rotation
            rpy = euler_from_quaternion((q.x, q.y, q.z, q.w))
            print(f"At time {t.header.stamp.to_sec():.3f}", file=out)
            print(f"- Translation: [{p.x:.3f}, {p.y:.3f}, {p.z:.3f}]", file=out)
            print(f"- Rotation: in Quaternion [{q.x:.3f}, {q.y:.3f}, {q.z:.3f}, {q.w:.3f}]", file=out)
            print(f"            in RPY (radian) [{rpy[0]:.3f}, {rpy[1]:.3f}, {rpy[2]:.3f}]", file=out)
            print(
                f"            in RPY (degree) [{', '.join(f'{math.degrees(a):.3f}' for a in rpy)}]", file=out
            )
            printed += 1
            stop.wait(0.5)
    return printed


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=None, help="stop after this many transforms")
    parser.add_argument("--timeout", type=float, default=5.0, help="seconds to wait for each transform")
    parser.add_argument("--broadcast", action="store_true", help="also run the course broadcaster here")
    args = parser.parse_args(argv)
    stop = threading.Event()
    if args.broadcast:
        import tf_broadcaster  # the course example, next to this file

        threading.Thread(target=tf_broadcaster.myPublishFunction, kwargs={"stop": stop}, daemon=True).start()
    try:
        printed = listen(count=args.count, timeout=args.timeout)
    except KeyboardInterrupt:
        return 0
    finally:
        stop.set()
    return 0 if args.count is None or printed == args.count else 1


if __name__ == "__main__":
    sys.exit(main())
