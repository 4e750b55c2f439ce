"""``urdftk fk``: table and JSON output checked against Robot/Pinocchio; bad input exits 2 with one line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from _kinematics_oracle import EXAMPLES, raw_pin_poses

import urdftk

ROBOT0 = EXAMPLES / "robot0_description" / "urdf" / "robot0.urdf"
MOBILE = EXAMPLES / "mobile_manipulator_description" / "urdf" / "mobile_manipulator.urdf.xacro"


def _run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "urdftk", "fk", *args], capture_output=True, text=True, timeout=120
    )


def test_table_output():
    res = _run(str(ROBOT0), "joint_1:=0.5")
    assert res.returncode == 0, res.stderr
    robot = urdftk.load(ROBOT0)
    expected = raw_pin_poses(robot, np.array([0.5]))
    rows = {line.split()[0]: line.split()[1:] for line in res.stdout.splitlines()[3:]}
    assert list(rows) == list(robot.link_names)
    for i, link in enumerate(robot.link_names):
        np.testing.assert_allclose([float(v) for v in rows[link][:3]], expected[i][:3, 3], atol=1e-6)


def test_json_output_with_frame_and_mimic():
    res = _run(
        str(MOBILE),
        "left_finger_joint:=0.02",
        "lift_joint:=0.3",
        "--frame",
        "right_finger",
        "--frame",
        "tool0",
        "--format",
        "json",
    )
    assert res.returncode == 0, res.stderr
    doc = json.loads(res.stdout)
    assert list(doc["frames"]) == ["right_finger", "tool0"]
    assert doc["joints"]["right_finger_joint"] == pytest.approx(-0.02)
    robot = urdftk.load(MOBILE)
    q = robot.q({"left_finger_joint": 0.02, "lift_joint": 0.3})
    expected = raw_pin_poses(robot, q)
    for name, frame in doc["frames"].items():
        np.testing.assert_allclose(frame["matrix"], expected[robot.link_names.index(name)], atol=1e-12)
        assert len(frame["quaternion_xyzw"]) == 4


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["joint_x:=0.5"], "unknown joint 'joint_x'"),
        (["joint_1:=50"], "out of limits"),
        (["joint_1:=abc"], "not a number"),
        (["--frame", "nope"], "unknown frame 'nope'"),
        (["stray"], "unexpected argument"),
    ],
)
def test_errors_exit_2_with_one_line(args, message):
    res = _run(str(ROBOT0), *args)
    assert res.returncode == 2
    assert res.stdout == ""
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0] and "Traceback" not in res.stderr


def test_missing_file_exit_2(tmp_path: Path):
    res = _run(str(tmp_path / "none.urdf"))
    assert res.returncode == 2 and len(res.stderr.strip().splitlines()) == 1


def test_clip_flag():
    res = _run(str(ROBOT0), "joint_1:=50", "--clip", "--format", "json")
    assert res.returncode == 0 and json.loads(res.stdout)["joints"]["joint_1"] == pytest.approx(np.pi)
