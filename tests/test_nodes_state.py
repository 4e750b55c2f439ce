"""joint_state_publisher and robot_state_publisher: in one process and across processes."""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import threading

import numpy as np
import pytest
from helpers.procs import REPO, Child, child_env, unique_domain, urdftk_cmd

import tf
import urdftk
from tf.messages import Header, JointState, TFMessage, Time
from tf.transport import InProcessTransport
from tf.transport.zenoh import ZenohTransport
from urdftk.joint_state import JointStatePublisher
from urdftk.robot_state import RobotStatePublisher

pytestmark = pytest.mark.timeout(180)
MOBILE = REPO / "examples/robots/mobile_manipulator_description/urdf/mobile_manipulator.urdf.xacro"
CLEAN_ENV = {k: v for k, v in os.environ.items() if not k.startswith("URDFTK_ZENOH")}
SMALL = """<robot name="small">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/><link name="d"/><link name="e"/>
  <joint name="fixed_j" type="fixed"><parent link="base"/><child link="a"/>
    <origin xyz="0 0 0.5" rpy="0 0 1.0"/></joint>
  <joint name="rev" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0.1 0 0"/><axis xyz="0 0 1"/>
    <limit lower="0.2" upper="1.0" effort="1" velocity="1"/></joint>
  <joint name="cont" type="continuous"><parent link="b"/><child link="c"/>
    <origin xyz="0 0.2 0"/><axis xyz="1 0 0"/></joint>
  <joint name="slide" type="prismatic"><parent link="c"/><child link="d"/><axis xyz="0 0 1"/>
    <limit lower="-0.3" upper="-0.1" effort="1" velocity="1"/></joint>
  <joint name="follow" type="prismatic"><parent link="c"/><child link="e"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint="slide" multiplier="-2" offset="0.05"/></joint>
</robot>"""


@pytest.fixture(scope="module")
def mobile() -> urdftk.Robot:
    return urdftk.load(MOBILE)


@pytest.fixture(scope="module")
def small() -> urdftk.Robot:
    return urdftk.load(SMALL)


def _matrix(t: tf.TransformStamped) -> np.ndarray:
    v, q = t.transform.translation, t.transform.rotation
    T = tf.transformations.quaternion_matrix([q.x, q.y, q.z, q.w])
    T[:3, 3] = (v.x, v.y, v.z)
    return T


def test_joint_state_publisher_zeros_limits_mimic_continuous(small: urdftk.Robot) -> None:
    with InProcessTransport() as bus:
        got: list[JointState] = []
        bus.subscribe("/joint_states", JointState, got.append)
        jsp = JointStatePublisher(small, bus)
        msg = jsp.publish(Time(5, 0))
        assert got == [msg]
        values = dict(zip(msg.name, msg.position, strict=True))
        # 0 clamped into each joint's limits, taken from the robot (the URDF) itself
        for name, lo, hi in zip(small.joint_names, small.limits.lower, small.limits.upper, strict=True):
            assert values[name] == min(max(0.0, lo), hi)
        mult, off = small.mimic["follow"][1:]
        assert values["follow"] == pytest.approx(mult * values["slide"] + off)
        jsp.set_positions({"cont": 7.5, "rev": 5.0})
        values = jsp.positions
        assert values["cont"] == 7.5  # one angle, not wrapped, not cos/sin
        assert values["rev"] == 1.0  # clamped to the upper limit
        with pytest.raises(urdftk.JointNotFound, match="rev"):
            jsp.set_positions({"nope": 1.0})
        jsp.close()


def test_joint_state_publisher_merges_sources(small: urdftk.Robot, caplog: pytest.LogCaptureFixture) -> None:
    with InProcessTransport() as bus:
        jsp = JointStatePublisher(small, bus, source_list=["/src_a", "/src_b"], zeros={"rev": 0.5})
        assert jsp.positions["rev"] == 0.5
        a = bus.publisher("/src_a", JointState)
        b = bus.publisher("/src_b", JointState)
        a.publish(JointState(Header(), ["rev"], [0.7]))
        with caplog.at_level(logging.WARNING, logger="urdftk.joint_state"):
            b.publish(JointState(Header(), ["slide", "ghost"], [-0.2, 3.0]))
        values = jsp.positions
        assert values["rev"] == 0.7 and values["slide"] == -0.2
        assert values["follow"] == pytest.approx(-2 * -0.2 + 0.05)
        assert any("ghost" in r.getMessage() for r in caplog.records)
        got: list[JointState] = []
        bus.subscribe("/joint_states", JointState, got.append)
        jsp.rate = 200.0
        jsp.start()
        done = threading.Event()
        bus.subscribe("/joint_states", JointState, lambda _m: len(got) >= 5 and done.set())
        assert done.wait(5)
        jsp.close()
        assert dict(zip(got[-1].name, got[-1].position, strict=True))["rev"] == 0.7


def test_robot_state_publisher_statics_dynamics_prefix(mobile: urdftk.Robot, caplog) -> None:
    with InProcessTransport() as bus:
        statics: list[TFMessage] = []
        dynamics: list[TFMessage] = []
        bus.subscribe("/tf_static", TFMessage, statics.append)
        bus.subscribe("/tf", TFMessage, dynamics.append)
        rsp = RobotStatePublisher(mobile, bus, frame_prefix="r1/", publish_frequency=50.0)
        assert len(statics) == 1
        expected_static = {(f"r1/{a}", f"r1/{b}"): T for a, b, T in mobile.fixed_transforms()}
        assert {(t.header.frame_id, t.child_frame_id) for t in statics[0].transforms} == set(expected_static)
        for t in statics[0].transforms:
            np.testing.assert_allclose(
                _matrix(t), expected_static[t.header.frame_id, t.child_frame_id], atol=1e-12
            )
        q = mobile.random(3)
        names = list(mobile.joint_names)
        js = JointState(Header(Time(100, 5), ""), [*names, "not_a_joint"], [*q.tolist(), 1.0])
        with caplog.at_level(logging.WARNING, logger="urdftk.robot_state"):
            bus.publisher("/joint_states", JointState).publish(js)
        assert any("not_a_joint" in r.getMessage() for r in caplog.records)
        assert len(dynamics) == 1
        expected = {(f"r1/{a}", f"r1/{b}"): T for a, b, T in mobile.joint_transforms(q)}
        sent = dynamics[0].transforms
        assert {(t.header.frame_id, t.child_frame_id) for t in sent} == set(expected)  # mimic finger included
        for t in sent:
            assert t.header.stamp == Time(100, 5)
            np.testing.assert_allclose(_matrix(t), expected[t.header.frame_id, t.child_frame_id], atol=1e-12)
        # publish_frequency 50 Hz: a message 1 ms later is absorbed, one 20 ms later goes out
        pub = bus.publisher("/joint_states", JointState)
        pub.publish(JointState(Header(Time(100, 1_000_005), ""), names, q.tolist()))
        assert len(dynamics) == 1
        pub.publish(JointState(Header(Time(100, 20_000_005), ""), names, q.tolist()))
        assert len(dynamics) == 2
        rsp.close()


def test_in_process_pipeline_matches_frame_pose(mobile: urdftk.Robot) -> None:
    with InProcessTransport() as bus:
        buffer = tf.Buffer()
        tf.TransformListener(buffer, bus)
        rsp = RobotStatePublisher(mobile, bus, publish_frequency=0)
        jsp = JointStatePublisher(mobile, bus)
        q = mobile.random(11)
        jsp.set_positions(dict(zip(mobile.joint_names, q.tolist(), strict=True)))
        jsp.publish(Time(10, 0))
        for link in ("tool_center_point", "left_finger", "right_finger", "camera_optical_frame"):
            t = buffer.lookup_transform(mobile.root_link, link, Time(10, 0))
            np.testing.assert_allclose(_matrix(t), mobile.frame_pose(link, q), atol=1e-9)
        rsp.close()
        jsp.close()


def test_jsp_to_rsp_to_listener_across_processes(mobile: urdftk.Robot) -> None:
    domain = unique_domain()
    env = child_env(domain)
    zeros = {"lift_joint": 0.3, "shoulder_pan_joint": 0.4, "shoulder_lift_joint": -0.7, "elbow_joint": 1.1}
    zeros |= {"wrist_1_joint": 0.2, "wrist_2_joint": -0.5, "wrist_3_joint": 2.0, "left_finger_joint": 0.03}
    zeros |= {"left_wheel_joint": 9.0}  # continuous: any angle
    jsp_cmd = urdftk_cmd("joint-state-publisher", str(MOBILE), "--rate", "20")
    for k, v in zeros.items():
        jsp_cmd += ["--zeros", f"{k}={v}"]
    q = mobile.q(zeros)
    with (
        ZenohTransport(domain_id=domain, environ=CLEAN_ENV) as bus,
        Child(urdftk_cmd("robot-state-publisher", str(MOBILE)), env) as rsp,
        Child(jsp_cmd, env) as jsp,
    ):
        buffer = tf.Buffer()
        tf.TransformListener(buffer, bus)
        rsp.expect("running", 60)
        jsp.expect("running", 60)
        for link in ("tool_center_point", "right_finger", "camera_optical_frame"):
            t = buffer.lookup_transform(mobile.root_link, link, Time(), timeout=30.0)
            np.testing.assert_allclose(_matrix(t), mobile.frame_pose(link, q), atol=1e-9)


def test_node_cli_bad_input_is_one_line() -> None:
    proc = subprocess.run(
        [*urdftk_cmd("joint-state-publisher", str(MOBILE), "--zeros", "elbow")],
        capture_output=True,
        text=True,
        timeout=60,
        env=child_env(unique_domain()),
    )
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "JOINT=VALUE" in proc.stderr
    proc = subprocess.run(
        [sys.executable, "-m", "urdftk", "robot-state-publisher", "/nonexistent.urdf"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
