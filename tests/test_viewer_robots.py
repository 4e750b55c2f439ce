"""``urdftk view`` on example-robot-data's Panda (Collada colours) and Talos (STL + URDF materials).

Each robot is drawn in headless Chromium; the "Visual" checkbox is switched off in the page and
the difference between the two pictures is the robot: it must lie in the middle of the view
(the camera frames the robot) and carry the robot's own colours.
"""

from __future__ import annotations

import numpy as np
import pytest
from viewer_support import Browser, ViewProcess, colour_mask, count_in, example_robot_data, scene_only

pytestmark = pytest.mark.timeout(240)

CENTRE = (0.15, 0.08, 0.64, 0.95)  # around the view centre, left of the control panel


def _robot_pixels(path: str) -> tuple[np.ndarray, np.ndarray]:
    with ViewProcess([path]) as view, Browser(view.url) as browser:
        shown = browser.shot()
        browser.tab("Display")
        browser.click_checkbox("Visual")
        hidden = browser.shot()
    robot = scene_only(np.abs(shown - hidden).max(axis=2) > 30)
    return shown, robot


def _check_region(robot: np.ndarray) -> None:
    assert robot.sum() > 2000, "no robot drawn"
    assert count_in(robot, CENTRE) > 0.97 * robot.sum(), "robot pixels outside the expected region"


def test_panda_collada_colours():
    path = str(example_robot_data() / "robots/panda_description/urdf/panda.urdf")
    shown, robot = _robot_pixels(path)
    _check_region(robot)
    px = shown[robot]
    # the Collada materials: white links and dark grey (64, 64, 64) joints, lit
    grey = np.ptp(px, axis=1) < 12
    dark = grey & (px.max(axis=1) < 110)
    light = grey & (px.min(axis=1) > 170)
    assert dark.sum() > 100, "Panda's dark grey Collada material is missing"
    assert light.sum() > 500, "Panda's white Collada material is missing"


def test_talos_urdf_materials():
    path = str(example_robot_data() / "robots/talos_data/robots/talos_full_v2.urdf")
    shown, robot = _robot_pixels(path)
    _check_region(robot)
    px = shown[robot]
    orange = colour_mask(px[None], (255, 128, 0), tol=30)[0]
    dark = (np.ptp(px, axis=1) < 15) & (px.max(axis=1) < 80)
    assert orange.sum() > 50, "Talos's orange URDF material is missing"
    assert dark.sum() > 300, "Talos's dark grey URDF material is missing"
