"""examples/robots (every robot file found, at least one): fk vs raw Pinocchio and yourdfpy to 1e-9 m
at 20 seeded configurations, Jacobians vs central finite differences, fk_batch == fk row by row."""

from __future__ import annotations

import numpy as np
import pytest
from _kinematics_oracle import (
    EXAMPLES,
    example_robots,
    fd_jacobians,
    raw_pin_poses,
    yourdfpy_model,
    yourdfpy_poses,
)

import urdftk


@pytest.mark.parametrize("path", example_robots(), ids=lambda p: str(p.relative_to(EXAMPLES)))
def test_example_robot_against_oracles(path):
    robot = urdftk.load(path)
    rng = np.random.default_rng(7)
    ydf = yourdfpy_model(robot)
    Q = np.array([robot.random(rng) for _ in range(20)]).reshape(20, robot.dof)
    for q in Q:
        F = robot.fk(q)
        np.testing.assert_allclose(F, raw_pin_poses(robot, q), atol=1e-9, rtol=0)
        np.testing.assert_allclose(F, yourdfpy_poses(ydf, robot, q), atol=1e-9, rtol=0)
    singles = np.array([robot.fk(q) for q in Q])
    for backend in ("numba", "numpy"):
        np.testing.assert_allclose(robot.fk_batch(Q, backend=backend), singles, atol=1e-12, rtol=0)
    for q in Q[:3]:
        for reference, expected in fd_jacobians(robot, q).items():
            for i, link in enumerate(robot.link_names):
                np.testing.assert_allclose(robot.jacobian(link, q, reference), expected[i], atol=1e-6, rtol=0)
