"""Fast construction of received messages (the CDR decoder's hot path).

Building a ``TransformStamped`` through its public constructors costs five Python-level
``__init__`` calls and fourteen frozen-slot setter calls. Here each object is filled as an instance
of a *twin*: a plain class with exactly the same ``__slots__`` (so plain, fast slot stores), then
re-typed to the public class with ``__class__`` assignment, which CPython allows between classes of
identical layout. The results are ordinary instances of :mod:`tf.messages` classes: equal to,
hashing like and as immutable as constructed ones. No validation is done: the caller (the decoder)
has checked the values.
"""

from __future__ import annotations

from collections.abc import Iterable

from ..messages import Header, Quaternion, Time, Transform, TransformStamped, Vector3

__all__ = ["transform_stampeds"]


def _twin(cls: type) -> type:
    """A plain class with exactly ``cls``'s slots, whose instances can be re-typed to ``cls``."""
    return type(f"_Raw{cls.__name__}", (), {"__slots__": cls.__slots__, "__module__": __name__})


_RAW_V, _RAW_Q, _RAW_TR, _RAW_H, _RAW_TS = map(
    _twin, (Vector3, Quaternion, Transform, Header, TransformStamped)
)


def transform_stampeds(
    stamps: Iterable[Time],
    frame_ids: Iterable[str],
    child_frame_ids: Iterable[str],
    tx: Iterable[float],
    ty: Iterable[float],
    tz: Iterable[float],
    qx: Iterable[float],
    qy: Iterable[float],
    qz: Iterable[float],
    qw: Iterable[float],
) -> tuple[TransformStamped, ...]:
    """Build TransformStamped messages from parallel sequences of their fields (no validation).

    Returns:
        One ``TransformStamped`` per position, equal to
        ``TransformStamped(Header(stamp, frame_id), child, Transform(Vector3(x, y, z), Quaternion(...)))``.
    """
    out = []
    append = out.append
    V, Q, TR, H, TS = Vector3, Quaternion, Transform, Header, TransformStamped
    RV, RQ, RTR, RH, RTS = _RAW_V, _RAW_Q, _RAW_TR, _RAW_H, _RAW_TS
    for stamp, frame_id, child, x, y, z, rx, ry, rz, rw in zip(
        stamps, frame_ids, child_frame_ids, tx, ty, tz, qx, qy, qz, qw, strict=False
    ):
        v = RV()
        v.x = x
        v.y = y
        v.z = z
        v.__class__ = V
        q = RQ()
        q.x = rx
        q.y = ry
        q.z = rz
        q.w = rw
        q.__class__ = Q
        tr = RTR()
        tr.translation = v
        tr.rotation = q
        tr.__class__ = TR
        h = RH()
        h.stamp = stamp
        h.frame_id = frame_id
        h.__class__ = H
        ts = RTS()
        ts.header = h
        ts.child_frame_id = child
        ts.transform = tr
        ts.__class__ = TS
        append(ts)
    return tuple(out)
