"""tf's public surface: __all__ of every module, messages, and the Buffer conveniences."""

from __future__ import annotations

import asyncio
import dataclasses
import importlib
import inspect
import pkgutil
import threading

import numpy as np
import pytest

import tf
from tf.transformations import quaternion_from_euler, quaternion_matrix, translation_matrix

TF_MODULES = ["tf"] + [m.name for m in pkgutil.walk_packages(tf.__path__, prefix="tf.")]


@pytest.mark.parametrize("name", TF_MODULES)
def test_all_matches_what_is_importable(name):
    module = importlib.import_module(name)
    exported = module.__all__
    assert len(set(exported)) == len(exported)  # the order is ruff's (RUF022)
    namespace: dict = {}
    exec(f"from {name} import *", namespace)
    assert sorted(k for k in namespace if k != "__builtins__") == sorted(exported)
    public = {
        k
        for k, v in vars(module).items()
        if not k.startswith("_") and (inspect.isclass(v) or inspect.isfunction(v)) and v.__module__ == name
    }
    assert public <= set(exported), (
        f"{name} defines public names missing from __all__: {public - set(exported)}"
    )


def test_time_and_duration_arithmetic():
    t = tf.Time(1, 1_500_000_000)
    assert (t.sec, t.nanosec) == (2, 500_000_000)
    assert tf.Time.from_sec(2.5) == t and t.to_sec() == 2.5 and t.nanoseconds == 2_500_000_000
    assert tf.Duration(10).nanoseconds == 10**10 and tf.Duration(-1.5) == tf.Duration(-2, 500_000_000)
    assert t + tf.Duration(1) == tf.Time(3, 500_000_000) and t - tf.Duration.from_sec(0.5) == tf.Time(2)
    assert tf.Time(3) - tf.Time(1) == tf.Duration(2) and -tf.Duration(2) == tf.Duration(-2)
    assert tf.Time(1) < tf.Time(1, 1) < tf.Time(2) and tf.Time().is_zero()
    assert abs(tf.Time.now().to_sec() - __import__("time").time()) < 5
    with pytest.raises(ValueError):
        tf.Time(-1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        t.sec = 5  # type: ignore[misc]
    with pytest.raises(TypeError):
        tf.Time(1) < tf.Duration(1)  # noqa: B015


def test_messages_have_ros2_field_names_and_are_values():
    names = {f.name for f in dataclasses.fields(tf.TransformStamped)}
    assert names == {"header", "child_frame_id", "transform"}
    assert [f.name for f in dataclasses.fields(tf.JointState)] == [
        "header",
        "name",
        "position",
        "velocity",
        "effort",
    ]
    js = tf.JointState(name=["a", "b"], position=np.array([1, 2]))
    assert js.position == (1.0, 2.0) and isinstance(js.position[0], float) and js.velocity == ()
    msg = tf.TFMessage([tf.TransformStamped(child_frame_id="c")])
    assert isinstance(msg.transforms, tuple)
    assert dataclasses.replace(msg.transforms[0], child_frame_id="d").child_frame_id == "d"
    assert tf.Quaternion() == tf.Quaternion(0, 0, 0, 1) and hash(tf.Quaternion()) == hash(
        tf.Quaternion(0, 0, 0, 1)
    )
    assert dataclasses.asdict(tf.Header(tf.Time(1), "f")) == {
        "stamp": {"sec": 1, "nanosec": 0},
        "frame_id": "f",
    }


def _tree() -> tf.Buffer:
    b = tf.Buffer(cache_time=5.0)
    q = quaternion_from_euler(0.1, 0.2, 0.3)
    for sec in (1, 2):
        b.set_transform(
            tf.TransformStamped(
                tf.Header(tf.Time(sec), "world"),
                "base",
                tf.Transform(tf.Vector3(sec, 0, 0), tf.Quaternion(*q)),
            )
        )
    b.set_transform_static(
        tf.TransformStamped(tf.Header(tf.Time(), "base"), "cam", tf.Transform(tf.Vector3(0, 0, 1)))
    )
    return b


def _matrix(ts: tf.TransformStamped) -> np.ndarray:
    t, q = ts.transform.translation, ts.transform.rotation
    return translation_matrix([t.x, t.y, t.z]) @ quaternion_matrix([q.x, q.y, q.z, q.w])


def test_transform_helpers_match_the_looked_up_matrix():
    b = _tree()
    assert b.cache_time == tf.Duration(5)
    T = _matrix(b.lookup_transform("world", "cam", tf.Time(2)))
    h = tf.Header(tf.Time(2), "cam")
    p = b.transform(tf.PointStamped(h, tf.Point(1, 2, 3)), "world")
    assert p.header.frame_id == "world" and p.header.stamp == tf.Time(2)
    np.testing.assert_allclose([p.point.x, p.point.y, p.point.z], (T @ [1, 2, 3, 1])[:3], atol=1e-12)
    v = b.transform(tf.Vector3Stamped(h, tf.Vector3(1, 0, 0)), "world")
    np.testing.assert_allclose([v.vector.x, v.vector.y, v.vector.z], T[:3, 0], atol=1e-12)
    q = quaternion_from_euler(0.3, -0.2, 1.0)
    pose = b.transform(tf.PoseStamped(h, tf.Pose(tf.Point(1, 2, 3), tf.Quaternion(*q))), "world")
    expected = T @ translation_matrix([1, 2, 3]) @ quaternion_matrix(q)
    o = pose.pose.orientation
    got = translation_matrix(
        [pose.pose.position.x, pose.pose.position.y, pose.pose.position.z]
    ) @ quaternion_matrix([o.x, o.y, o.z, o.w])
    np.testing.assert_allclose(got, expected, atol=1e-12)
    with pytest.raises(tf.InvalidArgumentException):
        tf.do_transform("nope", b.lookup_transform("world", "cam"))  # type: ignore[arg-type]


def test_batched_lookups_equal_single_lookups():
    b = _tree()
    for time in (tf.Time(), tf.Time(1, 250_000_000)):
        batch = b.lookup_transforms("world", ["cam", "base", "world"], time)
        assert batch.shape == (3, 4, 4)
        for i, src in enumerate(["cam", "base", "world"]):
            np.testing.assert_allclose(batch[i], _matrix(b.lookup_transform("world", src, time)), atol=1e-12)
    with pytest.raises(tf.LookupException):
        b.lookup_transforms("world", ["cam", "nope"])
    filled = b.lookup_transforms("world", ["cam", "nope"], fill_missing=True)
    assert not np.isnan(filled[0]).any() and np.isnan(filled[1]).all()


def test_introspection():
    b = _tree()
    assert b.frames() == ["base", "world", "cam"]
    assert b.get_parent("cam") == "base" and b.get_parent("world") is None
    assert b.get_latest_common_time("world", "cam") == tf.Time(2)
    dot = b.all_frames_as_dot()
    assert dot.startswith("digraph G {") and '"world" -> "base"' in dot and dot.endswith("}")
    assert b.why_not("world", "cam") == "" and "does not exist" in b.why_not("world", "x")
    with pytest.raises(tf.InvalidArgumentException):
        b.lookup_transform("world", "cam", 1.5)  # type: ignore[arg-type]
    with pytest.raises(tf.InvalidArgumentException):
        tf.Buffer(cache_time=0)
    assert b.can_transform_full("cam", tf.Time(2), "cam", tf.Time(1), "world", timeout=0.01)
    assert not b.can_transform_full("cam", tf.Time(9), "cam", tf.Time(1), "world", timeout=0.01)
    full = b.lookup_transform_full("cam", tf.Time(2), "cam", tf.Time(1), "world", timeout=0.5)
    expected = _matrix(b.lookup_transform("cam", "world", tf.Time(2))) @ _matrix(
        b.lookup_transform("world", "cam", tf.Time(1))
    )
    np.testing.assert_allclose(_matrix(full), expected, atol=1e-12)
    assert full.header.stamp == tf.Time(2)


def test_async_waiting_wakes_on_new_data():
    b = _tree()

    async def scenario():
        loop = asyncio.get_running_loop()
        loop.call_later(
            0.1,
            lambda: threading.Thread(
                target=b.set_transform,
                args=(tf.TransformStamped(tf.Header(tf.Time(3), "world"), "base", tf.Transform()),),
            ).start(),
        )
        got = await b.lookup_transform_async("world", "cam", tf.Time(3), timeout=5)
        with pytest.raises(tf.TimeoutException):
            await b.wait_for_transform_async("world", "cam", tf.Time(30), timeout=0.05)
        b.set_transform(tf.TransformStamped(tf.Header(tf.Time(8), "world"), "base", tf.Transform()))
        with pytest.raises(tf.ExtrapolationException):  # older than the cache keeps: never available
            await b.wait_for_transform_async("world", "cam", tf.Time(0, 1), timeout=5)
        return got

    got = asyncio.run(asyncio.wait_for(scenario(), 20))
    assert got.header.stamp == tf.Time(3)
    assert b._core._requests == {}  # every request was cancelled or fired


def test_batched_lookups_equal_single_lookups_on_random_trees():
    from tf_oracle_client import OurRunner, generate_dense

    ops = generate_dense(77, 3000)
    runner = OurRunner()
    checked = 0
    for i, op in enumerate(ops):
        if op["op"] != "new" and (i + 1 == len(ops) or ops[i + 1]["op"] != "new"):
            runner.step(i, op)
            continue
        if op["op"] != "new":
            runner.step(i, op)
        b = runner.buf
        names = b.frames()
        for target in names[:3]:
            for time in (tf.Time(), tf.Time(2), tf.Time(3, 300_000_000)):
                batch = b.lookup_transforms(target, names, time, fill_missing=True)
                for k, source in enumerate(names):
                    try:
                        single = _matrix(b.lookup_transform(target, source, time))
                    except tf.TransformException:
                        assert np.isnan(batch[k]).all()
                        continue
                    np.testing.assert_allclose(batch[k], single, atol=1e-9)
                    checked += 1
        if op["op"] == "new":
            runner.step(i, op)
    assert checked > 500
