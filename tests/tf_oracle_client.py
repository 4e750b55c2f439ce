"""Differential-testing helpers: run the same ops on real tf2 (the oracle) and on our tf.Buffer.

The oracle is ``../shared/tools/tf2_oracle.py`` run by Debian's ``/usr/bin/python3`` (python3-tf2-ros,
geometry2 0.7.6 = ROS 1). Ops and results use the oracle's JSON format (see that file's docstring).
Our side (:func:`run_ours`) produces results in the same format, with our ROS 2 texts.
"""

from __future__ import annotations

import json
import math
import random
import re
import subprocess
from pathlib import Path
from typing import Any

import tf

SHARED = Path(__file__).resolve().parents[2] / "shared"
ORACLE = SHARED / "tools" / "tf2_oracle.py"
SYSTEM_PYTHON = "/usr/bin/python3"
INSTALL_HINT = "apt-get install python3-tf2-ros python3-geometry-msgs"

# Our exception classes, as named by ROS 1 tf2 (which has no Forward/Backward/NoData subclasses).
ROS1_NAME = {
    "ForwardExtrapolationException": "ExtrapolationException",
    "BackwardExtrapolationException": "ExtrapolationException",
    "NoDataForExtrapolationException": "ExtrapolationException",
}


def check_oracle() -> None:
    """Fail loudly (never skip) when the oracle cannot run."""
    if not ORACLE.is_file():
        raise AssertionError(f"tf2 oracle missing at {ORACLE}; the repo expects ../shared next to it")
    probe = subprocess.run(
        [SYSTEM_PYTHON, "-c", "import tf2_ros, tf2_py, geometry_msgs.msg"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    if probe.returncode != 0:
        raise AssertionError(
            f"{SYSTEM_PYTHON} cannot import tf2_ros (the real tf2 oracle). Install it with: "
            f"`{INSTALL_HINT}`\n{probe.stderr[-2000:]}"
        )


def run_oracle(ops: list[dict[str, Any]], timeout: float = 300.0) -> list[dict[str, Any]]:
    """Run ``ops`` through real tf2 (``--lines`` mode) and return one result per op."""
    check_oracle()
    text = "".join(json.dumps(op) + "\n" for op in ops)
    proc = subprocess.run(
        [SYSTEM_PYTHON, str(ORACLE), "--lines"], input=text, capture_output=True, text=True, timeout=timeout
    )
    if proc.returncode != 0:
        raise AssertionError(f"tf2 oracle failed ({proc.returncode}): {proc.stderr[-3000:]}")
    results = [json.loads(line) for line in proc.stdout.splitlines() if line.strip()]
    assert len(results) == len(ops), f"oracle returned {len(results)} results for {len(ops)} ops"
    return results


# ---------------------------------------------------------------------------------------------- ours
def _time(v: Any) -> tf.Time:
    if isinstance(v, (list, tuple)):
        return tf.Time(int(v[0]), int(v[1]))
    return tf.Time() if float(v) == 0.0 else tf.Time.from_sec(float(v))


def _msg(op: dict[str, Any]) -> tf.TransformStamped:
    t = op.get("t", [0.0, 0.0, 0.0])
    q = op.get("q", [0.0, 0.0, 0.0, 1.0])
    return tf.TransformStamped(
        tf.Header(_time(op.get("stamp", 0)), op["parent"]),
        op["child"],
        tf.Transform(tf.Vector3(*map(float, t)), tf.Quaternion(*map(float, q))),
    )


def _out(ts: tf.TransformStamped) -> dict[str, Any]:
    tr, ro = ts.transform.translation, ts.transform.rotation
    return {
        "parent": ts.header.frame_id,
        "child": ts.child_frame_id,
        "stamp": [ts.header.stamp.sec, ts.header.stamp.nanosec],
        "t": [tr.x, tr.y, tr.z],
        "q": [ro.x, ro.y, ro.z, ro.w],
    }


class OurRunner:
    """Executes oracle-format ops on ``tf.Buffer``."""

    def __init__(self) -> None:
        self.buf = tf.Buffer()

    def run(self, op: dict[str, Any]) -> dict[str, Any]:
        kind = op["op"]
        b = self.buf
        if kind == "new":
            self.buf = tf.Buffer(op.get("cache_time", 10.0))
            return {}
        if kind == "set":
            setter = b.set_transform_static if op.get("static", False) else b.set_transform
            return {"accepted": setter(_msg(op), op.get("authority", "oracle"))}
        if kind == "lookup":
            return {
                "transform": _out(b.lookup_transform(op["target"], op["source"], _time(op.get("time", 0))))
            }
        if kind == "lookup_full":
            ts = b.lookup_transform_full(
                op["target"],
                _time(op.get("target_time", 0)),
                op["source"],
                _time(op.get("source_time", 0)),
                op["fixed"],
            )
            return {"transform": _out(ts)}
        if kind == "can":
            t = _time(op.get("time", 0))
            return {
                "result": b.can_transform(op["target"], op["source"], t),
                "msg": b.why_not(op["target"], op["source"], t),
            }
        if kind == "can_full":
            ok = b.can_transform_full(
                op["target"],
                _time(op.get("target_time", 0)),
                op["source"],
                _time(op.get("source_time", 0)),
                op["fixed"],
            )
            return {"result": ok}
        if kind == "latest_common_time":
            t = b.get_latest_common_time(op["target"], op["source"])
            return {"time": [t.sec, t.nanosec]}
        if kind == "all_frames_as_string":
            return {"result": b.all_frames_as_string()}
        if kind == "all_frames_as_yaml":
            return {"result": b.all_frames_as_yaml()}
        if kind == "frames":
            return {"result": b.frames()}
        if kind == "clear":
            b.clear()
            return {}
        raise ValueError(f"unknown op {kind!r}")

    def step(self, i: int, op: dict[str, Any]) -> dict[str, Any]:
        res: dict[str, Any] = {"i": i, "op": op.get("op")}
        try:
            res.update(self.run(op))
            res["ok"] = True
        except tf.TransformException as e:
            res.update(ok=False, exc=type(e).__name__, msg=str(e))
        return res


def run_ours(ops: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Run ``ops`` on our tf.Buffer."""
    runner = OurRunner()
    return [runner.step(i, op) for i, op in enumerate(ops)]


# ---------------------------------------------------------------------------------------------- compare
_EXTRAP = re.compile(
    r"Lookup would require extrapolation "
    r"(?:(?P<at>at time (?P<t0>[\d.]+), but only time (?P<b0>[\d.]+) is in the buffer)"
    r"|(?:[\d.]+s )?into the (?P<dir>future|past)\.  Requested time (?P<t1>[\d.]+) but the "
    r"(?:latest|earliest) data is at time (?P<b1>[\d.]+))"
)
_SUFFIX = re.compile(r", when looking up transform from frame \[(.*)\] to frame \[(.*)\]$")


def _extrapolation_key(msg: str) -> tuple[Any, ...]:
    m = _EXTRAP.search(msg)
    suffix = _SUFFIX.search(msg)
    frames = suffix.groups() if suffix else None
    if not m:
        return ("none", None, None, frames)
    if m.group("at"):
        return ("at", float(m.group("t0")), float(m.group("b0")), frames)
    return (m.group("dir"), float(m.group("t1")), float(m.group("b1")), frames)


def _same_rotation(ours: list[float], theirs: list[float], tol: float) -> bool:
    n = math.sqrt(sum(v * v for v in theirs))
    ref = [v / n for v in theirs]
    return all(abs(a - b) <= tol for a, b in zip(ours, ref, strict=True)) or all(
        abs(a + b) <= tol for a, b in zip(ours, ref, strict=True)
    )


def _norm_yaml(text: str) -> str:
    text = "[]" if text == "{}" else text
    return re.sub(
        r"(most_recent_transform|oldest_transform): ([\d.]+)", lambda m: f"{m[1]}: {float(m[2]):.3f}", text
    )


def compare(
    op: dict[str, Any], ours: dict[str, Any], theirs: dict[str, Any], tol: float = 1e-9
) -> str | None:
    """None if our result agrees with tf2's for ``op``, else a description of the difference.

    Agreement: same success, same exception class (ours mapped to ROS 1 names), transforms within
    ``tol`` (rotations compared as rotations: ROS 2 normalises the returned quaternion, ROS 1 does not),
    and for messages the parts that ROS 1 and ROS 2 share.
    """
    kind = op["op"]
    if theirs.get("exc", "").startswith("harness:"):
        return f"oracle harness error: {theirs}"
    if kind == "set":
        if op.get("_duplicate"):
            return None  # ROS 1 logs TF_REPEATED_DATA, ROS 2 drops silently: same buffer state (rule 3)
        return None if ours["accepted"] == theirs["accepted"] else f"accepted {ours['accepted']} vs {theirs}"
    if ours["ok"] != theirs["ok"]:
        return f"success differs: ours {ours} vs tf2 {theirs}"
    if not ours["ok"]:
        name = ROS1_NAME.get(ours["exc"], ours["exc"])
        if kind == "latest_common_time" and theirs["exc"] == "TransformException":
            name = "TransformException"  # ROS 1's tf2_py raises the base class for every failure here
        if name != theirs["exc"]:
            return f"exception {ours['exc']} vs {theirs['exc']}: {ours['msg']!r} / {theirs['msg']!r}"
        return _compare_message(name, ours["msg"], theirs["msg"])
    if kind in ("lookup", "lookup_full"):
        a, b = ours["transform"], theirs["transform"]
        if (a["parent"], a["child"], a["stamp"]) != (b["parent"], b["child"], b["stamp"]):
            return f"header differs: {a} vs {b}"
        if any(abs(x - y) > tol for x, y in zip(a["t"], b["t"], strict=True)):
            return f"translation differs: {a['t']} vs {b['t']}"
        if not _same_rotation(a["q"], b["q"], tol):
            return f"rotation differs: {a['q']} vs {b['q']}"
        return None
    if kind in ("can", "can_full"):
        if ours["result"] != theirs["result"]:
            return f"can_transform {ours['result']} vs {theirs['result']} ({theirs.get('msg')!r})"
        if kind == "can" and not ours["result"] and "extrapolation" in theirs.get("msg", ""):
            return _compare_message("ExtrapolationException", ours["msg"], theirs["msg"])
        return None
    if kind == "all_frames_as_yaml":
        return None if _norm_yaml(ours["result"]) == _norm_yaml(theirs["result"]) else "yaml differs"
    key = {"latest_common_time": "time"}.get(kind, "result")
    if key in theirs and ours.get(key) != theirs[key]:
        return f"{kind}: {ours.get(key)!r} vs {theirs[key]!r}"
    return None


def _compare_message(name: str, ours: str, theirs: str) -> str | None:
    if name == "ExtrapolationException":
        a, b = _extrapolation_key(ours), _extrapolation_key(theirs)
        if b[0] == "none":  # ROS 1 gives no text for an emptied cache; ROS 2 says "at time ... only time 0"
            return None if a[0] == "at" and a[3] == b[3] else f"extrapolation text {ours!r} vs {theirs!r}"
        same = a[0] == b[0] and a[3] == b[3] and abs(a[1] - b[1]) < 2e-6 and abs(a[2] - b[2]) < 2e-6
        return None if same else f"extrapolation text {ours!r} vs {theirs!r}"
    if name == "InvalidArgumentException":
        return None  # ROS 1 and ROS 2 word it differently (we follow ROS 2); the class is what matters
    if name == "LookupException":
        return None if ours.startswith(theirs) else f"lookup text {ours!r} vs {theirs!r}"
    if name == "TransformException" and theirs.endswith("does not exist. "):
        return None if ours.startswith(theirs) else f"lookup text {ours!r} vs {theirs!r}"
    return None if ours == theirs else f"{name} text {ours!r} vs {theirs!r}"


# ---------------------------------------------------------------------------------------------- generator
def _stamp(rng: random.Random, lo_ms: int = 1000, hi_ms: int = 9000) -> list[int]:
    ms = rng.randint(lo_ms, hi_ms)
    return [ms // 1000, (ms % 1000) * 1_000_000]


def _quat(rng: random.Random, denormalise: bool = False) -> list[float]:
    v = [rng.gauss(0.0, 1.0) for _ in range(4)]
    n = math.sqrt(sum(x * x for x in v))
    scale = (1.0 + rng.uniform(-0.004, 0.004)) if denormalise else 1.0
    return [x / n * scale for x in v]


def generate(seed: int, n_ops: int, max_frames: int = 30) -> list[dict[str, Any]]:
    """A seeded random op sequence exercising tf2's semantics, avoiding only ROS 1 vs ROS 2 differences.

    Avoided: two different samples with the same stamp for one child (rule 3), pruning (stamps stay
    within a window shorter than the cache, rule 4), and a frame switching between static and dynamic
    (rule 10). Exact duplicates are sent and marked ``_duplicate``.
    """
    rng = random.Random(seed)
    ops: list[dict[str, Any]] = []
    while len(ops) < n_ops:
        ops.extend(_episode(rng, max_frames))
    return ops[:n_ops]


def _episode(rng: random.Random, max_frames: int) -> list[dict[str, Any]]:
    ops: list[dict[str, Any]] = [{"op": "new"}]
    trees = rng.choice([1, 1, 1, 2, 3])
    n = rng.randint(trees + 1, max_frames)
    names = [f"{'abc'[i % trees]}{i}" for i in range(n)]
    kinds = {name: ("static" if rng.random() < 0.3 else "dynamic") for name in names}
    used: dict[str, dict[tuple[int, int], dict[str, Any]]] = {name: {} for name in names}
    parent_of: dict[str, str] = {}
    roots = set(names[:trees])

    def pick_parent(i: int) -> str:
        same_tree = [names[j] for j in range(i) if j % trees == i % trees]
        return rng.choice(same_tree)

    def set_op(i: int) -> dict[str, Any]:
        child = names[i]
        if child not in parent_of or rng.random() < 0.05:  # re-parenting from time to time
            parent_of[child] = pick_parent(i)
        op: dict[str, Any] = {
            "op": "set",
            "parent": parent_of[child],
            "child": child,
            "t": [rng.uniform(-2, 2) for _ in range(3)],
            "q": _quat(rng, denormalise=rng.random() < 0.1),
            "authority": rng.choice(["alpha", "beta"]),
        }
        if kinds[child] == "static":
            op["static"] = True
            op["stamp"] = _stamp(rng)
            return op
        stamp = tuple(_stamp(rng))
        if stamp in used[child]:
            if rng.random() < 0.5:
                dup = dict(used[child][stamp])
                dup["_duplicate"] = True
                return dup
            return {"op": "frames"}
        op["stamp"] = list(stamp)
        used[child][stamp] = op
        return op

    def frame() -> str:
        r = rng.random()
        if r < 0.03:
            return "unknown_frame"
        if r < 0.05:
            return rng.choice(["", "/" + names[0]])
        return rng.choice(names)

    def time(child: str | None = None) -> Any:
        r = rng.random()
        if r < 0.3:
            return 0
        if r < 0.55 and child and used.get(child):
            return list(rng.choice(list(used[child])))
        ms = rng.randint(500, 9500)
        return [ms // 1000, (ms % 1000) * 1_000_000 + rng.randint(0, 999) * 1000]

    population = [i for i in range(trees, n) for _ in range(rng.randint(1, 7))]
    rng.shuffle(population)
    ops.extend(set_op(i) for i in population)  # initial population, stamps in random order
    for _ in range(rng.randint(40, 160)):
        r = rng.random()
        if r < 0.25:
            ops.append(set_op(rng.randrange(trees, n)))
        elif r < 0.27:
            ops.append(_invalid_set(rng, names))
        elif r < 0.60:
            src = frame()
            ops.append({"op": "lookup", "target": frame(), "source": src, "time": time(src)})
        elif r < 0.70:
            ops.append(
                {
                    "op": "lookup_full",
                    "target": frame(),
                    "target_time": time(),
                    "source": frame(),
                    "source_time": time(),
                    "fixed": frame(),
                }
            )
        elif r < 0.85:
            src = frame()
            ops.append({"op": "can", "target": frame(), "source": src, "time": time(src)})
        elif r < 0.90:
            ops.append(
                {
                    "op": "can_full",
                    "target": frame(),
                    "target_time": time(),
                    "source": frame(),
                    "source_time": time(),
                    "fixed": frame(),
                }
            )
        elif r < 0.94:
            ops.append({"op": "latest_common_time", "target": rng.choice(names), "source": rng.choice(names)})
        elif r < 0.97:
            ops.append({"op": rng.choice(["all_frames_as_string", "all_frames_as_yaml"])})
        elif r < 0.98:
            ops.append({"op": "clear"})
            for d in used.values():
                d.clear()
        else:
            ops.append({"op": "frames"})
    del roots
    return ops


def _invalid_set(rng: random.Random, names: list[str]) -> dict[str, Any]:
    child = rng.choice(names[1:] or names)
    op: dict[str, Any] = {"op": "set", "parent": names[0], "child": child, "stamp": _stamp(rng)}
    kind = rng.randrange(5)
    if kind == 0:
        op["parent"] = child
    elif kind == 1:
        op["child"] = ""
    elif kind == 2:
        op["parent"] = ""
    elif kind == 3:
        op["t"] = [float("nan"), 0.0, 0.0]
    else:
        op["q"] = [0.0, 0.0, 0.0, 1.02]
    return op


def generate_dense(seed: int, n_ops: int, max_frames: int = 30) -> list[dict[str, Any]]:
    """Success-heavy ops: every dynamic frame sampled at shared stamps (as a state publisher does).

    Inserts arrive shuffled (out of order), some frames are re-parented at a stamp, and lookups
    are at 0, at sample stamps and in between, so the interpolation and composition paths dominate.
    """
    rng = random.Random(seed)
    ops: list[dict[str, Any]] = []
    while len(ops) < n_ops:
        ops.append({"op": "new"})
        n = rng.randint(3, max_frames)
        names = [f"d{i}" for i in range(n)]
        static = {names[i] for i in range(1, n) if rng.random() < 0.25}
        stamps = sorted(rng.sample(range(1000, 9000, 250), rng.randint(2, 8)))
        sets = []
        for i in range(1, n):
            parent = names[rng.randrange(i)]
            switch_at = rng.choice(stamps) if rng.random() < 0.15 else None
            other = names[rng.randrange(i)]
            for k, ms in enumerate(stamps):
                if names[i] in static and k:
                    break
                p = other if switch_at is not None and ms >= switch_at else parent
                sets.append(
                    {
                        "op": "set",
                        "parent": p,
                        "child": names[i],
                        "stamp": [ms // 1000, (ms % 1000) * 1_000_000],
                        "t": [rng.uniform(-1, 1) for _ in range(3)],
                        "q": _quat(rng),
                        "static": names[i] in static,
                        "authority": "dense",
                    }
                )
        rng.shuffle(sets)
        ops.extend(sets)
        for _ in range(rng.randint(30, 90)):
            r = rng.random()
            ms = rng.randint(stamps[0] - 100, stamps[-1] + 100)
            t: Any = (
                0
                if r < 0.2
                else ([ms // 1000, (ms % 1000) * 1_000_000] if r < 0.9 else [stamps[0] // 1000, 0])
            )
            target, source = rng.choice(names), rng.choice(names)
            if rng.random() < 0.8:
                ops.append({"op": "lookup", "target": target, "source": source, "time": t})
            else:
                ops.append(
                    {"op": "lookup_full", "target": target, "target_time": t, "source": source,
                     "source_time": rng.choice([0, t]), "fixed": rng.choice(names)}
                )  # fmt: skip
    return ops[:n_ops]


def agree(ops: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Run ``ops`` on real tf2 and on ``tf``, assert every result agrees, and return ours."""
    theirs = run_oracle(ops)
    ours = run_ours(ops)
    pairs = zip(ops, ours, theirs, strict=True)
    problems = [f"op {a['i']} {op}: {d}" for op, a, b in pairs if (d := compare(op, a, b))]
    assert not problems, f"{len(problems)} disagreements, first ones:\n" + "\n".join(problems[:15])
    return ours
