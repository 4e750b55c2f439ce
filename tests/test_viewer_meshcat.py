"""``urdftk view --backend meshcat --listen``: meshcat's page shows the robot in its colours and
follows joint states published by a robot state publisher in another process (this test)."""

from __future__ import annotations

import os
import random

import numpy as np
import pytest
from viewer_support import Browser, ViewProcess, colour_mask, count_in, free_port

import urdftk
from tf.transport.zenoh import ZenohTransport
from urdftk.joint_state import JointStatePublisher
from urdftk.robot_state import RobotStatePublisher

pytestmark = pytest.mark.timeout(240)

MM = "examples/robots/mobile_manipulator_description/urdf/mobile_manipulator.urdf.xacro"
ORANGE = (235, 120, 20)
CLEAN_ENV = {k: v for k, v in os.environ.items() if not k.startswith("URDFTK_ZENOH")}


def test_meshcat_draws_and_follows_joint_states():
    domain = random.randrange(10_000, 2_000_000_000)
    zport = free_port()
    robot = urdftk.load(MM)
    with ViewProcess([MM, "--backend", "meshcat", "--listen"], domain=domain, zenoh_port=zport) as view:
        assert "/static/" in view.url
        with ZenohTransport(connect=[f"tcp/127.0.0.1:{zport}"], domain_id=domain, environ=CLEAN_ENV) as bus:
            rsp = RobotStatePublisher(robot, bus, publish_frequency=0)
            jsp = JointStatePublisher(robot, bus, rate=20.0).start()
            try:
                with Browser(view.url) as browser:
                    browser.page.wait_for_timeout(1500)
                    before = browser.shot()
                    orange = colour_mask(before, ORANGE, tol=25)
                    assert count_in(orange, (0.0, 0.0, 1.0, 1.0)) > 200, "meshcat shows no orange base cover"
                    jsp.set_positions({"shoulder_lift_joint": -1.2, "elbow_joint": 1.4, "lift_joint": 0.4})
                    browser.page.wait_for_timeout(1000)
                    after = browser.shot()
                changed = np.abs(after - before).max(axis=2) > 40
                assert changed.sum() > 500, "meshcat did not follow the joint states"
            finally:
                jsp.close()
                rsp.close()
    assert not any("Traceback" in line for line in view.stderr), "".join(view.stderr)
