"""Transport benchmark: Zenoh (urdftk's transport) vs ZeroMQ PUB/SUB, two processes on 127.0.0.1.

    python bench/transport.py [--seconds 5] [--burst 20000]

Measures, for a TFMessage of 30 transforms (CDR, 2.6 kB):
- latency p50/p99 (publisher's stamp before building the message -> subscriber callback with the
  decoded message) at 100 Hz and 1 kHz;
- sustained messages/s with no loss (publisher sends as fast as it can, subscriber counts);
- CPU per side at 1 kHz (process CPU time / wall time, in % of one core); the publisher's figure
  includes building the messages with the public constructors, which is also shown on its own;
- the floor under those CPU figures, measured in the same run: a bare publisher loop that only
  paces itself at the rate (no sending), and bare Zenoh (``zenoh-raw``: the same session
  configuration, a prebuilt payload put with a 33-byte attachment, a callback that only reads the
  stamp), i.e. what any Python program moving these bytes over Zenoh pays before urdftk's code;
- the tf listener side (``listener``): urdftk's publisher, and on the other side a
  ``tf.TransformListener`` storing every transform in a ``tf.Buffer`` (what a tf user runs);
- end to end: JointState -> RobotStatePublisher (own process) -> /tf -> Buffer lookup latency.
Both transports use the same codec, so the ratios compare the transports themselves.
"""

from __future__ import annotations

import argparse
import math
import os
import random
import subprocess
import sys
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from tf.messages import Header, JointState, Quaternion, TFMessage, Time, Transform, TransformStamped, Vector3  # noqa: E402
from tf.transport import _cdr  # noqa: E402

N_TF = 30
PARENTS = tuple("world" if i == 0 else f"link_{i - 1}" for i in range(N_TF))
CHILDREN = tuple(f"link_{i}" for i in range(N_TF))
ROBOT = REPO / "examples/robots/mobile_manipulator_description/urdf/mobile_manipulator.urdf.xacro"


def _message(k: int) -> TFMessage:
    """A chain of N_TF moving frames, built with the public constructors as an application would."""
    stamp = Time.from_nsec(time.time_ns())
    angle = k * 1e-3
    qz, qw = math.sin(angle / 2), math.cos(angle / 2)
    return TFMessage(
        tuple(
            TransformStamped(
                Header(stamp, parent),
                child,
                Transform(Vector3(0.1 * i, 0.001 * k, 0.0), Quaternion(0.0, 0.0, qz, qw)),
            )
            for i, (parent, child) in enumerate(zip(PARENTS, CHILDREN, strict=True))
        )
    )


# ------------------------------------------------------------------------------------ child roles
def _raw_key(domain: int) -> str:
    return f"urdftk_bench/{domain}/raw"


def _raw_session():
    import zenoh

    from tf.transport._zconfig import session_config

    return zenoh.open(session_config(environ={}))


def _child(kind: str, rate: float, count: int, port: int, domain: int) -> None:
    """Publish ``count`` messages at ``rate`` (0: flat out), then report CPU use."""
    if kind in ("zenoh", "listener"):
        from tf.transport.zenoh import ZenohTransport

        bus = ZenohTransport(domain_id=domain, environ={})
        pub = bus.publisher("/tf", TFMessage)
        pub.wait_for_subscribers(20)
        time.sleep(0.5)
        send = pub.publish
    elif kind == "zenoh-raw":
        import zenoh

        session = _raw_session()
        zpub = session.declare_publisher(
            _raw_key(domain),
            congestion_control=zenoh.CongestionControl.BLOCK,
            reliability=zenoh.Reliability.RELIABLE,
        )
        body = _cdr.encode(_message(0))[8:]
        attachment = bytes(33)
        time.sleep(2.0)  # discovery (no matching listener in this bare setup)

        def send(_msg: object) -> None:
            zpub.put(time.time_ns().to_bytes(8, "little") + body, attachment=attachment)
    elif kind == "pace":

        def send(_msg: object) -> None:
            pass
    else:
        import zmq

        ctx = zmq.Context()
        sock = ctx.socket(zmq.PUB)
        sock.setsockopt(zmq.SNDHWM, 0)
        sock.bind(f"tcp://127.0.0.1:{port}")
        time.sleep(1.0)  # slow joiner

        def send(msg: TFMessage) -> None:
            sock.send(_cdr.encode(msg), copy=False)

    print("go", flush=True)
    cpu0, wall0 = time.process_time(), time.perf_counter()
    period = 1.0 / rate if rate > 0 else 0.0
    for k in range(count):
        if period:
            delay = wall0 + k * period - time.perf_counter()
            if delay > 0:
                time.sleep(delay)
        send(k if kind in ("zenoh-raw", "pace") else _message(k))
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    build0 = time.process_time()
    for k in range(count):  # what building the messages alone costs (the application's share)
        _message(k)
    build = time.process_time() - build0
    print(f"cpu {cpu / wall * 100:.2f} wall {wall:.3f} build {build / wall * 100:.2f}", flush=True)
    sys.stdin.read()  # stay alive until the parent has everything


def _rsp_child(domain: int) -> None:
    import urdftk
    from tf.transport.zenoh import ZenohTransport
    from urdftk.robot_state import RobotStatePublisher

    robot = urdftk.load(ROBOT)
    bus = ZenohTransport(domain_id=domain, environ={})
    RobotStatePublisher(robot, bus, publish_frequency=0)
    print("go", flush=True)
    sys.stdin.read()


def _jsp_child(domain: int, rate: float, count: int) -> None:
    import urdftk
    from tf.transport.zenoh import ZenohTransport

    robot = urdftk.load(ROBOT)
    bus = ZenohTransport(domain_id=domain, environ={})
    pub = bus.publisher("/joint_states", JointState)
    pub.wait_for_subscribers(20)
    time.sleep(1.0)
    print("go", flush=True)
    rng = random.Random(0)
    for _ in range(count):
        q = robot.random(rng.randrange(1 << 30))
        positions = robot.joint_positions(q)
        pub.publish(
            JointState(Header(Time.from_nsec(time.time_ns()), ""), positions.keys(), positions.values())
        )
        time.sleep(1.0 / rate)
    sys.stdin.read()


# ------------------------------------------------------------------------------------ measuring side
def _spawn(*args: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, __file__, *args], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, cwd=REPO
    )


def _wait_line(proc: subprocess.Popen, prefix: str) -> str:
    for line in proc.stdout:
        if line.startswith(prefix):
            return line.strip()
    raise RuntimeError(f"child ended before {prefix!r}")


def _run(kind: str, rate: float, count: int) -> dict:
    port = random.randrange(20000, 60000)
    domain = random.randrange(10_000, 1_000_000)
    latencies: list[int] = []
    done = threading.Event()

    def on_message(msg: TFMessage) -> None:
        latencies.append(time.time_ns() - msg.transforms[0].header.stamp.nanoseconds)
        if len(latencies) >= count:
            done.set()

    def on_payload(payload: bytes) -> None:
        on_message(_cdr.decode(TFMessage, payload))

    closer = None
    if kind == "zenoh":
        from tf.transport.zenoh import ZenohTransport

        bus = ZenohTransport(domain_id=domain, environ={})
        bus.subscribe("/tf", TFMessage, on_message)
        closer = bus.close
        child = _spawn("_pub", kind, str(rate), str(count), str(port), str(domain))
    elif kind == "listener":
        import tf
        from tf.transport.zenoh import ZenohTransport

        bus = ZenohTransport(domain_id=domain, environ={})
        buffer = tf.Buffer()
        listener = tf.TransformListener(buffer, bus)
        last = CHILDREN[-1]

        def count_stored() -> None:  # the buffer holds every message's stamp for the last frame
            stamps = buffer._core._caches[buffer._core._ids[last]].stamps
            latencies.extend([0] * len(stamps))
            done.set()

        closer = lambda: (count_stored(), listener.close(), bus.close())  # noqa: E731
        child = _spawn("_pub", kind, str(rate), str(count), str(port), str(domain))
    elif kind == "zenoh-raw":
        import zenoh

        session = _raw_session()

        def on_raw(sample: zenoh.Sample) -> None:
            latencies.append(time.time_ns() - int.from_bytes(sample.payload.to_bytes()[:8], "little"))
            if len(latencies) >= count:
                done.set()

        zsub = session.declare_subscriber(_raw_key(domain), zenoh.handlers.Callback(on_raw, indirect=False))
        closer = lambda: (zsub.undeclare(), session.close())  # noqa: E731
        child = _spawn("_pub", kind, str(rate), str(count), str(port), str(domain))
    elif kind == "pace":
        done.set()
        closer = lambda: None  # noqa: E731
        child = _spawn("_pub", kind, str(rate), str(count), str(port), str(domain))
    else:
        import zmq

        child = _spawn("_pub", kind, str(rate), str(count), str(port), str(domain))
        ctx = zmq.Context()
        sock = ctx.socket(zmq.SUB)
        sock.setsockopt(zmq.RCVHWM, 0)
        sock.setsockopt(zmq.SUBSCRIBE, b"")
        sock.connect(f"tcp://127.0.0.1:{port}")

        def loop() -> None:
            while not done.is_set():
                if sock.poll(200):
                    on_payload(sock.recv())

        threading.Thread(target=loop, daemon=True).start()
        closer = lambda: (done.set(), time.sleep(0.3), sock.close(0), ctx.term())  # noqa: E731
    try:
        _wait_line(child, "go")
        cpu0, wall0 = time.process_time(), time.perf_counter()
        report = _wait_line(child, "cpu")
        done.wait(10 if kind != "listener" else 0.2)
        wall = time.perf_counter() - wall0
        sub_cpu = (time.process_time() - cpu0) / wall * 100
    finally:
        child.kill()
        child.wait()
        closer()
    fields = report.split()
    pub_cpu, pub_wall, pub_build = float(fields[1]), float(fields[3]), float(fields[5])
    lat = sorted(latencies)
    pick = (lambda p: lat[min(len(lat) - 1, int(p * len(lat)))] / 1000) if lat else (lambda p: float("nan"))
    return {
        "received": len(lat),
        "sent": count,
        "p50_us": pick(0.50),
        "p99_us": pick(0.99),
        "pub_cpu": pub_cpu,
        "pub_build": pub_build,
        "sub_cpu": sub_cpu,
        "msgs_per_s": count / pub_wall,
    }


def _end_to_end(count: int) -> dict:
    import tf
    import urdftk
    from tf.transport.zenoh import ZenohTransport

    robot = urdftk.load(ROBOT)
    domain = random.randrange(10_000, 1_000_000)
    buffer = tf.Buffer()
    delays: list[int] = []
    bus = ZenohTransport(domain_id=domain, environ={})
    tool = "tool_center_point"

    def on_static(msg: TFMessage) -> None:
        for t in msg.transforms:
            buffer.set_transform_static(t)

    def on_tf(msg: TFMessage) -> None:
        for t in msg.transforms:
            buffer.set_transform(t)
        stamp = msg.transforms[0].header.stamp
        try:
            buffer.lookup_transform(robot.root_link, tool, stamp)
        except tf.TransformException:
            return
        delays.append(time.time_ns() - stamp.nanoseconds)

    bus.subscribe("/tf_static", TFMessage, on_static)
    bus.subscribe("/tf", TFMessage, on_tf)
    rsp = _spawn("_rsp", str(domain))
    jsp = None
    try:
        _wait_line(rsp, "go")
        jsp = _spawn("_jsp", str(domain), "100", str(count))
        _wait_line(jsp, "go")
        time.sleep(count / 100 + 2.0)
    finally:
        for proc in (jsp, rsp):
            if proc is not None:
                proc.kill()
                proc.wait()
        bus.close()
    lat = sorted(delays)
    return {"n": len(lat), "p50_us": lat[len(lat) // 2] / 1000, "p99_us": lat[int(0.99 * len(lat))] / 1000}


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "_pub":
        _child(sys.argv[2], float(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), int(sys.argv[6]))
        return
    if len(sys.argv) > 1 and sys.argv[1] == "_rsp":
        _rsp_child(int(sys.argv[2]))
        return
    if len(sys.argv) > 1 and sys.argv[1] == "_jsp":
        _jsp_child(int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]))
        return
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0, help="duration of each rate run")
    parser.add_argument("--burst", type=int, default=20000, help="messages in the flat-out run")
    args = parser.parse_args()
    print(
        f"python {sys.version.split()[0]}, {os.cpu_count()} cpus; TFMessage of {N_TF} transforms, "
        f"{len(_cdr.encode(_message(0)))} bytes CDR"
    )
    results = {}
    for rate in (100.0, 1000.0):
        for kind in ("zenoh", "zmq"):
            results[kind, rate] = r = _run(kind, rate, int(rate * args.seconds))
            print(
                f"{kind:5s} {rate:6.0f} Hz: got {r['received']}/{r['sent']}  latency p50 {r['p50_us']:.0f} us"
                f"  p99 {r['p99_us']:.0f} us  cpu pub {r['pub_cpu']:.1f}% (msgs {r['pub_build']:.1f}%)"
                f"  sub {r['sub_cpu']:.1f}%",
                flush=True,
            )
    n = int(1000 * args.seconds)
    pace = _run("pace", 1000.0, n)
    raw = _run("zenoh-raw", 1000.0, n)
    lis = _run("listener", 1000.0, n)
    print(
        f"floor at 1 kHz: pacing loop alone {pace['pub_cpu']:.1f}%;"
        f"  bare Zenoh (prebuilt bytes, no-op callback): got {raw['received']}/{raw['sent']}"
        f"  p50 {raw['p50_us']:.0f} us  p99 {raw['p99_us']:.0f} us"
        f"  cpu pub {raw['pub_cpu']:.1f}%  sub {raw['sub_cpu']:.1f}%",
        flush=True,
    )
    print(
        f"tf listener at 1 kHz (TransformListener -> Buffer): stored {lis['received']}/{lis['sent']}"
        f"  cpu pub {lis['pub_cpu']:.1f}% (msgs {lis['pub_build']:.1f}%)  sub {lis['sub_cpu']:.1f}%",
        flush=True,
    )
    for kind in ("zenoh", "zmq"):
        results[kind, 0.0] = r = _run(kind, 0.0, args.burst)
        print(
            f"{kind:5s} flat out: received {r['received']}/{r['sent']}  {r['msgs_per_s']:.0f} msgs/s sent"
            f"  (lost {r['sent'] - r['received']})",
            flush=True,
        )
    z = results["zenoh", 1000.0]
    print(
        f"urdftk's share at 1 kHz (ours minus bare Zenoh): pub {z['pub_cpu'] - raw['pub_cpu']:.1f}%"
        f" (of which building messages {z['pub_build']:.1f}%)  sub {z['sub_cpu'] - raw['sub_cpu']:.1f}%",
        flush=True,
    )
    z, q = results["zenoh", 1000.0], results["zmq", 1000.0]
    throughput = results["zenoh", 0.0]["msgs_per_s"] / results["zmq", 0.0]["msgs_per_s"]
    print(
        f"ratio zenoh/zmq at 1 kHz: p50 {z['p50_us'] / q['p50_us']:.2f}x  "
        f"p99 {z['p99_us'] / q['p99_us']:.2f}x  throughput {throughput:.2f}x"
    )
    e2e = _end_to_end(int(100 * args.seconds))
    print(
        f"end to end JointState -> robot_state_publisher -> /tf -> lookup: n={e2e['n']}  "
        f"p50 {e2e['p50_us']:.0f} us  p99 {e2e['p99_us']:.0f} us"
    )


if __name__ == "__main__":
    main()
