"""Message types with ROS 2 field names: stamps, transforms, TF and joint-state messages.

Every message is a frozen (immutable) slotted dataclass whose field names are exactly those of
the ROS 2 message it mirrors (``builtin_interfaces/msg/Time``, ``geometry_msgs/msg/TransformStamped``,
``tf2_msgs/msg/TFMessage``, ``sensor_msgs/msg/JointState``...), so that the CDR codec can map them
one to one. Quaternions are xyzw. Constructors are hand-written to stay cheap on hot paths;
``dataclasses.replace``, ``fields``, ``asdict``, equality and hashing work as usual.
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

__all__ = [
    "Duration",
    "Header",
    "JointState",
    "Point",
    "PointStamped",
    "Pose",
    "PoseStamped",
    "Quaternion",
    "TFMessage",
    "Time",
    "Transform",
    "TransformStamped",
    "Vector3",
    "Vector3Stamped",
]

_NS = 1_000_000_000


def _setters(cls: type, *names: str) -> tuple[Any, ...]:
    """Slot setters of a frozen slotted dataclass (used only by the hand-written constructors)."""
    return tuple(cls.__dict__[name].__set__ for name in names)


def _split_ns(total: int) -> tuple[int, int]:
    sec, nanosec = divmod(total, _NS)
    return sec, nanosec


def _to_ns(sec: Any, nanosec: Any) -> int:
    """Total nanoseconds from ``sec`` (int or float seconds) and ``nanosec`` (int)."""
    if isinstance(sec, float):
        if not math.isfinite(sec):
            raise ValueError(f"time value must be finite, got {sec!r}")
        return round(sec * _NS) + int(nanosec)
    return int(sec) * _NS + int(nanosec)


@dataclass(frozen=True, slots=True, order=True, init=False)
class Duration:
    """A signed span of time, ``sec`` seconds plus ``nanosec`` (0 <= nanosec < 1e9) nanoseconds.

    ``Duration(10)`` is ten seconds, ``Duration.from_sec(0.25)`` a quarter of a second.
    Float seconds given as ``sec`` are rounded to the nearest nanosecond.
    """

    sec: int
    nanosec: int

    def __init__(self, sec: int | float = 0, nanosec: int = 0) -> None:
        if sec.__class__ is not int or nanosec.__class__ is not int or not 0 <= nanosec < _NS:
            sec, nanosec = _split_ns(_to_ns(sec, nanosec))
        _D_SEC(self, sec)
        _D_NSEC(self, nanosec)

    @classmethod
    def from_sec(cls, seconds: float) -> Duration:
        """A duration of ``seconds`` (float), rounded to the nearest nanosecond."""
        return cls(*_split_ns(_to_ns(float(seconds), 0)))

    @classmethod
    def from_nsec(cls, nanoseconds: int) -> Duration:
        """A duration of an integer number of nanoseconds."""
        return cls(*_split_ns(int(nanoseconds)))

    @property
    def nanoseconds(self) -> int:
        """The duration as an integer number of nanoseconds."""
        return self.sec * _NS + self.nanosec

    def to_sec(self) -> float:
        """The duration in float seconds."""
        return self.sec + self.nanosec * 1e-9

    def __add__(self, other: object) -> Duration:
        if isinstance(other, Duration):
            return Duration.from_nsec(self.nanoseconds + other.nanoseconds)
        return NotImplemented

    def __sub__(self, other: object) -> Duration:
        if isinstance(other, Duration):
            return Duration.from_nsec(self.nanoseconds - other.nanoseconds)
        return NotImplemented

    def __neg__(self) -> Duration:
        return Duration.from_nsec(-self.nanoseconds)

    def __bool__(self) -> bool:
        return bool(self.sec or self.nanosec)


(_D_SEC, _D_NSEC) = _setters(Duration, "sec", "nanosec")


@dataclass(frozen=True, slots=True, order=True, init=False)
class Time:
    """A point in time: ``sec`` seconds plus ``nanosec`` nanoseconds since the epoch.

    ``Time()`` (zero) means "the latest available" in buffer lookups, as in tf2.
    """

    sec: int
    nanosec: int

    def __init__(self, sec: int | float = 0, nanosec: int = 0) -> None:
        if sec.__class__ is not int or nanosec.__class__ is not int or not 0 <= nanosec < _NS:
            sec, nanosec = _split_ns(_to_ns(sec, nanosec))
        if sec < 0:
            raise ValueError(f"Time cannot be negative (sec={sec}, nanosec={nanosec})")
        _T_SEC(self, sec)
        _T_NSEC(self, nanosec)

    @classmethod
    def now(cls) -> Time:
        """The current wall-clock time."""
        return cls(*_split_ns(_time.time_ns()))

    @classmethod
    def from_sec(cls, seconds: float) -> Time:
        """A time from float seconds, rounded to the nearest nanosecond."""
        return cls(*_split_ns(_to_ns(float(seconds), 0)))

    @classmethod
    def from_nsec(cls, nanoseconds: int) -> Time:
        """A time from an integer number of nanoseconds."""
        return cls(*_split_ns(int(nanoseconds)))

    @property
    def nanoseconds(self) -> int:
        """The time as an integer number of nanoseconds."""
        return self.sec * _NS + self.nanosec

    def to_sec(self) -> float:
        """The time in float seconds."""
        return self.sec + self.nanosec * 1e-9

    def is_zero(self) -> bool:
        """Whether this is time zero ("latest available" in lookups)."""
        return not (self.sec or self.nanosec)

    def __add__(self, other: object) -> Time:
        if isinstance(other, Duration):
            return Time.from_nsec(self.nanoseconds + other.nanoseconds)
        return NotImplemented

    __radd__ = __add__

    def __sub__(self, other: object) -> Any:
        if isinstance(other, Time):
            return Duration.from_nsec(self.nanoseconds - other.nanoseconds)
        if isinstance(other, Duration):
            return Time.from_nsec(self.nanoseconds - other.nanoseconds)
        return NotImplemented


(_T_SEC, _T_NSEC) = _setters(Time, "sec", "nanosec")
_TIME_ZERO = Time()


@dataclass(frozen=True, slots=True, init=False)
class Vector3:
    """A 3D vector (metres, or whatever the field it sits in says)."""

    x: float
    y: float
    z: float

    def __init__(self, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> None:
        _V_X(self, x)
        _V_Y(self, y)
        _V_Z(self, z)


(_V_X, _V_Y, _V_Z) = _setters(Vector3, "x", "y", "z")


@dataclass(frozen=True, slots=True, init=False)
class Point:
    """A position in 3D space (metres)."""

    x: float
    y: float
    z: float

    def __init__(self, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> None:
        _P_X(self, x)
        _P_Y(self, y)
        _P_Z(self, z)


(_P_X, _P_Y, _P_Z) = _setters(Point, "x", "y", "z")


@dataclass(frozen=True, slots=True, init=False)
class Quaternion:
    """A rotation as a unit quaternion, xyzw order; the default is the identity."""

    x: float
    y: float
    z: float
    w: float

    def __init__(self, x: float = 0.0, y: float = 0.0, z: float = 0.0, w: float = 1.0) -> None:
        _Q_X(self, x)
        _Q_Y(self, y)
        _Q_Z(self, z)
        _Q_W(self, w)


(_Q_X, _Q_Y, _Q_Z, _Q_W) = _setters(Quaternion, "x", "y", "z", "w")
_V_ZERO = Vector3()
_P_ZERO = Point()
_Q_IDENTITY = Quaternion()


@dataclass(frozen=True, slots=True, init=False)
class Transform:
    """A rigid transform: ``translation`` then ``rotation`` (maps child coordinates to parent)."""

    translation: Vector3
    rotation: Quaternion

    def __init__(self, translation: Vector3 | None = None, rotation: Quaternion | None = None) -> None:
        _TR_T(self, _V_ZERO if translation is None else translation)
        _TR_R(self, _Q_IDENTITY if rotation is None else rotation)


(_TR_T, _TR_R) = _setters(Transform, "translation", "rotation")
_TR_IDENTITY = Transform()


@dataclass(frozen=True, slots=True, init=False)
class Pose:
    """A position and an orientation."""

    position: Point
    orientation: Quaternion

    def __init__(self, position: Point | None = None, orientation: Quaternion | None = None) -> None:
        _PO_P(self, _P_ZERO if position is None else position)
        _PO_O(self, _Q_IDENTITY if orientation is None else orientation)


(_PO_P, _PO_O) = _setters(Pose, "position", "orientation")


@dataclass(frozen=True, slots=True, init=False)
class Header:
    """A stamp and the frame the data is expressed in."""

    stamp: Time
    frame_id: str

    def __init__(self, stamp: Time | None = None, frame_id: str = "") -> None:
        _H_S(self, _TIME_ZERO if stamp is None else stamp)
        _H_F(self, frame_id)


(_H_S, _H_F) = _setters(Header, "stamp", "frame_id")
_HEADER_EMPTY = Header()


@dataclass(frozen=True, slots=True, init=False)
class TransformStamped:
    """The pose of ``child_frame_id`` in ``header.frame_id`` at ``header.stamp``."""

    header: Header
    child_frame_id: str
    transform: Transform

    def __init__(
        self, header: Header | None = None, child_frame_id: str = "", transform: Transform | None = None
    ) -> None:
        _TS_H(self, _HEADER_EMPTY if header is None else header)
        _TS_C(self, child_frame_id)
        _TS_T(self, _TR_IDENTITY if transform is None else transform)


(_TS_H, _TS_C, _TS_T) = _setters(TransformStamped, "header", "child_frame_id", "transform")


@dataclass(frozen=True, slots=True, init=False)
class PointStamped:
    """A point with a header."""

    header: Header
    point: Point

    def __init__(self, header: Header | None = None, point: Point | None = None) -> None:
        _PS_H(self, _HEADER_EMPTY if header is None else header)
        _PS_P(self, _P_ZERO if point is None else point)


(_PS_H, _PS_P) = _setters(PointStamped, "header", "point")


@dataclass(frozen=True, slots=True, init=False)
class Vector3Stamped:
    """A direction with a header (transforms rotate it, never translate it)."""

    header: Header
    vector: Vector3

    def __init__(self, header: Header | None = None, vector: Vector3 | None = None) -> None:
        _VS_H(self, _HEADER_EMPTY if header is None else header)
        _VS_V(self, _V_ZERO if vector is None else vector)


(_VS_H, _VS_V) = _setters(Vector3Stamped, "header", "vector")


@dataclass(frozen=True, slots=True, init=False)
class PoseStamped:
    """A pose with a header."""

    header: Header
    pose: Pose

    def __init__(self, header: Header | None = None, pose: Pose | None = None) -> None:
        _PSS_H(self, _HEADER_EMPTY if header is None else header)
        _PSS_P(self, Pose() if pose is None else pose)


(_PSS_H, _PSS_P) = _setters(PoseStamped, "header", "pose")


@dataclass(frozen=True, slots=True, init=False)
class TFMessage:
    """A batch of transforms, as sent on ``/tf`` and ``/tf_static`` (``tf2_msgs/msg/TFMessage``)."""

    transforms: tuple[TransformStamped, ...]

    def __init__(self, transforms: Iterable[TransformStamped] = ()) -> None:
        _TF_T(self, transforms if transforms.__class__ is tuple else tuple(transforms))


(_TF_T,) = _setters(TFMessage, "transforms")


def _floats(values: Iterable[float]) -> tuple[float, ...]:
    return tuple(map(float, values))


@dataclass(frozen=True, slots=True, init=False)
class JointState:
    """Joint positions, velocities and efforts by name (``sensor_msgs/msg/JointState``).

    ``velocity`` and ``effort`` may be empty; otherwise each has one entry per name.
    """

    header: Header
    name: tuple[str, ...]
    position: tuple[float, ...]
    velocity: tuple[float, ...]
    effort: tuple[float, ...]

    def __init__(
        self,
        header: Header | None = None,
        name: Iterable[str] = (),
        position: Iterable[float] = (),
        velocity: Iterable[float] = (),
        effort: Iterable[float] = (),
    ) -> None:
        _JS_H(self, _HEADER_EMPTY if header is None else header)
        _JS_N(self, tuple(map(str, name)))
        _JS_P(self, _floats(position))
        _JS_V(self, _floats(velocity))
        _JS_E(self, _floats(effort))


(_JS_H, _JS_N, _JS_P, _JS_V, _JS_E) = _setters(JointState, "header", "name", "position", "velocity", "effort")


def _transform_stamped(
    stamp: Time,
    frame_id: str,
    child_frame_id: str,
    tx: float,
    ty: float,
    tz: float,
    qx: float,
    qy: float,
    qz: float,
    qw: float,
    _new: Any = object.__new__,
) -> TransformStamped:
    """Build a TransformStamped without five constructor calls (the buffer's lookup hot path)."""
    v = _new(Vector3)
    _V_X(v, tx)
    _V_Y(v, ty)
    _V_Z(v, tz)
    q = _new(Quaternion)
    _Q_X(q, qx)
    _Q_Y(q, qy)
    _Q_Z(q, qz)
    _Q_W(q, qw)
    tr = _new(Transform)
    _TR_T(tr, v)
    _TR_R(tr, q)
    h = _new(Header)
    _H_S(h, stamp)
    _H_F(h, frame_id)
    ts = _new(TransformStamped)
    _TS_H(ts, h)
    _TS_C(ts, child_frame_id)
    _TS_T(ts, tr)
    return ts
