"""The ROS ``tf.transformations`` helpers: homogeneous matrices, Euler angles, quaternions (xyzw).

Same names, argument order and conventions as ROS 1's ``tf.transformations`` (Gohlke's
transformations.py as shipped by ROS): quaternions are ``[x, y, z, w]``, Euler axes are given as a
4-letter string such as ``'sxyz'`` (the default: static frame, roll about x, pitch about y, yaw about
z) or ``'rzyx'`` (rotating frame); all 24 conventions are supported. Matrices are 4x4 numpy arrays.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import reduce

import numpy as np

__all__ = [
    "AXES",
    "concatenate_matrices",
    "euler_from_matrix",
    "euler_from_quaternion",
    "euler_matrix",
    "identity_matrix",
    "inverse_matrix",
    "is_same_transform",
    "quaternion_about_axis",
    "quaternion_conjugate",
    "quaternion_from_euler",
    "quaternion_from_matrix",
    "quaternion_inverse",
    "quaternion_matrix",
    "quaternion_multiply",
    "quaternion_slerp",
    "random_quaternion",
    "random_rotation_matrix",
    "rotation_matrix",
    "translation_from_matrix",
    "translation_matrix",
    "unit_vector",
    "vector_norm",
]

_EPS = np.finfo(float).eps * 4.0
_NEXT_AXIS = (1, 2, 0, 1)

# axes string -> (first axis, parity, repetition, frame); 's' = static, 'r' = rotating frame.
AXES: dict[str, tuple[int, int, int, int]] = {
    "sxyz": (0, 0, 0, 0), "sxyx": (0, 0, 1, 0), "sxzy": (0, 1, 0, 0), "sxzx": (0, 1, 1, 0),
    "syzx": (1, 0, 0, 0), "syzy": (1, 0, 1, 0), "syxz": (1, 1, 0, 0), "syxy": (1, 1, 1, 0),
    "szxy": (2, 0, 0, 0), "szxz": (2, 0, 1, 0), "szyx": (2, 1, 0, 0), "szyz": (2, 1, 1, 0),
    "rzyx": (0, 0, 0, 1), "rxyx": (0, 0, 1, 1), "ryzx": (0, 1, 0, 1), "rxzx": (0, 1, 1, 1),
    "rxzy": (1, 0, 0, 1), "ryzy": (1, 0, 1, 1), "rzxy": (1, 1, 0, 1), "ryxy": (1, 1, 1, 1),
    "ryxz": (2, 0, 0, 1), "rzxz": (2, 0, 1, 1), "rxyz": (2, 1, 0, 1), "rzyz": (2, 1, 1, 1),
}  # fmt: skip


def _axes(axes: str | tuple[int, int, int, int]) -> tuple[int, int, int, int]:
    if isinstance(axes, tuple):
        return axes
    try:
        return AXES[axes.lower()]
    except (KeyError, AttributeError):
        raise ValueError(f"unknown Euler axes {axes!r}; use one of {sorted(AXES)}") from None


def identity_matrix() -> np.ndarray:
    """A new 4x4 identity matrix."""
    return np.identity(4)


def translation_matrix(direction: Sequence[float]) -> np.ndarray:
    """The 4x4 matrix translating by ``direction`` (x, y, z)."""
    m = np.identity(4)
    m[:3, 3] = np.asarray(direction, dtype=float)[:3]
    return m


def translation_from_matrix(matrix: np.ndarray) -> np.ndarray:
    """The translation (x, y, z) of a 4x4 matrix."""
    return np.array(matrix, dtype=float, copy=True)[:3, 3]


def rotation_matrix(
    angle: float, direction: Sequence[float], point: Sequence[float] | None = None
) -> np.ndarray:
    """The 4x4 matrix rotating by ``angle`` (rad) about the axis ``direction`` through ``point``."""
    s, c = math.sin(angle), math.cos(angle)
    d = unit_vector(np.asarray(direction, dtype=float)[:3])
    r = np.diag([c, c, c]) + np.outer(d, d) * (1.0 - c)
    d = d * s
    r += np.array([[0.0, -d[2], d[1]], [d[2], 0.0, -d[0]], [-d[1], d[0], 0.0]])
    m = np.identity(4)
    m[:3, :3] = r
    if point is not None:
        p = np.asarray(point, dtype=float)[:3]
        m[:3, 3] = p - r @ p
    return m


def euler_matrix(ai: float, aj: float, ak: float, axes: str = "sxyz") -> np.ndarray:
    """The 4x4 rotation matrix from Euler angles ``ai, aj, ak`` (rad) in convention ``axes``."""
    first, parity, repetition, frame = _axes(axes)
    i = first
    j = _NEXT_AXIS[i + parity]
    k = _NEXT_AXIS[i - parity + 1]
    if frame:
        ai, ak = ak, ai
    if parity:
        ai, aj, ak = -ai, -aj, -ak
    si, sj, sk = math.sin(ai), math.sin(aj), math.sin(ak)
    ci, cj, ck = math.cos(ai), math.cos(aj), math.cos(ak)
    cc, cs = ci * ck, ci * sk
    sc, ss = si * ck, si * sk
    m = np.identity(4)
    if repetition:
        m[i, i], m[i, j], m[i, k] = cj, sj * si, sj * ci
        m[j, i], m[j, j], m[j, k] = sj * sk, -cj * ss + cc, -cj * cs - sc
        m[k, i], m[k, j], m[k, k] = -sj * ck, cj * sc + cs, cj * cc - ss
    else:
        m[i, i], m[i, j], m[i, k] = cj * ck, sj * sc - cs, sj * cc + ss
        m[j, i], m[j, j], m[j, k] = cj * sk, sj * ss + cc, sj * cs - sc
        m[k, i], m[k, j], m[k, k] = -sj, cj * si, cj * ci
    return m


def euler_from_matrix(matrix: np.ndarray, axes: str = "sxyz") -> tuple[float, float, float]:
    """Euler angles (rad) in convention ``axes`` of the rotation part of ``matrix`` (3x3 or 4x4)."""
    first, parity, repetition, frame = _axes(axes)
    i = first
    j = _NEXT_AXIS[i + parity]
    k = _NEXT_AXIS[i - parity + 1]
    m = np.asarray(matrix, dtype=float)[:3, :3]
    if repetition:
        sy = math.hypot(m[i, j], m[i, k])
        if sy > _EPS:
            ax, ay, az = math.atan2(m[i, j], m[i, k]), math.atan2(sy, m[i, i]), math.atan2(m[j, i], -m[k, i])
        else:
            ax, ay, az = math.atan2(-m[j, k], m[j, j]), math.atan2(sy, m[i, i]), 0.0
    else:
        cy = math.hypot(m[i, i], m[j, i])
        if cy > _EPS:
            ax, ay, az = math.atan2(m[k, j], m[k, k]), math.atan2(-m[k, i], cy), math.atan2(m[j, i], m[i, i])
        else:
            ax, ay, az = math.atan2(-m[j, k], m[j, j]), math.atan2(-m[k, i], cy), 0.0
    if parity:
        ax, ay, az = -ax, -ay, -az
    if frame:
        ax, az = az, ax
    return ax, ay, az


def euler_from_quaternion(quaternion: Sequence[float], axes: str = "sxyz") -> tuple[float, float, float]:
    """Euler angles (rad) in convention ``axes`` of an xyzw quaternion (roll, pitch, yaw for 'sxyz')."""
    return euler_from_matrix(quaternion_matrix(quaternion), axes)


def quaternion_from_euler(ai: float, aj: float, ak: float, axes: str = "sxyz") -> np.ndarray:
    """The xyzw quaternion of Euler angles ``ai, aj, ak`` (rad); ``(roll, pitch, yaw)`` for 'sxyz'."""
    first, parity, repetition, frame = _axes(axes)
    i = first
    j = _NEXT_AXIS[i + parity]
    k = _NEXT_AXIS[i - parity + 1]
    if frame:
        ai, ak = ak, ai
    if parity:
        aj = -aj
    ai, aj, ak = ai / 2.0, aj / 2.0, ak / 2.0
    ci, si = math.cos(ai), math.sin(ai)
    cj, sj = math.cos(aj), math.sin(aj)
    ck, sk = math.cos(ak), math.sin(ak)
    cc, cs = ci * ck, ci * sk
    sc, ss = si * ck, si * sk
    q = np.empty(4)
    if repetition:
        q[i] = cj * (cs + sc)
        q[j] = sj * (cc + ss)
        q[k] = sj * (cs - sc)
        q[3] = cj * (cc - ss)
    else:
        q[i] = cj * sc - sj * cs
        q[j] = cj * ss + sj * cc
        q[k] = cj * cs - sj * sc
        q[3] = cj * cc + sj * ss
    if parity:
        q[j] *= -1.0
    return q


def quaternion_about_axis(angle: float, axis: Sequence[float]) -> np.ndarray:
    """The xyzw quaternion rotating by ``angle`` (rad) about ``axis``."""
    q = np.zeros(4)
    q[:3] = np.asarray(axis, dtype=float)[:3]
    n = vector_norm(q[:3])
    if n > _EPS:
        q[:3] *= math.sin(angle / 2.0) / n
    q[3] = math.cos(angle / 2.0)
    return q


def quaternion_matrix(quaternion: Sequence[float]) -> np.ndarray:
    """The 4x4 rotation matrix of an xyzw quaternion (normalised first; zero gives identity)."""
    q = np.array(quaternion[:4], dtype=float, copy=True)
    n = float(q @ q)
    if n < _EPS:
        return np.identity(4)
    q *= math.sqrt(2.0 / n)
    o = np.outer(q, q)
    return np.array(
        [
            [1.0 - o[1, 1] - o[2, 2], o[0, 1] - o[2, 3], o[0, 2] + o[1, 3], 0.0],
            [o[0, 1] + o[2, 3], 1.0 - o[0, 0] - o[2, 2], o[1, 2] - o[0, 3], 0.0],
            [o[0, 2] - o[1, 3], o[1, 2] + o[0, 3], 1.0 - o[0, 0] - o[1, 1], 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def quaternion_from_matrix(matrix: np.ndarray) -> np.ndarray:
    """The xyzw quaternion of the rotation part of a 4x4 (or 3x3) matrix."""
    m = np.identity(4)
    src = np.asarray(matrix, dtype=float)
    m[: src.shape[0], : src.shape[1]] = src[:4, :4]
    q = np.empty(4)
    t = float(np.trace(m))
    if t > m[3, 3]:
        q[3] = t
        q[2] = m[1, 0] - m[0, 1]
        q[1] = m[0, 2] - m[2, 0]
        q[0] = m[2, 1] - m[1, 2]
    else:
        i, j, k = 0, 1, 2
        if m[1, 1] > m[0, 0]:
            i, j, k = 1, 2, 0
        if m[2, 2] > m[i, i]:
            i, j, k = 2, 0, 1
        t = m[i, i] - (m[j, j] + m[k, k]) + m[3, 3]
        q[i] = t
        q[j] = m[i, j] + m[j, i]
        q[k] = m[k, i] + m[i, k]
        q[3] = m[k, j] - m[j, k]
    q *= 0.5 / math.sqrt(t * m[3, 3])
    return q


def quaternion_multiply(quaternion1: Sequence[float], quaternion0: Sequence[float]) -> np.ndarray:
    """The product ``quaternion1 * quaternion0`` (apply q0 first, then q1), xyzw."""
    x0, y0, z0, w0 = quaternion0
    x1, y1, z1, w1 = quaternion1
    return np.array(
        [
            x1 * w0 + y1 * z0 - z1 * y0 + w1 * x0,
            -x1 * z0 + y1 * w0 + z1 * x0 + w1 * y0,
            x1 * y0 - y1 * x0 + z1 * w0 + w1 * z0,
            -x1 * x0 - y1 * y0 - z1 * z0 + w1 * w0,
        ]
    )


def quaternion_conjugate(quaternion: Sequence[float]) -> np.ndarray:
    """The conjugate (-x, -y, -z, w)."""
    x, y, z, w = quaternion
    return np.array([-x, -y, -z, w], dtype=float)


def quaternion_inverse(quaternion: Sequence[float]) -> np.ndarray:
    """The inverse: conjugate divided by the squared norm."""
    q = quaternion_conjugate(quaternion)
    return q / float(q @ q)


def quaternion_slerp(
    quat0: Sequence[float], quat1: Sequence[float], fraction: float, spin: int = 0, shortestpath: bool = True
) -> np.ndarray:
    """Spherical linear interpolation between two xyzw quaternions (0 -> quat0, 1 -> quat1)."""
    q0 = unit_vector(np.asarray(quat0, dtype=float)[:4])
    q1 = unit_vector(np.asarray(quat1, dtype=float)[:4])
    if fraction == 0.0:
        return q0
    if fraction == 1.0:
        return q1
    d = float(q0 @ q1)
    if abs(abs(d) - 1.0) < _EPS:
        return q0
    if shortestpath and d < 0.0:
        d = -d
        q1 = -q1
    angle = math.acos(max(-1.0, min(1.0, d))) + spin * math.pi
    if abs(angle) < _EPS:
        return q0
    isin = 1.0 / math.sin(angle)
    return q0 * (math.sin((1.0 - fraction) * angle) * isin) + q1 * (math.sin(fraction * angle) * isin)


def random_quaternion(rand: Sequence[float] | None = None) -> np.ndarray:
    """A uniformly distributed random unit quaternion (xyzw); ``rand``: three numbers in [0, 1)."""
    r = np.random.random_sample(3) if rand is None else np.asarray(rand, dtype=float)
    r1, r2 = math.sqrt(1.0 - r[0]), math.sqrt(r[0])
    t1, t2 = 2.0 * math.pi * r[1], 2.0 * math.pi * r[2]
    return np.array([math.sin(t1) * r1, math.cos(t1) * r1, math.sin(t2) * r2, math.cos(t2) * r2])


def random_rotation_matrix(rand: Sequence[float] | None = None) -> np.ndarray:
    """A uniformly distributed random 4x4 rotation matrix."""
    return quaternion_matrix(random_quaternion(rand))


def concatenate_matrices(*matrices: np.ndarray) -> np.ndarray:
    """Multiply 4x4 matrices left to right: passing ``T_a_b, T_b_c`` gives ``T_a_c``."""
    return reduce(np.dot, matrices, np.identity(4))


def inverse_matrix(matrix: np.ndarray) -> np.ndarray:
    """The inverse of a square matrix."""
    return np.linalg.inv(matrix)


def is_same_transform(matrix0: np.ndarray, matrix1: np.ndarray) -> bool:
    """Whether two 4x4 matrices are the same transform (after normalising the homogeneous scale)."""
    m0 = np.array(matrix0, dtype=float, copy=True)
    m1 = np.array(matrix1, dtype=float, copy=True)
    m0 /= m0[3, 3]
    m1 /= m1[3, 3]
    return bool(np.allclose(m0, m1))


def vector_norm(data: Sequence[float] | np.ndarray, axis: int | None = None) -> float | np.ndarray:
    """The Euclidean norm of a vector, or of each vector along ``axis``."""
    a = np.asarray(data, dtype=float)
    if axis is None:
        return float(math.sqrt(float(np.dot(a.ravel(), a.ravel()))))
    return np.sqrt(np.sum(a * a, axis=axis))


def unit_vector(data: Sequence[float] | np.ndarray, axis: int | None = None) -> np.ndarray:
    """``data`` scaled to unit length (or each vector along ``axis``)."""
    a = np.array(data, dtype=float, copy=True)
    if axis is None:
        n = vector_norm(a)
        return a / n if n else a
    return a / np.expand_dims(np.sqrt(np.sum(a * a, axis=axis)), axis)
