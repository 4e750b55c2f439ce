"""``urdftk view`` end to end: a real viewer process, a real headless Chromium, real Zenoh /tf.

The mobile manipulator (xacro, OBJ/MTL + STL meshes, mimic gripper) is drawn in its colours;
moving a slider in the page changes the picture and the /tf a separate listener receives
(compared with ``robot.frame_pose``); choosing a fixed frame in the page moves the scene root to
``T_fixed_root`` (read from viser's own websocket messages); the collision toggle shows the
collision geometry.
"""

from __future__ import annotations

import os
import random

import numpy as np
import pytest
from viewer_support import Browser, SceneClient, ViewProcess, colour_mask, count_in, free_port

import tf
import urdftk
from tf.transport.zenoh import ZenohTransport

pytestmark = pytest.mark.timeout(240)

MM = "examples/robots/mobile_manipulator_description/urdf/mobile_manipulator.urdf.xacro"
ORANGE = (235, 120, 20)  # base_cover.mtl Kd
PURPLE = (140, 64, 217)  # urdftk.viewer._geometry.COLLISION_RGBA
CENTRE = (0.2, 0.15, 0.8, 0.95)
CLEAN_ENV = {k: v for k, v in os.environ.items() if not k.startswith("URDFTK_ZENOH")}


def _lookup(buffer: tf.Buffer, target: str, source: str) -> np.ndarray:
    return buffer.lookup_transforms(target, [source])[0]


@pytest.fixture(scope="module")
def session():
    domain = random.randrange(10_000, 2_000_000_000)
    zport = free_port()
    robot = urdftk.load(MM)
    with ViewProcess([MM, "--publish"], domain=domain, zenoh_port=zport) as view:
        bus = ZenohTransport(connect=[f"tcp/127.0.0.1:{zport}"], domain_id=domain, environ=CLEAN_ENV)
        buffer = tf.Buffer()
        listener = tf.TransformListener(buffer, bus)
        scene = SceneClient(view.url)
        browser = Browser(view.url)
        try:
            yield robot, view, buffer, scene, browser
        finally:
            browser.close()
            scene.close()
            listener.close()
            bus.close()


def test_robot_drawn_in_its_colours(session):
    _robot, _view, _buffer, _scene, browser = session
    img = browser.shot()
    orange = colour_mask(img, ORANGE, tol=25)
    assert count_in(orange, CENTRE) > 300, "the orange base cover (OBJ/MTL colour) is not drawn"
    # the robot is in the middle of the view (the camera is framed on it), not at the edges
    assert count_in(orange, CENTRE) > 0.95 * orange.sum()
    # the collision geometry is hidden by default
    assert count_in(colour_mask(img, PURPLE, tol=20), (0, 0, 1, 1)) < 50


def test_slider_moves_robot_and_tf(session):
    robot, _view, buffer, scene, browser = session
    q = robot.neutral()
    tip = "tool0"
    assert buffer.can_transform(robot.root_link, tip, tf.Time(), timeout=20), buffer.all_frames_as_string()
    before_img = browser.shot()
    np.testing.assert_allclose(_lookup(buffer, robot.root_link, tip), robot.frame_pose(tip, q), atol=1e-6)
    browser.set_slider("shoulder_lift_joint", -1.2)
    browser.set_slider("elbow_joint", 1.0)
    q = robot.q({"shoulder_lift_joint": -1.2, "elbow_joint": 1.0})
    expected = robot.frame_pose(tip, q)

    def tf_matches() -> bool:
        try:
            return np.allclose(_lookup(buffer, robot.root_link, tip), expected, atol=1e-4)
        except tf.TransformException:
            return False

    deadline = tf.Time.now().to_sec() + 15
    while not tf_matches():
        assert tf.Time.now().to_sec() < deadline, "the listener never received the slider's pose on /tf"
        browser.page.wait_for_timeout(200)
    after_img = browser.shot()
    changed = np.abs(after_img - before_img).max(axis=2) > 40
    assert count_in(changed, CENTRE) > 500, "the picture did not change after moving the sliders"
    # the scene node of the elbow's child carries exactly the joint transform TF has
    node = scene.wait(
        lambda s: next((n for n in s.created if n.endswith("/upper_arm_link/forearm_link")), None)
    )
    T_upper_forearm = robot.transform("upper_arm_link", "forearm_link", q)
    scene.wait(lambda s: np.allclose(s.pose(node), T_upper_forearm, atol=1e-5))


def test_fixed_frame_switch_moves_scene_root(session):
    robot, _view, buffer, scene, browser = session
    root_node = f"/tf/{robot.root_link}"
    scene.wait(lambda s: root_node in s.created)
    browser.tab("Display")
    browser.choose("Fixed frame", "tool0")
    T_root_tool = _lookup(buffer, robot.root_link, "tool0")
    expected = np.linalg.inv(T_root_tool)  # the root node is placed at T_fixed_root
    got = scene.wait(
        lambda s: s.pose(root_node) if np.allclose(s.pose(root_node), expected, atol=1e-4) else None
    )
    np.testing.assert_allclose(got, expected, atol=1e-4)
    browser.choose("Fixed frame", robot.root_link)
    scene.wait(lambda s: np.allclose(s.pose(root_node), np.eye(4), atol=1e-9))
    browser.tab("Joints")


def test_collision_toggle(session):
    _robot, _view, _buffer, scene, browser = session
    browser.tab("Display")
    browser.click_checkbox("Collision")
    scene.wait(lambda s: any(n.endswith("/@collision") and v for n, v in s.visible.items()))
    img = browser.shot()
    assert count_in(colour_mask(img, PURPLE, tol=20), CENTRE) > 300, "collision geometry not drawn"
    browser.click_checkbox("Collision")
    scene.wait(lambda s: not any(n.endswith("/@collision") and v for n, v in s.visible.items()))
    browser.tab("Joints")
