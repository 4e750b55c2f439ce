"""The walk's "newest pair" fast path (tf._cache.TimeCache.pair) against real tf2, case by case.

Interpolation between a frame's two newest samples uses a pair prepared at insert time; these
sequences hit every way that pair can go stale (pruning followed by a rejected insert, out-of-order
inserts, re-parenting between the two samples, ``clear()``) and compare each result with tf2.
Pruning differs between ROS 1 (the oracle: insert, then prune) and ROS 2 (prune, then insert or
reject; docs/tf2-semantics.md), so the pruning case is checked against the ROS 2 rule instead.
"""

from __future__ import annotations

from typing import Any

import pytest
from tf_oracle_client import agree

import tf

_Q1 = [0.0, 0.0, 0.0, 1.0]
_Q2 = [0.0, 0.0, 0.7071067811865476, 0.7071067811865476]
_Q3 = [0.5, -0.5, 0.5, 0.5]


def _set(parent: str, child: str, stamp: float, q: list[float], x: float = 1.0) -> dict[str, Any]:
    return {"op": "set", "parent": parent, "child": child, "stamp": stamp, "t": [x, 0.5, -0.25], "q": q}


def _lookups(target: str, source: str, times: list[float]) -> list[dict[str, Any]]:
    return [{"op": "lookup", "target": target, "source": source, "time": t} for t in times]


def _sequences() -> list[dict[str, Any]]:
    times = [1.0, 1.25, 1.5, 2.0, 2.5, 2.75, 3.0, 3.5]
    ops: list[dict[str, Any]] = []
    # an out-of-order insert between the two newest samples, then one before them
    ops += [{"op": "new", "cache_time": 10.0}, _set("a", "b", 1.0, _Q1), _set("a", "b", 3.0, _Q2)]
    ops += _lookups("a", "b", times)
    ops += [_set("a", "b", 2.0, _Q3, x=-1.0)]
    ops += _lookups("a", "b", times)
    ops += [_set("a", "b", 1.25, _Q3, x=2.0)]
    ops += _lookups("a", "b", times)
    ops += [_set("a", "b", 3.5, _Q1)]
    ops += _lookups("a", "b", times)
    # re-parenting between the two newest samples (tf2 keeps the older sample, no interpolation)
    ops += [{"op": "new", "cache_time": 10.0}, _set("a", "c", 0.5, _Q2), _set("a", "c", 4.0, _Q3)]
    ops += [_set("a", "b", 1.0, _Q1), _set("c", "b", 3.0, _Q2), _set("a", "b", 3.5, _Q3)]
    ops += _lookups("a", "b", times) + _lookups("c", "b", times) + _lookups("b", "c", times)
    # a three-link chain stamped together (a state publisher), cleared and refilled
    ops += [{"op": "new", "cache_time": 10.0}]
    for stamp, q in ((1.0, _Q1), (2.0, _Q2), (3.0, _Q3)):
        ops += [_set("a", "b", stamp, q), _set("b", "c", stamp, _Q2), _set("c", "d", stamp, q, x=0.25)]
    ops += _lookups("a", "d", times) + _lookups("d", "a", times) + _lookups("b", "d", times)
    ops += [{"op": "clear"}, _set("a", "b", 5.0, _Q2), _set("b", "c", 5.0, _Q1), _set("c", "d", 5.0, _Q3)]
    ops += _lookups("a", "d", [2.5, 4.0, 5.0, 0.0])
    ops += [_set("a", "b", 6.0, _Q1), _set("b", "c", 6.0, _Q3), _set("c", "d", 6.0, _Q2)]
    ops += _lookups("a", "d", [4.0, 5.0, 5.5, 6.0, 0.0])
    return ops


@pytest.mark.timeout(120)
def test_newest_pair_agrees_with_tf2() -> None:
    ops = _sequences()
    ours = agree(ops)
    lookups = [r for r in ours if r["op"] == "lookup"]
    assert sum(r["ok"] for r in lookups) > 40 and sum(not r["ok"] for r in lookups) > 5


def _outcome(buf: tf.Buffer, t: float) -> Any:
    try:
        tr = buf.lookup_transform("a", "b", tf.Time.from_sec(t)).transform
    except tf.TransformException as e:
        return type(e).__name__, str(e)
    return (tr.translation.x, tr.translation.y, tr.translation.z, tr.rotation.z, tr.rotation.w)


def test_pair_dropped_when_a_rejected_insert_prunes_its_older_sample() -> None:
    """ROS 2 prunes against the newest stamp before rejecting old data: only 3.0 s survives here."""

    def msg(stamp: float, angle_z: float) -> tf.TransformStamped:
        q = tf.transformations.quaternion_from_euler(0.0, 0.0, angle_z)
        return tf.TransformStamped(
            tf.Header(tf.Time.from_sec(stamp), "a"),
            "b",
            tf.Transform(tf.Vector3(stamp, 0.0, 0.0), tf.Quaternion(*q)),
        )

    buf = tf.Buffer(1.0)
    assert buf.set_transform(msg(1.0, 0.1), "x") and buf.set_transform(msg(3.0, 0.9), "x")
    assert _outcome(buf, 2.0)[0] == pytest.approx(2.0)  # both samples held: interpolated
    assert not buf.set_transform(msg(1.5, 0.3), "x")  # prunes 1.0 s (< 3.0 - 1.0), then rejected
    alone = tf.Buffer(1.0)  # a buffer holding only the surviving sample
    assert alone.set_transform(msg(3.0, 0.9), "x")
    for t in (1.0, 1.5, 2.0, 2.5, 2.99, 3.0, 3.5):
        assert _outcome(buf, t) == _outcome(alone, t), t
    assert _outcome(buf, 2.5)[0] == "NoDataForExtrapolationException"  # a single sample left
