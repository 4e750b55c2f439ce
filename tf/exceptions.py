"""The tf exception hierarchy, mirroring tf2's.

``TransformException`` is the root of every error the ``tf`` package raises on purpose.
The core works with integer error codes (as tf2's ``buffer_core.cpp`` does) and the API edge
turns a code into one of these classes with :func:`exception_for`.
"""

from __future__ import annotations

__all__ = [
    "BackwardExtrapolationException",
    "ConnectivityException",
    "ExtrapolationException",
    "ForwardExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "NoDataForExtrapolationException",
    "TimeoutException",
    "TransformException",
]


class TransformException(Exception):
    """Root of all tf errors; catch this to handle any failed transform request."""


class LookupException(TransformException):
    """A frame does not exist, or the tree contains a loop."""


class ConnectivityException(TransformException):
    """The two frames exist but are not part of the same tree."""


class ExtrapolationException(TransformException):
    """The requested time is outside the data held for some link of the chain."""


class ForwardExtrapolationException(ExtrapolationException):
    """The requested time is newer than the newest data of a link."""


class BackwardExtrapolationException(ExtrapolationException):
    """The requested time is older than the oldest data of a link."""


class NoDataForExtrapolationException(ExtrapolationException):
    """A link holds no data, or a single sample at another time."""


class InvalidArgumentException(TransformException):
    """A frame name is empty or starts with '/', or an argument has the wrong type."""


class TimeoutException(TransformException):
    """A wait for a transform ran out of time."""
