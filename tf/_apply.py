"""Applying a looked-up transform to stamped geometry (tf2_geometry_msgs' do_transform_*)."""

from __future__ import annotations

from typing import TypeVar

from ._math import quat_multiply, quat_rotate
from .exceptions import InvalidArgumentException
from .messages import (
    Header,
    Point,
    PointStamped,
    Pose,
    PoseStamped,
    Quaternion,
    Transform,
    TransformStamped,
    Vector3,
    Vector3Stamped,
)

__all__ = ["Stamped", "do_transform"]

Stamped = TypeVar("Stamped", PointStamped, PoseStamped, Vector3Stamped, TransformStamped)


def do_transform(obj: Stamped, transform: TransformStamped) -> Stamped:
    """Express ``obj`` (given in ``transform.child_frame_id``) in ``transform.header.frame_id``.

    Supports PointStamped, PoseStamped, Vector3Stamped (rotated only) and TransformStamped
    (composed: the result keeps ``obj.child_frame_id``). The result carries ``transform.header``.

    Raises:
        InvalidArgumentException: for any other type.
    """
    tr = transform.transform
    q = tr.rotation
    t = tr.translation
    qx, qy, qz, qw = q.x, q.y, q.z, q.w
    header: Header = transform.header
    if isinstance(obj, PointStamped):
        p = obj.point
        x, y, z = quat_rotate(qx, qy, qz, qw, p.x, p.y, p.z)
        return PointStamped(header, Point(x + t.x, y + t.y, z + t.z))
    if isinstance(obj, Vector3Stamped):
        v = obj.vector
        return Vector3Stamped(header, Vector3(*quat_rotate(qx, qy, qz, qw, v.x, v.y, v.z)))
    if isinstance(obj, PoseStamped):
        p = obj.pose.position
        o = obj.pose.orientation
        x, y, z = quat_rotate(qx, qy, qz, qw, p.x, p.y, p.z)
        rot = quat_multiply(qx, qy, qz, qw, o.x, o.y, o.z, o.w)
        return PoseStamped(header, Pose(Point(x + t.x, y + t.y, z + t.z), Quaternion(*rot)))
    if isinstance(obj, TransformStamped):
        p = obj.transform.translation
        o = obj.transform.rotation
        x, y, z = quat_rotate(qx, qy, qz, qw, p.x, p.y, p.z)
        rot = quat_multiply(qx, qy, qz, qw, o.x, o.y, o.z, o.w)
        return TransformStamped(
            header, obj.child_frame_id, Transform(Vector3(x + t.x, y + t.y, z + t.z), Quaternion(*rot))
        )
    raise InvalidArgumentException(
        f"cannot transform a {type(obj).__name__}; expected PointStamped, PoseStamped, Vector3Stamped "
        "or TransformStamped"
    )
