"""``urdftk view --watch``: editing a link length in a xacro on disk shows the new geometry within
2 s; a syntax error keeps the previous robot and shows the message in the page."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import numpy as np
import pytest
from viewer_support import REPO, Browser, SceneClient, ViewProcess, scene_only

pytestmark = pytest.mark.timeout(240)

PKG = REPO / "examples/robots/mobile_manipulator_description"
NODE_SUFFIX = "/upper_arm_link/forearm_link"


def test_reload_on_edit_and_error(tmp_path: Path):
    pkg = tmp_path / "mobile_manipulator_description"
    shutil.copytree(PKG, pkg)
    top = pkg / "urdf/mobile_manipulator.urdf.xacro"
    arm = pkg / "urdf/arm.xacro"  # an included file
    original = arm.read_text()
    with ViewProcess([str(top), "--watch"]) as view:
        scene = SceneClient(view.url)
        with Browser(view.url) as browser:
            node = scene.wait(lambda s: next((n for n in s.created if n.endswith(NODE_SUFFIX)), None), 30)
            scene.wait(lambda s: abs(s.pose(node)[2, 3] - 0.425) < 1e-9, 10)
            before = browser.shot()
            # 1. a longer upper arm, in the included arm.xacro
            arm.write_text(
                original.replace(
                    'name="arm_upper_arm_length" value="0.425"', 'name="arm_upper_arm_length" value="0.625"'
                )
            )
            t0 = time.monotonic()
            scene.wait(
                lambda s: any(
                    n.endswith(NODE_SUFFIX) and abs(s.pose(n)[2, 3] - 0.625) < 1e-9 for n in s.created
                ),
                2.0,
            )
            assert time.monotonic() - t0 <= 2.0
            after = browser.shot()
            assert scene_only(np.abs(after - before).max(axis=2) > 40).sum() > 300, (
                "the page does not show the longer arm"
            )
            # 2. a syntax error: the message is shown, the robot stays
            arm.write_text(
                original.replace("</robot>", "<robot") if "</robot>" in original else original + "<oops"
            )
            browser.page.get_by_text("Reload failed", exact=False).wait_for(timeout=10_000)
            text = browser.page.get_by_text("Reload failed", exact=False).inner_text()
            assert "arm.xacro" in text, text
            kept = browser.shot()
            browser.page.screenshot(path=str(tmp_path / "kept.png"))
            node = next(n for n in scene.created if n.endswith(NODE_SUFFIX))
            assert abs(scene.pose(node)[2, 3] - 0.625) < 1e-9, "the previous robot was not kept"
            assert scene_only(np.abs(kept - after).max(axis=2) > 40).sum() < 200, (
                "the picture changed after a failed reload"
            )
        scene.close()
