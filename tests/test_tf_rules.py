"""One test per tf2 BufferCore semantics rule (../shared/docs/tf2-semantics.md, rules 1-22).

Where ROS 1 and ROS 2 agree, the expected behaviour comes from real tf2 (the oracle) through
``agree()``; rules 3, 4, 9, 10 and 20 follow ROS 2 (no ROS 2 oracle here), so those tests check
ROS 2's documented behaviour directly.
"""

from __future__ import annotations

import logging
import math
import threading

import pytest
from tf_oracle_client import agree

import tf
from tf import _core

SQ = math.sqrt(0.5)


def ts(parent: str, child: str, sec: float, t=(0.0, 0.0, 0.0), q=(0.0, 0.0, 0.0, 1.0)) -> tf.TransformStamped:
    return tf.TransformStamped(
        tf.Header(tf.Time.from_sec(sec), parent), child, tf.Transform(tf.Vector3(*t), tf.Quaternion(*q))
    )


def S(parent, child, stamp, t=(0, 0, 0), q=(0, 0, 0, 1), static=False):
    return {
        "op": "set",
        "parent": parent,
        "child": child,
        "stamp": stamp,
        "t": list(t),
        "q": list(q),
        "static": static,
    }


def L(target, source, time=0):
    return {"op": "lookup", "target": target, "source": source, "time": time}


def test_rule01_default_cache_time_is_10s_and_configurable():
    assert tf.Buffer().cache_time == tf.Duration(10)
    assert tf.Buffer(tf.Duration(3)).cache_time == tf.Duration(3)
    ops = [{"op": "new", "cache_time": 2.0}, S("w", "a", 5.0), S("w", "a", 2.9), S("w", "a", 3.0)]
    ops += [{"op": "new"}, S("w", "a", 5.0), S("w", "a", 2.9), S("w", "a", 3.0)]
    ours = agree(ops)  # the cache length decides what counts as too old, in tf2 and here
    assert [r["accepted"] for r in ours if r["op"] == "set"] == [True, False, True, True, True, True]


def test_rule02_out_of_order_inserts_are_sorted_in():
    stamps = [3.0, 1.0, 5.0, 2.0, 4.0]
    ops = [S("w", "a", s, t=(s, 0, 0)) for s in stamps]
    ops += [L("w", "a", s) for s in (1.0, 1.5, 2.0, 3.5, 5.0)]
    ours = agree(ops)
    assert [r["transform"]["t"][0] for r in ours[5:]] == pytest.approx([1.0, 1.5, 2.0, 3.5, 5.0])


def test_rule03_ros2_keeps_same_stamp_different_data_and_drops_exact_duplicates():
    b = tf.Buffer()
    assert b.set_transform(ts("w", "a", 1.0, t=(1, 0, 0)))
    assert b.set_transform(ts("w", "a", 1.0, t=(1, 0, 0)))  # exact duplicate: dropped silently
    assert b.set_transform(ts("w", "a", 1.0, t=(2, 0, 0)))  # same stamp, new data: kept (ROS 2)
    assert len(b._core._caches[b._core._ids["a"]]) == 2
    # the later-inserted same-stamp sample is the one found at that stamp
    assert b.lookup_transform("w", "a", tf.Time(1)).transform.translation.x == 2.0


def test_rule04_ros2_prunes_first_then_rejects_old_data(caplog):
    b = tf.Buffer(tf.Duration(10))
    for sec in (1, 5, 11):
        assert b.set_transform(ts("w", "a", sec))
    # ROS 2 prunes *before* inserting, relative to the newest stamp before the insert (11):
    assert b.lookup_transform("w", "a", tf.Time(1)).header.stamp == tf.Time(1)  # 1 + 10 >= 11: kept
    assert b.set_transform(ts("w", "a", 12))  # prune against 11: nothing older than 1 -> 1 stays
    assert b.set_transform(ts("w", "a", 13))  # prune against 12: 1 < 2 goes
    with pytest.raises(tf.BackwardExtrapolationException):
        b.lookup_transform("w", "a", tf.Time(1))
    with caplog.at_level(logging.WARNING, logger="tf"):
        assert not b.set_transform(ts("w", "a", 2.9))  # 2.9 < 13 - 10: TF_OLD_DATA
        assert b.set_transform(ts("w", "a", 3.0))  # exactly newest - cache: accepted
    assert "TF_OLD_DATA" in caplog.text


def test_rule05_time_zero_is_the_latest_common_time():
    ops = [
        S("w", "a", 1.0), S("w", "a", 3.0), S("a", "b", 2.0), S("a", "b", 4.0),
        S("b", "s", 0, t=(0, 0, 1), static=True),
        L("w", "s", 0), L("b", "a", 0), L("w", "a", 0),
        {"op": "latest_common_time", "target": "w", "source": "s"},
        {"op": "latest_common_time", "target": "b", "source": "s"},
        S("b", "z", 0), S("z", "zz", 2.5), L("w", "zz", 0), L("b", "zz", 0), L("w", "z", 0), L("z", "w", 0),
    ]  # fmt: skip
    ours = agree(ops)
    assert ours[5]["transform"]["stamp"] == [3, 0]  # min(3, 4) along w<-a<-b, static ignored
    assert ours[7]["transform"]["stamp"] == [3, 0]  # single link: its newest sample
    assert ours[9]["time"] == [0, 0]  # static only


def test_rule06_exact_stamp_returns_the_stored_sample():
    q1 = (0.0, 0.0, math.sin(0.3), math.cos(0.3))
    ops = [
        S("w", "a", 1.0, t=(1, 2, 3)),
        S("w", "a", 2.0, t=(5, 5, 5), q=q1),
        S("w", "a", 3.0),
        L("w", "a", 2.0),
    ]
    ours = agree(ops)
    assert ours[3]["transform"]["t"] == [5.0, 5.0, 5.0]


def test_rule07_interpolation_is_lerp_and_shortest_path_slerp():
    q_a = (0.0, 0.0, math.sin(0.1), math.cos(0.1))
    q_b = (0.0, 0.0, -math.sin(1.4), -math.cos(1.4))  # far side of the sphere: shortest path flips it
    ops = [S("w", "a", 1.0, t=(0, 0, 0), q=q_a), S("w", "a", 2.0, t=(2, 4, 6), q=q_b)]
    ops += [L("w", "a", [1, k * 100_000_000]) for k in range(1, 10)]
    ours = agree(ops)
    mid = ours[2 + 4]["transform"]
    assert mid["t"] == pytest.approx([1.0, 2.0, 3.0])
    assert mid["q"] == pytest.approx([0.0, 0.0, math.sin(0.75), math.cos(0.75)])


def test_rule08_reparenting_uses_the_older_sample_without_interpolating():
    ops = [
        S("w", "a", 1.0, t=(1, 0, 0)),
        S("v", "a", 3.0, t=(3, 0, 0)),
        S("w", "v", 0, t=(0, 10, 0), static=True),
    ]
    ops += [L("w", "a", 2.0), L("v", "a", 2.0), L("v", "a", 3.0), L("w", "a", 1.0)]
    ours = agree(ops)
    assert ours[3]["transform"]["t"] == [1.0, 0.0, 0.0]  # parent at 2.0 is still w: older sample as is


def test_rule09_zero_tolerance_extrapolation_with_ros2_texts_and_classes():
    b = tf.Buffer()
    b.set_transform(ts("w", "a", 1.0))
    b.set_transform(ts("w", "a", 2.0))
    b.set_transform(ts("w", "one", 1.0))
    with pytest.raises(
        tf.ForwardExtrapolationException, match=r"into the future.  Requested time 2\.000001 but"
    ):
        b.lookup_transform("w", "a", tf.Time(2, 1000))
    with pytest.raises(
        tf.BackwardExtrapolationException, match=r"earliest data is at time 1\.000000, when looking"
    ):
        b.lookup_transform("w", "a", tf.Time(0, 999_999_999))
    with pytest.raises(
        tf.NoDataForExtrapolationException, match=r"at time 1\.500000, but only time 1\.000000 is"
    ):
        b.lookup_transform("w", "one", tf.Time.from_sec(1.5))
    assert issubclass(tf.ForwardExtrapolationException, tf.ExtrapolationException)
    ops = [S("w", "a", 1.0), S("w", "a", 2.0), L("w", "a", [2, 1000]), L("a", "w", [0, 999_999_999])]
    agree(ops)  # same class (mapped to ROS 1's) and same numbers as tf2


def test_rule10_static_is_valid_at_all_times_and_a_kind_switch_reallocates():
    ops = [
        S("w", "s", 5.0, t=(1, 0, 0), static=True),
        L("w", "s", 0),
        L("w", "s", 123.0),
        L("s", "w", [7, 5]),
    ]
    ops += [S("w", "s", 9.0, t=(2, 0, 0), static=True), L("w", "s", 1.0)]
    ours = agree(ops)
    assert ours[1]["transform"]["stamp"] == [0, 0] and ours[2]["transform"]["stamp"] == [123, 0]
    assert ours[5]["transform"]["t"][0] == 2.0  # re-insert overwrites
    b = tf.Buffer()  # ROS 2: static -> dynamic reallocates a time cache (and back)
    b.set_transform_static(ts("w", "s", 0, t=(1, 0, 0)))
    b.set_transform(ts("w", "s", 5.0, t=(2, 0, 0)))
    with pytest.raises(tf.ExtrapolationException):
        b.lookup_transform("w", "s", tf.Time(1))
    b.set_transform_static(ts("w", "s", 0, t=(3, 0, 0)))
    assert b.lookup_transform("w", "s", tf.Time(1)).transform.translation.x == 3.0


def test_rule11_clear_keeps_static_transforms_and_frame_names():
    ops = [S("w", "a", 1.0), S("a", "s", 0, static=True), {"op": "clear"}, L("a", "s", 0), L("w", "a", 1.0)]
    ops += [{"op": "all_frames_as_string"}, {"op": "frames"}]
    ours = agree(ops)
    assert ours[3]["ok"] and not ours[4]["ok"]
    assert "Frame a exists with parent NO_PARENT." in ours[5]["result"]


def test_rule12_invalid_inserts_are_rejected_and_slashes_stripped(caplog):
    nan = float("nan")
    ops = [
        S("a", "a", 1.0), S("", "b", 1.0), S("a", "", 1.0), S("/", "b", 1.0), S("a", "b", 1.0, t=(nan, 0, 0)),
        S("a", "b", 1.0, q=(0, 0, 0, 1.02)), S("a", "b", 1.0, q=(0, 0, 0, 0.996)), S("/w", "/c", 1.0),
        L("w", "c", 1.0), {"op": "frames"},
    ]  # fmt: skip
    with caplog.at_level(logging.ERROR, logger="tf"):
        ours = agree(ops)
    assert [r["accepted"] for r in ours[:8]] == [False] * 6 + [True, True]
    for code in (
        "TF_SELF_TRANSFORM",
        "TF_NO_FRAME_ID",
        "TF_NO_CHILD_FRAME_ID",
        "TF_NAN_INPUT",
        "TF_DENORMALIZED",
    ):
        assert code in caplog.text
    b = tf.Buffer()  # accepted quaternions are stored unnormalised (visible through the translation scale)
    b.set_transform(ts("w", "a", 1.0, q=(0, 0, 0, 0.996)))
    b.set_transform(ts("a", "b", 1.0, t=(1, 0, 0)))
    assert b.lookup_transform("w", "b", tf.Time(1)).transform.translation.x == pytest.approx(0.996**2)


def test_rule13_invalid_and_unknown_names_in_queries():
    ops = [S("w", "a", 1.0), L("", "a"), L("/w", "a"), L("w", "nope"), L("nope", "a")]
    ops += [
        {"op": "can", "target": "x", "source": "y", "time": 0},
        {"op": "can", "target": "/w", "source": "a", "time": 0},
    ]
    ours = agree(ops)
    assert [r.get("exc") for r in ours[1:5]] == ["InvalidArgumentException"] * 2 + ["LookupException"] * 2
    assert "Known frames: [a, w]" in ours[3]["msg"]  # a lookup error lists the valid names
    b = tf.Buffer()
    assert b.can_transform("x", "y") is False
    assert "does not exist" in b.why_not("x", "y")


def test_rule14_target_equals_source_is_identity_even_for_unknown_frames():
    ops = [
        S("w", "a", 2.0),
        S("w", "a", 3.0),
        S("a", "s", 0, static=True),
        L("zz", "zz", 0),
        L("zz", "zz", 4.5),
    ]
    ops += [L("a", "a", 0), L("w", "w", 0), L("s", "s", 0)]
    ours = agree(ops)
    assert ours[3]["transform"]["q"] == [0.0, 0.0, 0.0, 1.0]
    assert [ours[i]["transform"]["stamp"] for i in (3, 4, 5, 6, 7)] == [
        [0, 0],
        [4, 500_000_000],
        [3, 0],
        [0, 0],
        [0, 0],
    ]


def test_rule15_walk_to_top_parent_configurations():
    q = (0.0, math.sin(0.2), 0.0, math.cos(0.2))
    tree = [("w", "a"), ("a", "b"), ("b", "c"), ("a", "d"), ("d", "e"), ("w", "f")]
    ops = [S(p, c, 1.0, t=(i + 1, -i, 0.5 * i), q=q) for i, (p, c) in enumerate(tree)]
    frames = ["w", "a", "b", "c", "d", "e", "f"]
    ops += [L(x, y, 1.0) for x in frames for y in frames]  # i, v, y configurations, ancestors both ways
    agree(ops)


def test_rule16_disconnected_trees_raise_connectivity():
    ours = agree([S("w", "a", 1.0), S("v", "b", 1.0), L("a", "b", 1.0), L("b", "a", 0)])
    assert ours[2]["exc"] == "ConnectivityException"
    assert ours[2]["msg"].endswith("not part of the same tree.Tf has two or more unconnected trees.")


def test_rule17_loops_are_detected_at_depth_1000():
    ops = [S("a", "b", 1.0), S("b", "a", 1.0), S("x", "y", 1.0), L("y", "a", 1.0), L("y", "b", 0)]
    ours = agree(ops)
    assert ours[3]["exc"] == "LookupException"
    assert ours[3]["msg"].startswith("The tf tree is invalid because it contains a loop.\nFrame b exists")
    assert _core.MAX_GRAPH_DEPTH == 1000


def test_rule18_lookup_full_composes_through_the_fixed_frame():
    q = (0.0, 0.0, math.sin(0.4), math.cos(0.4))
    ops = [
        S("w", "r", 1.0, t=(1, 0, 0), q=q),
        S("w", "r", 3.0, t=(5, 1, 0)),
        S("r", "cam", 0, t=(0, 0, 1), static=True),
    ]
    full = {
        "op": "lookup_full",
        "target": "cam",
        "target_time": 3.0,
        "source": "cam",
        "source_time": 1.0,
        "fixed": "w",
    }
    ops += [
        full,
        {**full, "fixed": "nope"},
        {"op": "can_full", **{k: v for k, v in full.items() if k != "op"}},
    ]
    ours = agree(ops)
    assert ours[3]["transform"]["stamp"] == [3, 0]  # the target-side stamp
    assert "argument fixed_frame does not exist" in ours[4]["msg"]


def test_rule19_all_frames_as_string():
    ours = agree(
        [{"op": "all_frames_as_string"}, S("w", "b", 1.0), S("b", "a", 1.0), {"op": "all_frames_as_string"}]
    )
    assert ours[0]["result"] == ""
    assert ours[3]["result"] == "Frame b exists with parent w.\nFrame a exists with parent b.\n"


def test_rule20_all_frames_as_yaml_ros2_format():
    b = tf.Buffer()
    assert b.all_frames_as_yaml() == "[]"  # ROS 2 (ROS 1 says "{}")
    b.set_transform(ts("w", "a", 1.0), "alice")
    b.set_transform(ts("w", "a", 3.0), "alice")
    b.set_transform_static(ts("a", "s", 0), "bob")
    assert b.all_frames_as_yaml() == (
        "a: \n  parent: 'w'\n  broadcaster: 'alice'\n  rate: 1.000\n  most_recent_transform: 3.000000\n"
        "  oldest_transform: 1.000000\n  buffer_length: 2.000\n"
        "s: \n  parent: 'a'\n  broadcaster: 'bob'\n  rate: 10000.000\n  most_recent_transform: 0.000000\n"
        "  oldest_transform: 0.000000\n  buffer_length: 0.000\n"
    )
    assert "transform_delay: 7.000" in b.all_frames_as_yaml(tf.Time(10))
    ops = [S("w", "a", 1.0), S("w", "a", 3.0), S("a", "s", 0, static=True), {"op": "all_frames_as_yaml"}]
    agree(ops)  # same content as tf2 apart from ROS 2's six-decimal stamps


def test_rule21_transformable_requests_and_callbacks_outside_the_lock():
    core = tf.Buffer(tf.Duration(10))._core
    fired = []

    def cb(handle, target, source, t, available):
        # re-entering the core from the callback would deadlock if it ran under the lock
        fired.append((handle, target, source, t, available, core.can_transform_reason(target, source, t)))

    assert core.insert("w", "a", 1_000_000_000, (0, 0, 0, 1, 0, 0, 0), "x", False)
    assert core.add_transformable_request(cb, "w", "a", 1_000_000_000) == 0  # alreadyTransformable
    handle = core.add_transformable_request(cb, "w", "b", 2_000_000_000)  # waitForNewTransform
    assert handle not in (0, _core.NEVER_TRANSFORMABLE)
    core.insert("w", "b", 1_000_000_000, (0, 0, 0, 1, 0, 0, 0), "x", False)
    assert fired == []
    core.insert("w", "b", 3_000_000_000, (0, 0, 0, 1, 0, 0, 0), "x", False)
    assert fired == [(handle, "w", "b", 2_000_000_000, True, "")]
    core.insert("w", "a", 20_000_000_000, (0, 0, 0, 1, 0, 0, 0), "x", False)
    core.insert("w", "a", 25_000_000_000, (0, 0, 0, 1, 0, 0, 0), "x", False)  # prunes the 1 s sample
    assert core.add_transformable_request(cb, "w", "a", 5_000_000_000) == _core.NEVER_TRANSFORMABLE  # old


def test_rule22_waiting_lookups_wake_on_new_data_then_raise_tf2s_error():
    b = tf.Buffer()
    b.set_transform(ts("w", "a", 1.0))
    timer = threading.Timer(0.2, lambda: b.set_transform(ts("w", "a", 2.0)))
    timer.start()
    try:
        got = b.lookup_transform("w", "a", tf.Time(2), timeout=tf.Duration(5))
    finally:
        timer.join()
    assert got.header.stamp == tf.Time(2)
    with pytest.raises(tf.ForwardExtrapolationException):  # after the timeout, the underlying error
        b.lookup_transform("w", "a", tf.Time(9), timeout=0.05)
    assert b.can_transform("w", "a", tf.Time(9), timeout=0.05) is False
    with pytest.raises(tf.TimeoutException, match="into the future"):
        b.wait_for_transform("w", "a", tf.Time(9), timeout=0.05)
