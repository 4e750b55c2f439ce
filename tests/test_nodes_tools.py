"""urdftk tf echo|frames|static, topic list|echo|hz and router: real processes over Zenoh."""

from __future__ import annotations

import math
import re
import sys

import numpy as np
import pytest
import yaml
from helpers.procs import CHILD, Child, child_env, unique_domain, urdftk_cmd

from tf.transformations import euler_from_quaternion, quaternion_from_euler, quaternion_matrix
from urdftk.tftools import parse_static_args

pytestmark = pytest.mark.timeout(180)
NUM = r"(-?\d+\.\d+)"


def _parse_echo(text: str) -> list[dict]:
    """Parse tf2_echo blocks into numbers."""
    blocks = []
    pattern = re.compile(
        rf"At time (\d+)\.(\d{{9}})\n"
        rf"- Translation: \[{NUM}, {NUM}, {NUM}\]\n"
        rf"- Rotation: in Quaternion \[{NUM}, {NUM}, {NUM}, {NUM}\]\n"
        rf"- Rotation: in RPY \(radian\) \[{NUM}, {NUM}, {NUM}\]\n"
        rf"- Rotation: in RPY \(degree\) \[{NUM}, {NUM}, {NUM}\]\n"
        r"- Matrix:\n((?:(?: +-?\d+\.\d{3}){4}\n){3}(?: +-?\d+\.\d{3}){4})"
    )
    for m in pattern.finditer(text):
        g = m.groups()
        blocks.append(
            {
                "stamp": (int(g[0]), int(g[1])),
                "xyz": [float(v) for v in g[2:5]],
                "quat": [float(v) for v in g[5:9]],
                "rpy": [float(v) for v in g[9:12]],
                "deg": [float(v) for v in g[12:15]],
                "matrix": np.array([[float(v) for v in row.split()] for row in g[15].splitlines()]),
            }
        )
    return blocks


def test_tf_static_both_forms_and_echo_output_parsed() -> None:
    domain = unique_domain()
    env = child_env(domain)
    xyz, ypr = (0.5, -1.25, 2.0), (0.3, -0.2, 0.1)  # yaw pitch roll (static_transform_publisher order)
    euler = urdftk_cmd("tf", "static", *map(str, (*xyz, *ypr)), "world", "sensor")
    q2 = quaternion_from_euler(0.0, 0.0, math.pi / 2)
    quat = urdftk_cmd("tf", "static", "1", "2", "3", *map(str, q2), "sensor", "tip")
    with Child(euler, env) as s1, Child(quat, env) as s2:
        s1.expect("publishing static transform from world to sensor", 30)
        s2.expect("publishing static transform from sensor to tip", 30)
        echo = Child(
            urdftk_cmd("tf", "echo", "world", "sensor", "--count", "2", "--rate", "5", "--timeout", "30"), env
        )
        assert echo.wait(60) == 0, echo.describe()
        blocks = _parse_echo("".join(echo.stdout))
        assert len(blocks) == 2, echo.describe()
        expected_q = quaternion_from_euler(ypr[2], ypr[1], ypr[0])
        for b in blocks:
            assert b["stamp"] == (0, 0)  # statics are valid at every time: tf2_echo shows time 0
            assert b["xyz"] == pytest.approx(xyz, abs=5e-4)
            assert b["quat"] == pytest.approx(list(expected_q), abs=5e-4)
            assert b["rpy"] == pytest.approx([ypr[2], ypr[1], ypr[0]], abs=5e-4)
            assert b["deg"] == pytest.approx([math.degrees(v) for v in (ypr[2], ypr[1], ypr[0])], abs=5e-3)
            M = quaternion_matrix(expected_q)
            M[:3, 3] = xyz
            np.testing.assert_allclose(b["matrix"], M, atol=5e-4)
        chained = Child(urdftk_cmd("tf", "echo", "world", "tip", "--count", "1", "--timeout", "30"), env)
        assert chained.wait(60) == 0, chained.describe()
        (b,) = _parse_echo("".join(chained.stdout))
        T1 = quaternion_matrix(expected_q)
        T1[:3, 3] = xyz
        T2 = quaternion_matrix(q2)
        T2[:3, 3] = (1, 2, 3)
        np.testing.assert_allclose(b["matrix"], T1 @ T2, atol=5e-4)


def test_tf_static_ros2_flags_and_errors() -> None:
    t = parse_static_args([], xyz=(1, None, 3), rpy=(0.1, None, None), frame_id="a", child_frame_id="b")
    q = t.transform.rotation
    assert euler_from_quaternion([q.x, q.y, q.z, q.w]) == pytest.approx((0.1, 0, 0))
    assert (t.transform.translation.x, t.transform.translation.y, t.header.frame_id) == (1, 0, "a")
    t = parse_static_args([], quaternion=(0, 0, 2, 2), frame_id="a", child_frame_id="b")
    assert (t.transform.rotation.z, t.transform.rotation.w) == pytest.approx((2**-0.5, 2**-0.5))
    for bad in (["1", "2"], ["1", "2", "3", "x", "0", "0", "a", "b"], ["0"] * 7 + ["a", "a"], ["0"] * 9):
        with pytest.raises(ValueError):
            parse_static_args(bad)
    with pytest.raises(ValueError, match="zero"):
        parse_static_args(["0", "0", "0", "0", "0", "0", "0", "a", "b"])
    env = child_env(unique_domain())
    proc = Child(urdftk_cmd("tf", "static", "--x", "1", "--frame-id", "a"), env)
    assert proc.wait(60) == 2 and "child-frame-id" in "".join(proc.stderr)


def test_tf_frames_graph_and_topic_tools(tmp_path) -> None:
    domain = unique_domain()
    env = child_env(domain)
    with (
        Child([sys.executable, CHILD, "broadcast", "--rate", "50", "--frames", "2"], env) as pub,
        Child([sys.executable, CHILD, "static", "--frames", "1"], env) as static,
    ):
        pub.expect("ready", 30)
        static.expect("sent", 30)
        gv = tmp_path / "frames.gv"
        frames = Child(urdftk_cmd("tf", "frames", "-o", str(gv), "--duration", "2"), env)
        assert frames.wait(60) == 0, frames.describe()
        dot = gv.read_text()
        edges = set(re.findall(r'"([^"]+)" -> "([^"]+)"\[label', dot))
        assert edges == {("world", "f0"), ("f0", "f1"), ("world", "s0")}
        labels = re.findall(
            r'"([^"]+)" -> "([^"]+)"\[label=" Broadcaster: (\S+)\\nAverage rate: ([\d.]+)', dot
        )
        by_child = {c: (b, float(r)) for _, c, b, r in labels}
        assert by_child["f1"][0] == "child_broadcast" and 30 < by_child["f1"][1] < 70
        assert by_child["s0"][0] == "child_static"
        assert "Most recent transform:" in dot and "Oldest transform:" in dot
        pdf = tmp_path / "frames.pdf"
        assert Child(urdftk_cmd("tf", "frames", "-o", str(pdf), "--duration", "0.5"), env).wait(60) == 0
        assert pdf.read_bytes().startswith(b"%PDF")

        listing = Child(urdftk_cmd("topic", "list", "-t"), env)
        assert listing.wait(60) == 0, listing.describe()
        assert "/tf [tf2_msgs/msg/TFMessage]" in "".join(listing.stdout)
        assert "/tf_static [tf2_msgs/msg/TFMessage]" in "".join(listing.stdout)

        echo = Child(urdftk_cmd("topic", "echo", "/tf", "--count", "2", "--timeout", "20"), env)
        assert echo.wait(60) == 0, echo.describe()
        docs = [d for d in yaml.safe_load_all("".join(echo.stdout)) if d]
        assert len(docs) == 2
        assert [t["child_frame_id"] for t in docs[0]["transforms"]] == ["f0", "f1"]
        assert docs[0]["transforms"][0]["header"]["frame_id"] == "world"

        hz = Child(urdftk_cmd("topic", "hz", "/tf", "--duration", "2.5"), env)
        assert hz.wait(60) == 0, hz.describe()
        rates = [float(r) for r in re.findall(r"average rate: ([\d.]+)", "".join(hz.stdout))]
        assert rates and 35 < rates[-1] < 65, hz.describe()
