"""``urdftk view --screenshot``, the command-line edge, and ``Viewer`` markers read off viser's wire."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from viewer_support import REPO, SceneClient, colour_mask, count_in, png_array

import urdftk
from urdftk.viewer import MARKER_TYPES, Viewer

pytestmark = pytest.mark.timeout(180)

ROBOT0 = REPO / "examples/robots/robot0_description/urdf/robot0.urdf"


def _run(*args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "urdftk", "view", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        cwd=REPO,
    )


def test_screenshot_writes_png_of_the_robot(tmp_path):
    out = tmp_path / "robot0.png"
    proc = _run(str(ROBOT0), "--port", "0", "--screenshot", str(out))
    assert proc.returncode == 0, proc.stderr
    assert "http://127.0.0.1:" in proc.stdout
    img = png_array(out.read_bytes())
    red = colour_mask(img, (153, 13, 13), tol=30)  # robot0's link material rgba 0.6 0.05 0.05
    assert count_in(red, (0.15, 0.1, 0.85, 0.95)) > 300, "robot0's red link is not in the screenshot"


def test_bad_input_is_one_line_exit_2(tmp_path):
    out = tmp_path / "never.png"
    proc = _run(str(tmp_path / "missing.urdf"), "--screenshot", str(out))
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "missing.urdf" in proc.stderr and "Traceback" not in proc.stderr
    assert not out.exists()
    proc = _run(str(ROBOT0), "--port", "70000")
    assert proc.returncode == 2 and "port" in proc.stderr


def test_markers_follow_their_frame():
    robot = urdftk.load(ROBOT0)
    joint = robot.description.joint_map["joint_1"]
    wheel = str(REPO / "examples/robots/mobile_manipulator_description/meshes/wheel.stl")
    with Viewer(robot, port=0) as viewer:
        scene = SceneClient(viewer.url)
        try:
            viewer.refresh()
            for i, kind in enumerate(MARKER_TYPES):
                fields = {
                    "ns": "t",
                    "id": i,
                    "position": (0.1 * i, 0, 0),
                    "orientation": (0, 0, 0.7071068, 0.7071068),
                }
                if kind == "line_strip":
                    fields["points"] = ((0, 0, 0), (0.1, 0, 0), (0.1, 0.1, 0))
                if kind == "text":
                    fields["text"] = "hello"
                if kind == "mesh":
                    fields["mesh_resource"] = wheel
                viewer.add_marker(kind, joint.child, **fields)
            wanted = {f"t:{i}" for i in range(len(MARKER_TYPES))}
            names = scene.wait(
                lambda s: (lambda found: found if {n.rsplit("/", 1)[1] for n in found} == wanted else None)(
                    [n for n in s.created if "/@markers/" in n and n.rsplit("/", 1)[1] in wanted]
                )
            )
            frame_node = names[0].split("/@markers/")[0]
            assert frame_node.endswith(f"/{joint.parent}/{joint.child}")
            assert all(n.split("/@markers/")[0] == frame_node for n in names)
            # the marker pose is sent relative to its frame's node; xyzw -> wxyz only on the wire
            box = next(n for n in names if n.endswith(f"t:{MARKER_TYPES.index('box')}"))
            T = scene.pose(box)
            np.testing.assert_allclose(T[:3, 3], [0.1 * MARKER_TYPES.index("box"), 0, 0], atol=1e-6)
            np.testing.assert_allclose(T[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-6)
            # moving the joint moves the frame node the markers hang from
            viewer.set_joint_positions({"joint_1": 0.7})
            expected = robot.transform(joint.parent, joint.child, robot.q({"joint_1": 0.7}))
            scene.wait(lambda s: np.allclose(s.pose(frame_node), expected, atol=1e-6) or None)
            np.testing.assert_allclose(scene.pose(box), T, atol=1e-9)
        finally:
            scene.close()
