"""urdftk: robot descriptions, kinematics and frames without ROS.

The top-level import stays light: heavy modules (Pinocchio, yourdfpy) load on first use.

Example:
    >>> import urdftk
    >>> robot = urdftk.load("examples/robots/robot0_description/urdf/robot0.urdf")  # doctest: +SKIP
    >>> robot.frame_pose("end_effector", robot.neutral())  # doctest: +SKIP
"""

from __future__ import annotations

from urdftk.errors import (
    ConfigurationError,
    DescriptionError,
    JointNotFound,
    KinematicsError,
    LinkNotFound,
    MimicWarning,
    PackageNotFound,
    ResourceError,
    UrdftkError,
    XacroError,
)

TYPE_CHECKING = False  # as typing.TYPE_CHECKING, without importing typing at start-up
if TYPE_CHECKING:
    from urdftk.loading import load
    from urdftk.model import Robot

__version__ = "0.1.0"

__all__ = [
    "ConfigurationError",
    "DescriptionError",
    "JointNotFound",
    "KinematicsError",
    "LinkNotFound",
    "MimicWarning",
    "PackageNotFound",
    "ResourceError",
    "Robot",
    "UrdftkError",
    "XacroError",
    "__version__",
    "load",
]


def __getattr__(name: str) -> object:
    if name == "load":
        from urdftk.loading import load

        return load
    if name == "Robot":
        from urdftk.model import Robot

        return Robot
    raise AttributeError(f"module 'urdftk' has no attribute {name!r}")
