"""Quaternion/transform arithmetic exactly as tf2's LinearMath does it (plain floats, no numpy).

Used by the core's finalisation and by ``lookup_transform_full``; the per-link hot loop in
``_core`` inlines the same formulas.
"""

from __future__ import annotations

import math

__all__ = [
    "Raw",
    "canonical_rotation",
    "compose",
    "matrix_from_quaternion",
    "quat_multiply",
    "quat_rotate",
    "quaternion_from_matrix",
]

Raw = tuple  # (qx, qy, qz, qw, tx, ty, tz)


def quat_multiply(
    x1: float, y1: float, z1: float, w1: float, x2: float, y2: float, z2: float, w2: float
) -> tuple[float, float, float, float]:
    """Hamilton product q1 * q2 (tf2 operator*)."""
    return (
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 + y1 * w2 + z1 * x2 - x1 * z2,
        w1 * z2 + z1 * w2 + x1 * y2 - y1 * x2,
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
    )


def quat_rotate(
    x: float, y: float, z: float, w: float, vx: float, vy: float, vz: float
) -> tuple[float, float, float]:
    """tf2 quatRotate: q * v * conj(q) (scales by |q|^2 for a non-unit q, as tf2 does)."""
    rx = w * vx + y * vz - z * vy
    ry = w * vy + z * vx - x * vz
    rz = w * vz + x * vy - y * vx
    rw = -x * vx - y * vy - z * vz
    return (
        -rw * x + rx * w - ry * z + rz * y,
        -rw * y + ry * w - rz * x + rx * z,
        -rw * z + rz * w - rx * y + ry * x,
    )


def matrix_from_quaternion(x: float, y: float, z: float, w: float) -> tuple[float, ...]:
    """tf2 Matrix3x3::setRotation: the (normalised) rotation matrix, row-major 9-tuple."""
    s = 2.0 / (x * x + y * y + z * z + w * w)
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    return (
        1.0 - (yy + zz), xy - wz, xz + wy,
        xy + wz, 1.0 - (xx + zz), yz - wx,
        xz - wy, yz + wx, 1.0 - (xx + yy),
    )  # fmt: skip


def quaternion_from_matrix(m: tuple[float, ...]) -> tuple[float, float, float, float]:
    """tf2 Matrix3x3::getRotation (xyzw)."""
    m00, m01, m02, m10, m11, m12, m20, m21, m22 = m
    trace = m00 + m11 + m22
    if trace > 0.0:
        s = math.sqrt(trace + 1.0)
        w = s * 0.5
        s = 0.5 / s
        return (m21 - m12) * s, (m02 - m20) * s, (m10 - m01) * s, w
    rows = ((m00, m01, m02), (m10, m11, m12), (m20, m21, m22))
    i = (2 if m11 < m22 else 1) if m00 < m11 else (2 if m00 < m22 else 0)
    j = (i + 1) % 3
    k = (i + 2) % 3
    s = math.sqrt(rows[i][i] - rows[j][j] - rows[k][k] + 1.0)
    q = [0.0, 0.0, 0.0, 0.0]
    q[i] = s * 0.5
    s = 0.5 / s
    q[3] = (rows[k][j] - rows[j][k]) * s
    q[j] = (rows[j][i] + rows[i][j]) * s
    q[k] = (rows[k][i] + rows[i][k]) * s
    return q[0], q[1], q[2], q[3]


def canonical_rotation(x: float, y: float, z: float, w: float) -> tuple[float, float, float, float]:
    """What tf2 (ROS 2) returns for an accumulated rotation: through a matrix and back.

    ROS 2's BufferCore stores the result in a ``tf2::Transform`` (a rotation matrix) before
    writing the message, so the returned quaternion is normalised, with tf2's sign choice.
    ``quaternion_from_matrix(matrix_from_quaternion(...))`` inlined (equal up to rounding: the
    trace > 0 branch uses m21 - m12 = 2 w x s directly; the branch choice is computed as tf2 does).
    """
    s = 2.0 / (x * x + y * y + z * z + w * w)
    xs, ys, zs = x * s, y * s, z * s
    m00 = 1.0 - (y * ys + z * zs)
    m11 = 1.0 - (x * xs + z * zs)
    m22 = 1.0 - (x * xs + y * ys)
    trace = m00 + m11 + m22
    if trace > 0.0:
        r = math.sqrt(trace + 1.0)
        k = w / r  # (m21 - m12) * 0.5 / r = 2 w xs * 0.5 / r, and so on (equal up to rounding)
        return xs * k, ys * k, zs * k, r * 0.5
    return quaternion_from_matrix(matrix_from_quaternion(x, y, z, w))


def compose(a: Raw, b: Raw) -> Raw:
    """tf2::Transform product a * b via rotation matrices (as lookupTransform-full does)."""
    ma = matrix_from_quaternion(*a[:4])
    mb = matrix_from_quaternion(*b[:4])
    m = tuple(
        ma[3 * r] * mb[c] + ma[3 * r + 1] * mb[3 + c] + ma[3 * r + 2] * mb[6 + c]
        for r in range(3)
        for c in range(3)
    )
    bx, by, bz = b[4:]
    return (
        *quaternion_from_matrix(m),
        ma[0] * bx + ma[1] * by + ma[2] * bz + a[4],
        ma[3] * bx + ma[4] * by + ma[5] * bz + a[5],
        ma[6] * bx + ma[7] * by + ma[8] * bz + a[6],
    )
