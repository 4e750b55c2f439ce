"""tf2 setTransform's rejection messages (TF_SELF_TRANSFORM, TF_NAN_INPUT, ...), logged on ``tf``."""

from __future__ import annotations

import logging
import math

__all__ = ["reject"]

_TOLERANCE = 10e-3  # QUATERNION_NORMALIZATION_TOLERANCE
_log = logging.getLogger("tf")


def reject(parent: str, child: str, values: tuple[float, ...], authority: str) -> bool:
    """Log every tf2 TF_* reason why ``setTransform`` rejects this transform; returns False."""
    qx, qy, qz, qw, tx, ty, tz = values
    if child == parent:
        _log.error(
            'TF_SELF_TRANSFORM: Ignoring transform from authority "%s" with frame_id and  '
            'child_frame_id "%s" because they are the same',
            authority,
            child,
        )
    if not child:
        _log.error(
            'TF_NO_CHILD_FRAME_ID: Ignoring transform from authority "%s" because child_frame_id not set ',
            authority,
        )
    if not parent:
        _log.error(
            'TF_NO_FRAME_ID: Ignoring transform with child_frame_id "%s"  from authority "%s" '
            "because frame_id not set",
            child,
            authority,
        )
    if any(math.isnan(v) for v in values):
        _log.error(
            'TF_NAN_INPUT: Ignoring transform for child_frame_id "%s" from authority "%s" because'
            " of a nan value in the transform (%f %f %f) (%f %f %f %f)",
            child, authority, tx, ty, tz, qx, qy, qz, qw,
        )  # fmt: skip
    if not abs(qw * qw + qx * qx + qy * qy + qz * qz - 1.0) < _TOLERANCE:
        _log.error(
            'TF_DENORMALIZED_QUATERNION: Ignoring transform for child_frame_id "%s" from authority'
            ' "%s" because of an invalid quaternion in the transform (%f %f %f %f)',
            child, authority, qx, qy, qz, qw,
        )  # fmt: skip
    return False
