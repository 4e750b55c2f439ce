"""Benchmark tf.Buffer against tf2's C++ BufferCore (Debian python3-tf2-ros), measured in the same run.

    .venv/bin/python bench/tf.py            # full run (~1-2 min)
    .venv/bin/python bench/tf.py --quick    # fewer repetitions

Both sides run the same scenario script (below): ours in this interpreter, tf2 in a subprocess
of /usr/bin/python3 that times itself. Every lookup is timed individually (perf_counter_ns, minus
the measured timer overhead), and new transforms are inserted between lookups, so no result can
be served from a memo. Reported: median per-call microseconds; ratio = ours / tf2.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

# The scenario, written once and run by both sides. It defines `run(api, n)`; `api` adapts the
# two libraries (message construction, lookup, set).
SCENARIO = r'''
import gc, math, statistics, time

DEPTHS = (2, 10, 30)

def timer_overhead():
    pc = time.perf_counter_ns
    samples = []
    for _ in range(20000):
        a = pc(); b = pc(); samples.append(b - a)
    return statistics.median(samples)

def chain_message(api, k, stamp_ns, n_links=30):
    return [api.msg("f%d" % (i - 1), "f%d" % i, stamp_ns, 0.1 * i, math.sin(0.01 * k + i))
            for i in range(1, n_links + 1)]

def run(api, n):
    out = {}
    pc = time.perf_counter_ns
    over = timer_overhead()
    step = 10_000_000  # 100 Hz
    # --- time 0 and interpolated, state-publisher pattern: every link gets each new stamp
    buf = api.buffer(10.0)
    k = 0
    for k in range(1, 101):
        for m in chain_message(api, k, 1_000_000_000 + k * step):
            api.set(buf, m)
    for depth in DEPTHS:
        zero, interp, stag = [], [], []
        target, source = "f0", "f%d" % depth
        for _ in range(n):
            k += 1
            for m in chain_message(api, k, 1_000_000_000 + k * step):
                api.set(buf, m)
            # between two samples, and a different time on each iteration
            t = api.time(1_000_000_000 + k * step - 1_234_567 - (k % 7) * 1_000_000)
            a = pc(); api.lookup(buf, target, source, api.zero); b = pc()
            zero.append(b - a - over)
            a = pc(); api.lookup(buf, target, source, t); b = pc()
            interp.append(b - a - over)
        out["lookup_time0_depth%d" % depth] = statistics.median(zero) / 1000
        out["lookup_interp_depth%d" % depth] = statistics.median(interp) / 1000
    # --- time 0 with staggered publishers: one link per insert, newest stamps differ along the chain
    buf = api.buffer(10.0)
    stamp = 1_000_000_000
    for r in range(3):
        for i in range(1, 31):
            stamp += step // 30
            api.set(buf, api.msg("f%d" % (i - 1), "f%d" % i, stamp, 0.1, 0.2))
    for depth in DEPTHS:
        samples = []
        for j in range(n):
            stamp += step // 30
            i = 1 + j % 30
            api.set(buf, api.msg("f%d" % (i - 1), "f%d" % i, stamp, 0.1, math.sin(j)))
            a = pc(); api.lookup(buf, "f0", "f%d" % depth, api.zero); b = pc()
            samples.append(b - a - over)
        out["lookup_time0_staggered_depth%d" % depth] = statistics.median(samples) / 1000
    # --- set_transform: in-order samples on a 30-frame chain, messages built beforehand
    buf = api.buffer(10.0)
    msgs = [chain_message(api, j, 1_000_000_000 + j * step) for j in range(1, 1 + max(n // 30, 50))]
    samples = []
    for batch in msgs:
        for m in batch:
            a = pc(); api.set(buf, m); b = pc()
            samples.append(b - a - over)
    out["set_transform"] = statistics.median(samples) / 1000
    return out

def memory(api):
    """RSS growth for 100 frames at 100 Hz over a 10 s cache (1,050 stamps each, steady state)."""
    def rss():
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) * 1024
    gc.collect()
    buf = api.buffer(10.0)
    before = rss()
    for k in range(1, 1051):
        stamp = 1_000_000_000 + k * 10_000_000
        for i in range(1, 101):
            api.set(buf, api.msg("m%d" % (i // 2), "m%d" % i, stamp, 0.1 * k, 0.01 * k))
    gc.collect()
    return (rss() - before) / 1e6, buf
'''

TF2_API = r"""
import rospy, tf2_ros
from geometry_msgs.msg import TransformStamped

class Api:
    zero = rospy.Time(0)
    @staticmethod
    def buffer(cache_s):
        return tf2_ros.Buffer(rospy.Duration.from_sec(cache_s), debug=False)
    @staticmethod
    def time(ns):
        return rospy.Time(ns // 10**9, ns % 10**9)
    @staticmethod
    def msg(parent, child, ns, x, angle):
        m = TransformStamped()
        m.header.frame_id = parent; m.child_frame_id = child
        m.header.stamp = rospy.Time(ns // 10**9, ns % 10**9)
        m.transform.translation.x = x
        m.transform.rotation.z = math.sin(angle / 2); m.transform.rotation.w = math.cos(angle / 2)
        return m
    @staticmethod
    def set(buf, m):
        buf.set_transform(m, "bench")
    @staticmethod
    def lookup(buf, target, source, t):
        return buf.lookup_transform_core(target, source, t)

class ApiPy(Api):
    @staticmethod
    def lookup(buf, target, source, t):
        return buf.lookup_transform(target, source, t)
"""

OURS_API = r"""
import tf

class Api:
    zero = tf.Time()
    @staticmethod
    def buffer(cache_s):
        return tf.Buffer(tf.Duration.from_sec(cache_s))
    @staticmethod
    def time(ns):
        return tf.Time.from_nsec(ns)
    @staticmethod
    def msg(parent, child, ns, x, angle):
        return tf.TransformStamped(
            tf.Header(tf.Time.from_nsec(ns), parent), child,
            tf.Transform(tf.Vector3(x, 0.0, 0.0),
                         tf.Quaternion(0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))))
    @staticmethod
    def set(buf, m):
        buf.set_transform(m, "bench")
    @staticmethod
    def lookup(buf, target, source, t):
        return buf.lookup_transform(target, source, t)
"""

MAIN = r"""
import json, sys
mode, n = sys.argv[1], int(sys.argv[2])
if mode == "timing":
    res = run(Api, n)
    if "ApiPy" in globals():
        py = run(ApiPy, max(n // 4, 200))
        res.update({"py_" + k: v for k, v in py.items() if k.startswith("lookup_time0_depth")})
    if "BATCH" in globals():
        res.update(BATCH(n))
else:
    res = {"memory_mb": memory(Api)[0]}
print(json.dumps(res))
"""

BATCH = r'''
def BATCH(n):
    """Per-frame cost of lookup_transforms (30 frames of a 30-link chain, time 0, new data each call)."""
    buf = Api.buffer(10.0)
    pc = time.perf_counter_ns
    names = ["f%d" % i for i in range(1, 31)]
    samples = []
    for k in range(1, n // 10 + 100):
        for m in chain_message(Api, k, 1_000_000_000 + k * 10_000_000):
            Api.set(buf, m)
        a = pc(); buf.lookup_transforms("f0", names); b = pc()
        samples.append((b - a) / 30)
    return {"batched_per_frame": statistics.median(samples) / 1000}
'''


def _run(python: str, api: str, mode: str, n: int, extra: str = "") -> dict:
    code = "import math\n" + SCENARIO + api + extra + MAIN
    proc = subprocess.run(
        [python, "-c", code, mode, str(n)], capture_output=True, text=True, timeout=900, cwd=REPO
    )
    if proc.returncode != 0:
        sys.exit(f"{python} failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repetitions")
    parser.add_argument("-n", type=int, default=None, help="lookups per scenario and depth")
    args = parser.parse_args()
    n = args.n or (600 if args.quick else 3000)
    print(f"command: {' '.join([Path(sys.executable).name, *sys.argv])}  (n={n})")
    tf2 = _run("/usr/bin/python3", TF2_API, "timing", n)
    ours = _run(sys.executable, OURS_API, "timing", n, BATCH)
    tf2_mem = _run("/usr/bin/python3", TF2_API, "memory", n)
    ours_mem = _run(sys.executable, OURS_API, "memory", n)
    print(f"{'metric (median, us)':38s} {'urdftk tf':>10s} {'tf2 C++':>10s} {'ratio':>7s}")
    for key in sorted(k for k in tf2 if not k.startswith("py_")):
        print(f"{key:38s} {ours[key]:10.2f} {tf2[key]:10.2f} {ours[key] / tf2[key]:7.2f}")
    mine, theirs = ours_mem["memory_mb"], tf2_mem["memory_mb"]
    print(f"{'memory_mb (100 frames, 100 Hz, 10 s)':38s} {mine:10.2f} {theirs:10.2f} {mine / theirs:7.2f}")
    for depth in (2, 10, 30):
        key = f"lookup_time0_depth{depth}"
        print(f"  tf2_ros.Buffer.lookup_transform (Python wrapper) depth {depth}: {tf2['py_' + key]:.2f} us")
    print(f"  lookup_transforms (batched, 30 frames): {ours['batched_per_frame']:.2f} us per frame")
    print("  tf2 column: tf2_ros.Buffer.lookup_transform_core / set_transform (C++ through tf2_py).")
    return 0


if __name__ == "__main__":
    sys.exit(main())
