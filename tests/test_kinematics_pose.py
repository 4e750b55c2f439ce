"""Pose: group axioms, round trips, immutability (no shared mutable arrays)."""

from __future__ import annotations

import numpy as np
import pytest

from urdftk.pose import Pose, matrix_to_quaternion


def _random_pose(rng) -> Pose:
    return Pose.from_translation_quaternion(rng.normal(size=3), rng.normal(size=4))


def test_group_axioms_and_composition():
    rng = np.random.default_rng(0)
    for _ in range(100):
        a, b, c = (_random_pose(rng) for _ in range(3))
        assert ((a @ b) @ c).allclose(a @ (b @ c))
        assert (a @ a.inverse()).allclose(Pose.identity())
        assert (Pose.identity() @ a).allclose(a)
        np.testing.assert_allclose((a @ b).matrix, a.matrix @ b.matrix, atol=1e-12)


def test_quaternion_round_trip_xyzw():
    rng = np.random.default_rng(1)
    for _ in range(200):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        q = q if q[3] >= 0 else -q
        p = Pose.from_translation_quaternion([1, 2, 3], q)
        np.testing.assert_allclose(p.quaternion, q, atol=1e-12)
        np.testing.assert_allclose(Pose.from_matrix(p.matrix).quaternion, q, atol=1e-12)
    z90 = Pose.from_translation_quaternion([0, 0, 0], [0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)])
    np.testing.assert_allclose(z90.rotation @ [1, 0, 0], [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(matrix_to_quaternion(np.diag([1.0, -1.0, -1.0])), [1, 0, 0, 0], atol=1e-12)


def test_immutable_and_no_shared_arrays():
    p = Pose.identity()
    m = p.matrix
    m[0, 3] = 5.0
    p.translation[0] = 7.0
    assert p.matrix[0, 3] == 0.0
    assert Pose.identity().matrix[0, 3] == 0.0
    with pytest.raises(AttributeError):
        p.x = 1  # type: ignore[attr-defined]
    src = np.eye(4)
    q = Pose.from_matrix(src)
    src[0, 3] = 1.0
    assert q.translation[0] == 0.0


@pytest.mark.parametrize(
    "matrix",
    [
        np.zeros((3, 3)),
        np.diag([1.0, 1.0, -1.0, 1.0]),
        np.full((4, 4), np.nan),
        np.diag([2.0, 1.0, 1.0, 1.0]),
    ],
)
def test_rejects_non_rigid(matrix):
    with pytest.raises(ValueError):
        Pose.from_matrix(matrix)
