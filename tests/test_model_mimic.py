"""Mimic joints on real robots: the four files Pinocchio's mimic=True rejects, and a gripper whose
follower moves with its master (example-robot-data robots and the example mobile manipulator)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from _kinematics_oracle import EXAMPLES, erd_urdfs, raw_pin_poses, xml_mimics

import urdftk
from urdftk.errors import MimicWarning

FILES = {"/".join(p.parts[-3:]): p for p in erd_urdfs()}
PIN_MIMIC_FAILS = ["talos_full_v2.urdf", "talos_full_v2_box.urdf", "romeo.urdf", "alex_psyonic_hands.urdf"]


def _find(name: str) -> Path:
    hits = [p for key, p in FILES.items() if key.endswith("/" + name)]
    assert len(hits) == 1, (name, hits)
    return hits[0]


def test_pinocchio_mimic_really_fails_on_these_four():
    for name in PIN_MIMIC_FAILS:
        with pytest.raises(Exception, match="mimic"):
            pin.buildModelFromUrdf(str(_find(name)), mimic=True)


@pytest.mark.parametrize("name", PIN_MIMIC_FAILS)
def test_real_robot_loads_with_mimic_honoured(name):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = urdftk.load(_find(name))
    expected = xml_mimics(robot)
    assert expected, "the file has mimic joints"
    assert set(robot.mimic) == set(expected)
    for follower, (master, mult, off) in expected.items():
        assert follower not in robot.joint_names
        assert robot.mimic[follower] == (master, mult, off)
    repaired = [w for w in caught if issubclass(w.category, MimicWarning)]
    assert bool(repaired) == (name == "alex_psyonic_hands.urdf")
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = robot.random(rng)
        values = robot.joint_positions(q)
        for follower, (master, mult, off) in expected.items():
            assert values[follower] == pytest.approx(mult * values[master] + off, abs=1e-12)
        np.testing.assert_allclose(robot.fk(q), raw_pin_poses(robot, q), atol=1e-9)


def test_alex_psyonic_targets_resolved_within_the_prefix():
    with pytest.warns(MimicWarning, match="Left_index_q2"):
        robot = urdftk.load(_find("alex_psyonic_hands.urdf"))
    assert robot.mimic["Left_index_q2"][0] == "Left_index_q1"
    assert robot.mimic["Right_pinky_q2"][0] == "Right_pinky_q1"


def _moves_with_master(robot, master: str, follower: str, child_link: str) -> None:
    mult = robot.mimic[follower][1]
    lo, hi = (
        robot.limits.lower[robot.joint_names.index(master)],
        robot.limits.upper[robot.joint_names.index(master)],
    )
    poses = []
    for value in np.linspace(lo, hi, 5):
        q = robot.q({master: value})
        assert robot.joint_positions(q)[follower] == pytest.approx(mult * value + robot.mimic[follower][2])
        poses.append(robot.frame_pose(child_link, q))
        np.testing.assert_allclose(robot.fk(q), raw_pin_poses(robot, q), atol=1e-9)
    moved = [np.abs(p - poses[0]).max() for p in poses[1:]]
    assert min(moved) > 1e-4, "the follower's link must move when only the master changes"


def test_panda_finger_follows():
    robot = urdftk.load(_find("panda.urdf"))
    _moves_with_master(robot, "panda_finger_joint1", "panda_finger_joint2", "panda_rightfinger")
    q = robot.q({"panda_finger_joint1": 0.03})
    left = robot.transform("panda_hand", "panda_leftfinger", q)[:3, 3]
    right = robot.transform("panda_hand", "panda_rightfinger", q)[:3, 3]
    assert np.linalg.norm(left - right) == pytest.approx(0.06, abs=1e-9)


def test_pr2_gripper_follows():
    robot = urdftk.load(_find("pr2.urdf"))
    _moves_with_master(
        robot, "r_gripper_l_finger_joint", "r_gripper_r_finger_tip_joint", "r_gripper_r_finger_tip_link"
    )


def test_example_mobile_manipulator_gripper_follows():
    path = EXAMPLES / "mobile_manipulator_description" / "urdf" / "mobile_manipulator.urdf.xacro"
    robot = urdftk.load(path)
    assert robot.mimic == {"right_finger_joint": ("left_finger_joint", -1.0, 0.0)}
    _moves_with_master(robot, "left_finger_joint", "right_finger_joint", "right_finger")
    q = robot.q({"left_finger_joint": 0.03})
    y_left = robot.transform("gripper_base_link", "left_finger", q)[1, 3]
    y_right = robot.transform("gripper_base_link", "right_finger", q)[1, 3]
    assert y_left == pytest.approx(-y_right, abs=1e-12) and y_left > 0.03
