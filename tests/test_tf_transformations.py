"""tf.transformations against independent implementations (trimesh's transformations, Pinocchio).

trimesh ships Gohlke's transformations.py with wxyz quaternions; ROS's tf.transformations is the
same code with xyzw. Pinocchio's rpy gives the course's roll-pitch-yaw independently.
"""

from __future__ import annotations

import math
import random

import numpy as np
import pinocchio as pin
import pytest
import trimesh.transformations as ref

from tf import transformations as T

AXES = sorted(T.AXES)
RNG = random.Random(1234)
ANGLES = [tuple(RNG.uniform(-math.pi, math.pi) for _ in range(3)) for _ in range(25)]
ANGLES += [(0.0, math.pi / 2, 0.3), (0.2, -math.pi / 2, 0.1), (0.0, 0.0, 0.0)]  # gimbal lock cases


def xyzw(wxyz):
    return np.array([wxyz[1], wxyz[2], wxyz[3], wxyz[0]])


def test_all_24_conventions_are_supported():
    assert len(AXES) == 24 and set(AXES) == set(ref._AXES2TUPLE)


@pytest.mark.parametrize("axes", AXES)
def test_euler_matrix_and_quaternion_match_reference(axes):
    for a in ANGLES:
        np.testing.assert_allclose(T.euler_matrix(*a, axes=axes), ref.euler_matrix(*a, axes=axes), atol=1e-14)
        np.testing.assert_allclose(
            T.quaternion_from_euler(*a, axes=axes), xyzw(ref.quaternion_from_euler(*a, axes=axes)), atol=1e-14
        )
        np.testing.assert_allclose(
            T.euler_from_matrix(T.euler_matrix(*a, axes=axes), axes),
            ref.euler_from_matrix(ref.euler_matrix(*a, axes=axes), axes),
            atol=1e-12,
        )


@pytest.mark.parametrize("axes", AXES)
def test_euler_quaternion_round_trip(axes):
    for a in ANGLES:
        q = T.quaternion_from_euler(*a, axes=axes)
        assert np.linalg.norm(q) == pytest.approx(1.0)
        back = T.euler_from_quaternion(q, axes)
        # angles may differ (e.g. gimbal lock) but the rotation is the same
        np.testing.assert_allclose(T.euler_matrix(*back, axes=axes), T.euler_matrix(*a, axes=axes), atol=1e-9)
        np.testing.assert_allclose(T.quaternion_matrix(q), T.euler_matrix(*a, axes=axes), atol=1e-14)


def test_sxyz_is_roll_pitch_yaw_as_in_pinocchio():
    for r, p, y in ANGLES:
        np.testing.assert_allclose(T.euler_matrix(r, p, y)[:3, :3], pin.rpy.rpyToMatrix(r, p, y), atol=1e-14)
        x, yy, z, w = T.quaternion_from_euler(r, p, y)
        np.testing.assert_allclose(
            pin.Quaternion(w, x, yy, z).toRotationMatrix(), pin.rpy.rpyToMatrix(r, p, y), atol=1e-14
        )
        if abs(abs(p) - math.pi / 2) > 1e-6:
            assert T.euler_from_quaternion((x, yy, z, w)) == pytest.approx(
                tuple(pin.rpy.matrixToRpy(pin.rpy.rpyToMatrix(r, p, y))), abs=1e-12
            )


def test_quaternion_products_match_matrix_composition():
    for _ in range(50):
        q0, q1 = T.random_quaternion(), T.random_quaternion()
        np.testing.assert_allclose(
            T.quaternion_matrix(T.quaternion_multiply(q1, q0)),
            T.concatenate_matrices(T.quaternion_matrix(q1), T.quaternion_matrix(q0)),
            atol=1e-14,
        )
        np.testing.assert_allclose(
            T.quaternion_multiply(q1, q0),
            xyzw(ref.quaternion_multiply(q1[[3, 0, 1, 2]], q0[[3, 0, 1, 2]])),
            atol=1e-15,
        )
        np.testing.assert_allclose(
            T.quaternion_multiply(q0, T.quaternion_inverse(q0)), [0, 0, 0, 1], atol=1e-14
        )
        np.testing.assert_allclose(
            T.quaternion_multiply(q0, T.quaternion_conjugate(q0)), [0, 0, 0, 1], atol=1e-14
        )
        m = T.quaternion_matrix(q0)
        q = T.quaternion_from_matrix(m)
        assert min(np.abs(q - q0).max(), np.abs(q + q0).max()) < 1e-12


def test_slerp_about_axis_and_matrices_match_reference():
    for _ in range(20):
        q0, q1 = T.random_quaternion(), T.random_quaternion()
        for f in (0.0, 0.25, 0.5, 1.0):
            np.testing.assert_allclose(
                T.quaternion_slerp(q0, q1, f),
                xyzw(ref.quaternion_slerp(q0[[3, 0, 1, 2]], q1[[3, 0, 1, 2]], f)),
                atol=1e-12,
            )
    axis, angle = [1.0, 2.0, 3.0], 0.7
    np.testing.assert_allclose(
        T.quaternion_about_axis(angle, axis), xyzw(ref.quaternion_about_axis(angle, axis)), atol=1e-15
    )
    np.testing.assert_allclose(
        T.rotation_matrix(angle, axis, [1, 2, 0]), ref.rotation_matrix(angle, axis, [1, 2, 0]), atol=1e-14
    )
    t = T.translation_matrix([1, 2, 3])
    np.testing.assert_array_equal(T.translation_from_matrix(t), [1, 2, 3])
    np.testing.assert_allclose(T.concatenate_matrices(t, T.inverse_matrix(t)), np.identity(4))
    assert T.is_same_transform(t, t * 2.0)
    assert T.vector_norm([3, 4]) == 5.0
    np.testing.assert_allclose(T.unit_vector([[3, 4], [0, 2]], axis=1), [[0.6, 0.8], [0, 1]])
    with pytest.raises(ValueError, match="unknown Euler axes"):
        T.euler_matrix(0, 0, 0, "xyz")
