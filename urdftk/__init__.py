"""urdftk: robot descriptions, kinematics and frames without ROS.

The top-level import stays light: heavy modules (Pinocchio, yourdfpy) load on first use.

Example:
    >>> import urdftk
    >>> robot = urdftk.load("examples/robots/robot0_description/urdf/robot0.urdf")  # doctest: +SKIP
    >>> robot.frame_pose("end_effector", robot.neutral())  # doctest: +SKIP
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from urdftk.errors import (
    DescriptionError,
    JointNotFound,
    LinkNotFound,
    PackageNotFound,
    ResourceError,
    UrdftkError,
    XacroError,
)

if TYPE_CHECKING:
    from urdftk.loading import load
    from urdftk.model import Robot

__version__ = "0.1.0"

__all__ = [
    "DescriptionError",
    "JointNotFound",
    "LinkNotFound",
    "PackageNotFound",
    "ResourceError",
    "Robot",
    "UrdftkError",
    "XacroError",
    "__version__",
    "load",
]


def __getattr__(name: str) -> Any:
    if name == "load":
        from urdftk.loading import load

        return load
    if name == "Robot":
        from urdftk.model import Robot

        return Robot
    raise AttributeError(f"module 'urdftk' has no attribute {name!r}")
