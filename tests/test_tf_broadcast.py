"""Broadcasters, listeners and the in-process transport; the course's call form; the examples."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import tf
from tf.transformations import euler_from_quaternion, quaternion_from_euler
from tf.transport import InProcessTransport, default_transport

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples"


def _ts(parent, child, stamp, x=0.0):
    return tf.TransformStamped(tf.Header(stamp, parent), child, tf.Transform(tf.Vector3(x, 0.0, 0.0)))


def test_course_send_transform_form_reaches_a_listener():
    with InProcessTransport() as bus:
        buf = tf.Buffer()
        listener = tf.TransformListener(buf, bus)
        br = tf.TransformBroadcaster(bus)
        q = tf.transformations.quaternion_from_euler(0.25, 0.1, 0.2)
        br.sendTransform((0.2, 0.25, 1), q, tf.Time.now(), "my_frame", "world")  # child, then parent
        t = buf.lookup_transform("world", "my_frame", tf.Time())
        assert (t.transform.translation.x, t.transform.translation.y, t.transform.translation.z) == (
            0.2,
            0.25,
            1.0,
        )
        r = t.transform.rotation
        assert euler_from_quaternion((r.x, r.y, r.z, r.w)) == pytest.approx((0.25, 0.1, 0.2), abs=1e-12)
        br.send_transform(_ts("world", "a", tf.Time(5)))  # tf2 form, one message
        br.send_transform([_ts("world", "b", tf.Time(5)), _ts("b", "c", tf.Time(5), 1.0)])  # or a list
        br.sendTransform(_ts("world", "d", tf.Time(5)))
        assert buf.lookup_transform("world", "c", tf.Time(5)).transform.translation.x == 1.0
        assert {"a", "b", "c", "d"} <= set(buf.frames())
        listener.close()
        br.send_transform(_ts("world", "e", tf.Time(5)))
        assert not buf.frame_exists("e")
        with pytest.raises(TypeError):
            br.sendTransform((0, 0, 0), (0, 0, 0, 1))


def test_static_broadcaster_latches_the_accumulated_set_for_late_listeners():
    with InProcessTransport() as bus:
        sb = tf.StaticTransformBroadcaster(bus)
        sb.send_transform(_ts("base", "laser", tf.Time(1), 0.1))
        sb.send_transform(_ts("base", "camera", tf.Time(1), 0.2))
        sb.send_transform(_ts("base", "laser", tf.Time(2), 0.3))  # replaces the first laser
        other = tf.StaticTransformBroadcaster(bus)
        other.send_transform(_ts("world", "base", tf.Time(1), 1.0))
        late = tf.Buffer()
        tf.TransformListener(late, bus)  # created after everything was sent
        assert late.lookup_transform("world", "laser", tf.Time(123)).transform.translation.x == pytest.approx(
            1.3
        )
        assert late.lookup_transform("base", "camera", tf.Time()).transform.translation.x == 0.2
        assert len(sb.transforms) == 2
        assert "exists with parent base" in late.all_frames_as_string()
        yaml = late.all_frames_as_yaml()
        assert "rate: 10000.000" in yaml  # stored as static


def test_several_broadcasters_and_listeners_across_threads():
    n_threads, n_msgs = 4, 300
    with InProcessTransport() as bus:
        buffers = [tf.Buffer(tf.Duration(100)) for _ in range(3)]
        listeners = [tf.TransformListener(b, bus) for b in buffers]
        start = threading.Barrier(n_threads)
        errors = []

        def publish(i):
            try:
                br = tf.TransformBroadcaster(bus)
                start.wait()
                for k in range(1, n_msgs + 1):
                    br.send_transform(
                        _ts("world" if i == 0 else f"link{i - 1}", f"link{i}", tf.Time(1, k * 1000), k)
                    )
            except Exception as exc:
                errors.append(exc)

        threads = [threading.Thread(target=publish, args=(i,)) for i in range(n_threads)]
        for th in threads:
            th.start()
        for th in threads:
            th.join(30)
        assert not errors
        for b in buffers:
            for i in range(n_threads):
                assert len(b._core._caches[b._core._ids[f"link{i}"]]) == n_msgs
            t = b.lookup_transform("world", f"link{n_threads - 1}", tf.Time())
            assert t.transform.translation.x == pytest.approx(n_threads * n_msgs)
        for listener in listeners:
            listener.close()


def test_transport_contract_errors_isolated_and_close():
    with InProcessTransport() as bus:
        got = []

        def bad(msg):
            raise RuntimeError("boom")

        bus.subscribe("/tf", tf.TFMessage, bad)
        sub = bus.subscribe("/tf", tf.TFMessage, got.append)
        pub = bus.publisher("/tf", tf.TFMessage)
        pub.publish(tf.TFMessage())
        assert len(got) == 1  # the raising subscriber did not stop delivery
        with pytest.raises(TypeError):
            pub.publish("not a message")
        sub.close()
        pub.publish(tf.TFMessage())
        assert len(got) == 1
        latched = bus.publisher("/tf_static", tf.TFMessage, latched=True)
        latched.publish(tf.TFMessage())
        late = []
        bus.subscribe("/tf_static", tf.TFMessage, late.append)
        assert len(late) == 1
        latched.close()  # withdraws the latched message
        later = []
        bus.subscribe("/tf_static", tf.TFMessage, later.append)
        assert later == []
    pub.publish(tf.TFMessage())  # a closed transport's publishers do nothing


def test_default_transport_is_lazy_shared_and_chosen_by_env():
    code = (
        "import tf.transport as t, sys\n"
        "assert 'tf.transport.zenoh' not in sys.modules\n"
        "a = t.default_transport(); b = t.default_transport()\n"
        "print(type(a).__name__, a is b)\n"
        "import tf; br = tf.TransformBroadcaster(); buf = tf.Buffer(); tf.TransformListener(buf)\n"
        "br.sendTransform((1, 2, 3), (0, 0, 0, 1), tf.Time(1), 'c', 'p')\n"
        "print(buf.lookup_transform('p', 'c', tf.Time()).transform.translation.z)\n"
    )
    env = dict(os.environ, URDFTK_TRANSPORT="inproc")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["InProcessTransport", "True", "3.0"]
    env["URDFTK_TRANSPORT"] = "carrier-pigeon"
    bad = subprocess.run(
        [sys.executable, "-c", "import tf.transport as t; t.default_transport()"],
        env=env,
        capture_output=True,
        text=True,
    )
    assert bad.returncode != 0 and "carrier-pigeon" in bad.stderr
    assert callable(default_transport)


def _course_broadcaster() -> list[str]:
    """The Python broadcaster's code lines, as printed in the course (section 4.2.2.3)."""
    text = (REPO.parent / "shared" / "seed" / "ros-course.txt").read_text(encoding="utf-8")
    section = text[text.index("4.2.2.3 Publishing a tf marker in Python") :]
    block = section.split("```")[1]
    return [ln.rstrip() for ln in block.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]


def test_course_broadcaster_differs_only_in_rospy_lines():
    import difflib

    course = _course_broadcaster()
    ours = [
        ln.rstrip()
        for ln in (EXAMPLES / "tf_broadcaster.py").read_text().splitlines()
        if ln.strip() and not ln.lstrip().startswith("#")
    ]
    assert any("sendTransform" in ln for ln in course), "course block not found"
    # The course passes my_FrameName without defining it; the example defines it (one added line).
    undefined_name_fix = 'my_FrameName = "my_FrameName"'
    matcher = difflib.SequenceMatcher(a=course, b=ours, autojunk=False)
    for op, i1, i2, j1, j2 in matcher.get_opcodes():
        if op == "equal":
            continue
        removed, added = course[i1:i2], [ln for ln in ours[j1:j2] if ln != undefined_name_fix]
        assert all("rospy" in ln for ln in removed), (removed, added)
        assert len(added) <= len(removed), (removed, added)


@pytest.mark.timeout(120)
def test_course_broadcaster_reaches_a_listener_in_another_process():
    """The course script, unchanged but for rospy lines, talks to a listener process over Zenoh."""
    import signal

    env = {k: v for k, v in os.environ.items() if k != "URDFTK_TRANSPORT"}
    env["ROS_DOMAIN_ID"] = str(100 + os.getpid() % 100)
    br = subprocess.Popen(
        [sys.executable, str(EXAMPLES / "tf_broadcaster.py")],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        ls = subprocess.run(
            [sys.executable, str(EXAMPLES / "tf_listener.py"), "--count", "2", "--timeout", "20"],
            env=env,
            capture_output=True,
            text=True,
            timeout=90,
        )
        assert ls.returncode == 0, ls.stderr
        assert ls.stdout.count("- Translation: [0.200, 0.250, 1.000]") == 2
        rpy = euler_from_quaternion(quaternion_from_euler(0.25, 0.1, 0.2))
        assert f"in RPY (radian) [{rpy[0]:.3f}, {rpy[1]:.3f}, {rpy[2]:.3f}]" in ls.stdout
        assert br.poll() is None, br.stderr.read()
        br.send_signal(signal.SIGINT)  # Ctrl-C: the script's `except KeyboardInterrupt` ends it cleanly
        _, err = br.communicate(timeout=20)
        assert br.returncode == 0, err
        assert "Traceback" not in err
    finally:
        if br.poll() is None:
            br.kill()
            br.wait()


def test_course_quaternion_matches_matrix_composition():
    q = quaternion_from_euler(0.25, 0.1, 0.2)
    m = tf.transformations.euler_matrix(0.25, 0.1, 0.2)
    np.testing.assert_allclose(tf.transformations.quaternion_matrix(q), m, atol=1e-15)
