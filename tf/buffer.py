"""``tf.Buffer``: tf2's BufferCore with ROS 2's Python API, waiting and timeouts.

The store itself is ``tf._core.BufferCore`` (clock-free, lock-protected). This layer converts
messages, raises typed exceptions, and waits for transforms with tf2's transformable requests
(a ``threading.Event`` per wait, set from the inserting thread: no polling).
"""

from __future__ import annotations

import asyncio
import contextlib
import threading
import time as _time
from collections.abc import Sequence

import numpy as np

from . import _core
from ._apply import Stamped, do_transform
from .exceptions import (
    BackwardExtrapolationException,
    ConnectivityException,
    ForwardExtrapolationException,
    InvalidArgumentException,
    LookupException,
    NoDataForExtrapolationException,
    TimeoutException,
    TransformException,
)
from .messages import Duration, Time, TransformStamped, _transform_stamped

__all__ = [
    "DEFAULT_AUTHORITY",
    "DEFAULT_CACHE_TIME",
    "Buffer",
]

DEFAULT_CACHE_TIME = Duration(10)
DEFAULT_AUTHORITY = "default_authority"
_NS = 1_000_000_000
_TIME_ZERO = Time()

_EXCEPTIONS: dict[int, type[TransformException]] = {
    _core.LOOKUP: LookupException,
    _core.CONNECTIVITY: ConnectivityException,
    _core.FORWARD_EXTRAPOLATION: ForwardExtrapolationException,
    _core.BACKWARD_EXTRAPOLATION: BackwardExtrapolationException,
    _core.NO_DATA_FOR_EXTRAPOLATION: NoDataForExtrapolationException,
    _core.INVALID_ARGUMENT: InvalidArgumentException,
}


def _time_ns(time: Time) -> int:
    try:
        return time.sec * _NS + time.nanosec
    except AttributeError:
        raise InvalidArgumentException(f"time must be a tf.Time, got {type(time).__name__}") from None


def _seconds(value: Duration | float | None, what: str) -> float:
    """Seconds from a Duration or float seconds (None -> 0)."""
    if value is None:
        return 0.0
    if isinstance(value, Duration):
        return value.to_sec()
    if isinstance(value, (int, float)):
        return float(value)
    raise InvalidArgumentException(
        f"{what} must be a tf.Duration or float seconds, got {type(value).__name__}"
    )


def _message(target: str, source: str, r: tuple, query: Time, query_ns: int) -> TransformStamped:
    stamp = query if r[0] == query_ns else Time(*divmod(r[0], _NS))
    return _transform_stamped(stamp, target, source, r[5], r[6], r[7], r[1], r[2], r[3], r[4])


def _bad_name(name: str) -> bool:
    return not name or name[0] == "/"


class Buffer:
    """A tf2 transform buffer: store stamped transforms, look them up between any two frames.

    Args:
        cache_time: how long dynamic transforms are kept (tf.Duration or float seconds; default 10 s).

    Thread-safe: listeners may write while other threads read. ``Time()`` (zero) asks for the latest
    time every link of the chain has in common.
    """

    def __init__(self, cache_time: Duration | float = DEFAULT_CACHE_TIME) -> None:
        seconds = _seconds(cache_time, "cache_time")
        if not seconds > 0:
            raise InvalidArgumentException(f"cache_time must be positive, got {cache_time!r}")
        self._cache_time = Duration.from_sec(seconds) if not isinstance(cache_time, Duration) else cache_time
        self._core = _core.BufferCore(self._cache_time.nanoseconds)

    @property
    def cache_time(self) -> Duration:
        """How long dynamic transforms are kept."""
        return self._cache_time

    # ------------------------------------------------------------------ writing
    def set_transform(self, transform: TransformStamped, authority: str = DEFAULT_AUTHORITY) -> bool:
        """Store a dynamic transform; False if tf2 rejects it (self, empty name, NaN, bad quaternion, old).

        Rejections are logged on the ``tf`` logger with tf2's TF_* texts.
        """
        h = transform.header
        st = h.stamp
        tr = transform.transform
        v = tr.translation
        q = tr.rotation
        return self._core.insert(
            h.frame_id,
            transform.child_frame_id,
            st.sec * _NS + st.nanosec,
            (q.x, q.y, q.z, q.w, v.x, v.y, v.z),
            authority,
            False,
        )

    def set_transform_static(self, transform: TransformStamped, authority: str = DEFAULT_AUTHORITY) -> bool:
        """Store a static transform: valid at every time, overwritten by a later static one."""
        h = transform.header
        tr = transform.transform
        v = tr.translation
        q = tr.rotation
        return self._core.insert(
            h.frame_id,
            transform.child_frame_id,
            h.stamp.sec * _NS + h.stamp.nanosec,
            (q.x, q.y, q.z, q.w, v.x, v.y, v.z),
            authority,
            True,
        )

    def clear(self) -> None:
        """Drop all dynamic data; static transforms and frame names stay."""
        self._core.clear()

    # ------------------------------------------------------------------ lookups
    def lookup_transform(
        self,
        target_frame: str,
        source_frame: str,
        time: Time = _TIME_ZERO,
        timeout: Duration | float | None = None,
    ) -> TransformStamped:
        """The transform taking data from ``source_frame`` to ``target_frame`` at ``time``.

        ``result.transform`` is the pose of ``source_frame`` in ``target_frame``. With a timeout,
        first waits (without polling) until the transform is available or the timeout passes.

        Raises:
            LookupException: a frame is unknown (the message lists the known ones).
            ConnectivityException: the frames are in different trees.
            ExtrapolationException: ``time`` is outside the data of some link.
            InvalidArgumentException: a frame name is empty or starts with '/'.
        """
        t = _time_ns(time)
        if timeout is not None:
            self._wait(target_frame, source_frame, t, _seconds(timeout, "timeout"))
        code, r = self._core.lookup(target_frame, source_frame, t)
        if code:
            raise _EXCEPTIONS[code](r)
        return _message(target_frame, source_frame, r, time, t)

    def lookup_transform_full(
        self,
        target_frame: str,
        target_time: Time,
        source_frame: str,
        source_time: Time,
        fixed_frame: str,
        timeout: Duration | float | None = None,
    ) -> TransformStamped:
        """Source at ``source_time`` to target at ``target_time``, through ``fixed_frame`` (time travel).

        The stamp is the target-side one. Raises as :meth:`lookup_transform`.
        """
        tt = _time_ns(target_time)
        ts = _time_ns(source_time)
        if timeout is not None:
            self._wait_full(target_frame, tt, source_frame, ts, fixed_frame, timeout)
        code, r = self._core.lookup_full(target_frame, tt, source_frame, ts, fixed_frame)
        if code:
            raise _EXCEPTIONS[code](r)
        return _message(target_frame, source_frame, r, target_time, tt)

    def lookup_transforms(
        self,
        target_frame: str,
        source_frames: Sequence[str],
        time: Time = _TIME_ZERO,
        *,
        fill_missing: bool = False,
    ) -> np.ndarray:
        """Batched lookups: an (n, 4, 4) array, entry i = ``T_target_source[i]`` (homogeneous matrix).

        Each entry equals ``lookup_transform(target_frame, source_frames[i], time)`` as a matrix.
        With ``fill_missing`` a failing entry is filled with NaN instead of raising.

        Raises:
            TransformException: the first failure, unless ``fill_missing``.
        """
        t = _time_ns(time)
        results = self._core.lookup_many(target_frame, list(source_frames), t)
        n = len(results)
        raw = np.full((n, 7), np.nan)
        for i, (code, r) in enumerate(results):
            if code:
                if not fill_missing:
                    raise _EXCEPTIONS[code](r)
            else:
                raw[i] = r[1:]
        return _matrices(raw)

    def can_transform(
        self,
        target_frame: str,
        source_frame: str,
        time: Time = _TIME_ZERO,
        timeout: Duration | float | None = None,
    ) -> bool:
        """Whether ``lookup_transform`` would succeed (after waiting up to ``timeout``); never raises."""
        try:
            t = _time_ns(time)
            if timeout is not None:
                self._wait(target_frame, source_frame, t, _seconds(timeout, "timeout"))
        except TransformException:
            return False
        return not self._core.can_transform_reason(target_frame, source_frame, t)

    def can_transform_full(
        self,
        target_frame: str,
        target_time: Time,
        source_frame: str,
        source_time: Time,
        fixed_frame: str,
        timeout: Duration | float | None = None,
    ) -> bool:
        """Whether ``lookup_transform_full`` would succeed (after waiting up to ``timeout``); never raises."""
        try:
            tt = _time_ns(target_time)
            ts = _time_ns(source_time)
            if timeout is not None:
                self._wait_full(target_frame, tt, source_frame, ts, fixed_frame, timeout)
        except TransformException:
            return False
        return not self._core.can_transform_full_reason(target_frame, tt, source_frame, ts, fixed_frame)

    def why_not(self, target_frame: str, source_frame: str, time: Time = _TIME_ZERO) -> str:
        """Why ``lookup_transform`` would fail now (tf2's canTransform message), "" if it would not."""
        return self._core.can_transform_reason(target_frame, source_frame, _time_ns(time))

    def get_latest_common_time(self, target_frame: str, source_frame: str) -> Time:
        """The latest time at which every link between the two frames has data (Time() if all static)."""
        code, r = self._core.latest_common_time(target_frame, source_frame)
        if code:
            raise _EXCEPTIONS[code](r)
        return Time(*divmod(r, _NS))

    def transform(
        self,
        obj: Stamped,
        target_frame: str,
        timeout: Duration | float | None = None,
    ) -> Stamped:
        """``obj`` (Point/Pose/Vector3/TransformStamped) expressed in ``target_frame``.

        Uses the transform at ``obj.header.stamp`` (zero = latest). Raises as :meth:`lookup_transform`.
        """
        h = obj.header
        return do_transform(obj, self.lookup_transform(target_frame, h.frame_id, h.stamp, timeout))

    # ------------------------------------------------------------------ waiting
    def _wait_full(
        self, target: str, tt: int, source: str, ts: int, fixed: str, timeout: Duration | float
    ) -> None:
        """Wait for both legs of a time-travel lookup (target<-fixed at tt, fixed<-source at ts)."""
        deadline = _time.monotonic() + _seconds(timeout, "timeout")
        self._wait(target, fixed, tt, deadline - _time.monotonic())
        self._wait(fixed, source, ts, deadline - _time.monotonic())

    def wait_for_transform(
        self, target_frame: str, source_frame: str, time: Time = _TIME_ZERO, timeout: Duration | float = 1.0
    ) -> None:
        """Block until the transform is available.

        Raises:
            TimeoutException: not available within ``timeout`` (the message says why).
            TransformException: it can never become available (``time`` is older than the cache keeps).
        """
        t = _time_ns(time)
        if not self._wait(target_frame, source_frame, t, _seconds(timeout, "timeout")):
            reason = self._core.can_transform_reason(target_frame, source_frame, t)
            if reason:
                raise TimeoutException(
                    f"Timed out after {_seconds(timeout, 'timeout'):.3f} s waiting for the transform from "
                    f"[{source_frame}] to [{target_frame}]: {reason}"
                )

    async def wait_for_transform_async(
        self,
        target_frame: str,
        source_frame: str,
        time: Time = _TIME_ZERO,
        timeout: Duration | float | None = None,
    ) -> None:
        """Await until the transform is available (asyncio-friendly, no thread blocked).

        Raises:
            TimeoutException: not available within ``timeout`` (None = wait forever).
            TransformException: it can never become available.
        """
        t = _time_ns(time)
        loop = asyncio.get_running_loop()
        fut: asyncio.Future[bool] = loop.create_future()

        def _resolve(available: bool) -> None:
            if not fut.done():
                fut.set_result(available)

        def _callback(_handle: int, _target: str, _source: str, _t: int, available: bool) -> None:
            with contextlib.suppress(RuntimeError):  # a closed loop: nobody is waiting any more
                loop.call_soon_threadsafe(_resolve, available)

        handle = self._core.add_transformable_request(_callback, target_frame, source_frame, t)
        if handle == 0:
            return
        if handle == _core.NEVER_TRANSFORMABLE:
            self._raise_current(target_frame, source_frame, t)
        try:
            seconds = None if timeout is None else _seconds(timeout, "timeout")
            available = await asyncio.wait_for(fut, seconds)
        except asyncio.TimeoutError:
            raise TimeoutException(
                f"Timed out waiting for the transform from [{source_frame}] to [{target_frame}]: "
                + self._core.can_transform_reason(target_frame, source_frame, t)
            ) from None
        finally:
            self._core.cancel_transformable_request(handle)
        if not available:
            self._raise_current(target_frame, source_frame, t)

    async def lookup_transform_async(
        self,
        target_frame: str,
        source_frame: str,
        time: Time = _TIME_ZERO,
        timeout: Duration | float | None = None,
    ) -> TransformStamped:
        """Await the transform, then return it (see :meth:`wait_for_transform_async`)."""
        await self.wait_for_transform_async(target_frame, source_frame, time, timeout)
        return self.lookup_transform(target_frame, source_frame, time)

    def _raise_current(self, target: str, source: str, t: int) -> None:
        code, r = self._core.lookup(target, source, t)
        raise _EXCEPTIONS.get(code, TransformException)(
            r if code else f"transform from [{source}] to [{target}] can no longer become available"
        )

    def _wait(self, target: str, source: str, t: int, seconds: float) -> bool:
        """Wait up to ``seconds`` until transformable; True if it is. Invalid names do not wait."""
        if seconds <= 0 or _bad_name(target) or _bad_name(source):
            return not self._core.can_transform_reason(target, source, t)
        event = threading.Event()
        outcome: list[bool] = []

        def _callback(_handle: int, _target: str, _source: str, _t: int, available: bool) -> None:
            outcome.append(available)
            event.set()

        handle = self._core.add_transformable_request(_callback, target, source, t)
        if handle == 0:
            return True
        if handle == _core.NEVER_TRANSFORMABLE:
            return False
        try:
            event.wait(seconds)
        finally:
            self._core.cancel_transformable_request(handle)
        return bool(outcome and outcome[0])

    # ------------------------------------------------------------------ introspection
    def frames(self) -> list[str]:
        """Every frame name known (children and parents), in first-seen order."""
        return self._core.frame_names()

    def frame_exists(self, frame: str) -> bool:
        """Whether ``frame`` is known."""
        return self._core.frame_exists(frame)

    def get_parent(self, frame: str, time: Time = _TIME_ZERO) -> str | None:
        """The parent of ``frame`` at ``time`` (zero = latest), or None (root, unknown, or no data)."""
        return self._core.parent_of(frame, _time_ns(time))

    def all_frames_as_string(self) -> str:
        """tf2's "Frame C exists with parent P." listing."""
        return self._core.all_frames_as_string()

    def all_frames_as_yaml(self, current_time: Time | None = None) -> str:
        """tf2's (ROS 2) YAML view: parent, broadcaster, rate, stamps and buffer length per frame."""
        return self._core.all_frames_as_yaml(0 if current_time is None else _time_ns(current_time))

    def all_frames_as_dot(self, current_time: Time | None = None) -> str:
        """The tree as a graphviz digraph (tf2's view_frames input)."""
        return self._core.all_frames_as_dot(0 if current_time is None else _time_ns(current_time))


def _matrices(raw: np.ndarray) -> np.ndarray:
    """(n, 7) [qx qy qz qw tx ty tz] (any norm) -> (n, 4, 4) homogeneous matrices (NaN rows stay NaN)."""
    x, y, z, w = raw[:, 0], raw[:, 1], raw[:, 2], raw[:, 3]
    s = 2.0 / (x * x + y * y + z * z + w * w)
    out = np.zeros((raw.shape[0], 4, 4))
    out[:, 0, 0] = 1.0 - (y * y + z * z) * s
    out[:, 0, 1] = (x * y - w * z) * s
    out[:, 0, 2] = (x * z + w * y) * s
    out[:, 1, 0] = (x * y + w * z) * s
    out[:, 1, 1] = 1.0 - (x * x + z * z) * s
    out[:, 1, 2] = (y * z - w * x) * s
    out[:, 2, 0] = (x * z - w * y) * s
    out[:, 2, 1] = (y * z + w * x) * s
    out[:, 2, 2] = 1.0 - (x * x + y * y) * s
    out[:, :3, 3] = raw[:, 4:]
    out[:, 3, 3] = 1.0
    out[np.isnan(raw[:, 0])] = np.nan
    return out
