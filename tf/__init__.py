"""tf: tf2's transform buffer, broadcasters and listeners in pure Python, without ROS.

``tf.Buffer`` reproduces tf2's BufferCore (ROS 2 flavour) exception for exception;
``tf.TransformBroadcaster`` keeps the ROS 1 course call
``br.sendTransform((x, y, z), quaternion_from_euler(r, p, y), tf.Time.now(), child, parent)``;
``tf.transformations`` has the ROS helpers. Quaternions are xyzw; times are ``tf.Time``.
"""

from __future__ import annotations

from . import transformations
from ._apply import do_transform
from .broadcaster import StaticTransformBroadcaster, TransformBroadcaster
from .buffer import Buffer
from .exceptions import (
    BackwardExtrapolationException,
    ConnectivityException,
    ExtrapolationException,
    ForwardExtrapolationException,
    InvalidArgumentException,
    LookupException,
    NoDataForExtrapolationException,
    TimeoutException,
    TransformException,
)
from .listener import TransformListener
from .messages import (
    Duration,
    Header,
    JointState,
    Point,
    PointStamped,
    Pose,
    PoseStamped,
    Quaternion,
    TFMessage,
    Time,
    Transform,
    TransformStamped,
    Vector3,
    Vector3Stamped,
)
from .rate import Rate

__all__ = [
    "BackwardExtrapolationException",
    "Buffer",
    "ConnectivityException",
    "Duration",
    "ExtrapolationException",
    "ForwardExtrapolationException",
    "Header",
    "InvalidArgumentException",
    "JointState",
    "LookupException",
    "NoDataForExtrapolationException",
    "Point",
    "PointStamped",
    "Pose",
    "PoseStamped",
    "Quaternion",
    "Rate",
    "StaticTransformBroadcaster",
    "TFMessage",
    "Time",
    "TimeoutException",
    "Transform",
    "TransformBroadcaster",
    "TransformException",
    "TransformListener",
    "TransformStamped",
    "Vector3",
    "Vector3Stamped",
    "do_transform",
    "transformations",
]
