"""A small immutable rigid-body pose, ``T_parent_child``, with xyzw quaternions.

Example:
    >>> import numpy as np
    >>> from urdftk.pose import Pose
    >>> T_world_base = Pose.from_translation_quaternion([1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0])
    >>> T_base_tool = Pose.from_translation_quaternion([0.0, 2.0, 0.0], [0.0, 0.0, 0.0, 1.0])
    >>> (T_world_base @ T_base_tool).translation.tolist()
    [1.0, 2.0, 0.0]
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = ["Pose", "matrix_to_quaternion"]


def matrix_to_quaternion(R: np.ndarray) -> np.ndarray:
    """Convert a 3x3 rotation matrix to a unit quaternion, xyzw, with ``w >= 0``.

    Args:
        R: Rotation matrix.

    Returns:
        (4,) quaternion ``[x, y, z, w]``.
    """
    m = np.asarray(R, dtype=float)
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    if tr > 0.0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s]
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s]
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = [(m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = [(m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s, (m[1, 0] - m[0, 1]) / s]
    out = np.array(q)
    out /= np.linalg.norm(out)
    return -out if out[3] < 0 else out


class Pose:
    """An immutable rigid transform ``T_parent_child`` (rotation + translation, SI units).

    The pose owns a private read-only 4x4 array; every accessor returns a fresh copy, so no caller
    can change a pose (or another caller's result) through a returned array.
    """

    __slots__ = ("_m",)

    def __init__(self, matrix: np.ndarray | Sequence[Sequence[float]]):
        """Build from a 4x4 homogeneous matrix (see :meth:`from_matrix`)."""
        m = np.array(matrix, dtype=np.float64)
        if m.shape != (4, 4):
            raise ValueError(f"a pose needs a 4x4 matrix, got shape {m.shape}")
        if not np.all(np.isfinite(m)):
            raise ValueError("a pose matrix must be finite (got NaN or inf)")
        if not np.allclose(m[3], (0.0, 0.0, 0.0, 1.0), atol=1e-9):
            raise ValueError(f"the last row of a pose matrix must be [0, 0, 0, 1], got {m[3].tolist()}")
        R = m[:3, :3]
        if not np.allclose(R @ R.T, np.eye(3), atol=1e-6) or np.linalg.det(R) < 0:
            raise ValueError("the upper-left 3x3 block of a pose matrix must be a rotation")
        m.setflags(write=False)
        object.__setattr__(self, "_m", m)

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("Pose is immutable")

    @classmethod
    def from_matrix(cls, matrix: np.ndarray | Sequence[Sequence[float]]) -> Pose:
        """Build a pose from a 4x4 homogeneous matrix (copied and checked to be a rigid transform)."""
        return cls(matrix)

    @classmethod
    def identity(cls) -> Pose:
        """Return the identity pose (a new object every call)."""
        return cls(np.eye(4))

    @classmethod
    def from_translation_quaternion(cls, translation: Sequence[float], quaternion: Sequence[float]) -> Pose:
        """Build a pose from a translation (metres) and an xyzw quaternion (normalized here).

        Raises:
            ValueError: If the quaternion has zero or non-finite norm.
        """
        q = np.asarray(quaternion, dtype=float).reshape(4)
        n = float(np.linalg.norm(q))
        if not (n > 1e-12 and math.isfinite(n)):
            raise ValueError(f"quaternion {q.tolist()} has zero or non-finite norm")
        x, y, z, w = q / n
        m = np.eye(4)
        m[:3, :3] = [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
        m[:3, 3] = np.asarray(translation, dtype=float).reshape(3)
        return cls(m)

    @property
    def matrix(self) -> np.ndarray:
        """The 4x4 homogeneous matrix (a writable copy)."""
        return self._m.copy()

    @property
    def translation(self) -> np.ndarray:
        """The translation, metres (a copy)."""
        return self._m[:3, 3].copy()

    @property
    def rotation(self) -> np.ndarray:
        """The 3x3 rotation matrix (a copy)."""
        return self._m[:3, :3].copy()

    @property
    def quaternion(self) -> np.ndarray:
        """The rotation as a unit quaternion ``[x, y, z, w]`` with ``w >= 0``."""
        return matrix_to_quaternion(self._m[:3, :3])

    def inverse(self) -> Pose:
        """Return ``T_child_parent``."""
        m = np.eye(4)
        Rt = self._m[:3, :3].T
        m[:3, :3] = Rt
        m[:3, 3] = -Rt @ self._m[:3, 3]
        return Pose(m)

    def __matmul__(self, other: Pose) -> Pose:
        """Compose: ``T_a_b @ T_b_c -> T_a_c``."""
        if not isinstance(other, Pose):
            return NotImplemented
        return Pose(self._m @ other._m)

    def allclose(self, other: Pose, atol: float = 1e-9) -> bool:
        """Tell whether two poses have the same matrix within ``atol``."""
        return bool(np.allclose(self._m, other._m, atol=atol, rtol=0.0))

    def __repr__(self) -> str:
        t = ", ".join(f"{v:.6g}" for v in self._m[:3, 3])
        q = ", ".join(f"{v:.6g}" for v in self.quaternion)
        return f"Pose(translation=[{t}], quaternion_xyzw=[{q}])"
