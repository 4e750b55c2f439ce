"""Child process for the Zenoh tests: ``python zenoh_child.py ROLE [options]``.

Roles:
  broadcast  publish a moving chain world -> f0 -> ... on /tf at --rate Hz
  static     send static transforms once (latched /tf_static), then stay alive
  flood      wait for a subscriber, then publish --count TFMessages of --frames transforms at --rate
  garbage    put garbage payloads (and one valid message) on the raw /tf key
  listen     TransformListener; print "pose x y z qx qy qz qw" of --target/--source when available

Every role prints "ready" once its session is open and exits when stdin closes (parent gone).
The transport comes from the environment (zero-config unless URDFTK_ZENOH_* are set).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import threading
import time

import tf
from tf.messages import Header, Quaternion, TFMessage, Time, Transform, TransformStamped, Vector3
from tf.transport.zenoh import ZenohTransport


def _exit_when_parent_goes() -> threading.Event:
    stop = threading.Event()

    def watch() -> None:
        sys.stdin.read()
        stop.set()
        os._exit(0)

    threading.Thread(target=watch, daemon=True).start()
    return stop


def _chain(n: int, stamp: Time, phase: float) -> TFMessage:
    out = []
    for i in range(n):
        parent = "world" if i == 0 else f"f{i - 1}"
        a = phase + 0.01 * i
        out.append(
            TransformStamped(
                Header(stamp, parent),
                f"f{i}",
                Transform(
                    Vector3(1.0 + i, math.sin(a), 0.5), Quaternion(0.0, 0.0, math.sin(a / 2), math.cos(a / 2))
                ),
            )
        )
    return TFMessage(tuple(out))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("role")
    parser.add_argument("--rate", type=float, default=50.0)
    parser.add_argument("--frames", type=int, default=3)
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--target", default="world")
    parser.add_argument("--source", default="f2")
    args = parser.parse_args()
    stop = _exit_when_parent_goes()
    bus = ZenohTransport(node_name=f"child_{args.role}")
    print("ready", flush=True)
    if args.role == "broadcast":
        br = tf.TransformBroadcaster(bus)
        k = 0
        while not stop.wait(1.0 / args.rate):
            br.send_transform(_chain(args.frames, Time.now(), 0.01 * k).transforms)
            k += 1
            if k == 1:
                print("first sent", flush=True)
    elif args.role == "static":
        sbr = tf.StaticTransformBroadcaster(bus)
        for i in range(args.frames):
            parent = "world" if i == 0 else f"s{i - 1}"
            sbr.send_transform(
                TransformStamped(
                    Header(Time(1, 0), parent), f"s{i}", Transform(Vector3(float(i + 1), 0.0, 0.0))
                )
            )
        print("sent", flush=True)
        stop.wait()
    elif args.role == "flood":
        pub = bus.publisher("/tf", TFMessage)
        if not pub.wait_for_subscribers(20.0):
            print("no subscriber", flush=True)
            return
        time.sleep(0.5)  # let the subscriber's routes settle on every link
        period = 1.0 / args.rate
        start = time.perf_counter()
        for k in range(args.count):
            deadline = start + k * period
            delay = deadline - time.perf_counter()
            if delay > 0:
                time.sleep(delay)
            pub.publish(_chain(args.frames, Time.now(), 0.001 * k))
        print(f"done {args.count} in {time.perf_counter() - start:.3f}s", flush=True)
        stop.wait()
    elif args.role == "garbage":
        from tf.transport import _keys

        key = _keys.topic_key(bus.domain_id, "/tf", _keys.type_info(TFMessage))
        session = bus._session
        time.sleep(1.0)
        for payload in (b"", b"\x00", b"garbage!" * 10, b"\x00\x01\x00\x00\xff\xff\xff\x7f", os.urandom(300)):
            session.put(key, payload)
        pub = bus.publisher("/tf", TFMessage)
        pub.publish(_chain(1, Time(7, 0), 0.0))
        print("sent", flush=True)
        stop.wait()
    elif args.role == "listen":
        buffer = tf.Buffer()
        tf.TransformListener(buffer, bus)
        t = buffer.lookup_transform(args.target, args.source, Time(), timeout=20.0).transform
        r, q = t.translation, t.rotation
        print(f"pose {r.x!r} {r.y!r} {r.z!r} {q.x!r} {q.y!r} {q.z!r} {q.w!r}", flush=True)
        stop.wait()
    else:
        raise SystemExit(f"unknown role {args.role}")


if __name__ == "__main__":
    main()
