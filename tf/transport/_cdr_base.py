"""CDR primitives shared by the message codecs of :mod:`tf.transport._cdr`: errors, alignment, strings."""

from __future__ import annotations

import struct
from typing import Any

from ..messages import Time

__all__ = [
    "CDR_HEADER",
    "CdrError",
    "check_end",
    "check_header",
    "make_time",
    "padding",
    "read_string",
    "remember",
    "utf8",
]

CDR_HEADER = b"\x00\x01\x00\x00"
NS = 1_000_000_000
MAX_CACHED_LAYOUTS = 256
U32 = struct.Struct("<I")
STAMP = struct.Struct("<iI")
SEVEN_DOUBLES = struct.Struct("<7d")


class CdrError(ValueError):
    """A payload is not a valid CDR encoding of the expected message (or a message cannot be encoded)."""


def padding(offset: int, align: int) -> int:
    """Bytes of padding needed at data offset ``offset`` (relative to the end of the header)."""
    return -offset % align


def utf8(text: str, what: str) -> bytes:
    """``text`` as UTF-8; CdrError (naming ``what``) if it cannot be encoded."""
    try:
        return text.encode("utf-8")
    except UnicodeEncodeError as exc:
        raise CdrError(f"{what} {text!r} cannot be encoded as UTF-8: {exc.reason}") from None


def remember(cache: dict[Any, Any], key: Any, value: Any) -> Any:
    """Store ``value`` in a bounded layout cache (emptied when full) and return it."""
    if len(cache) >= MAX_CACHED_LAYOUTS:
        cache.clear()
    cache[key] = value
    return value


def check_header(data: bytes, what: str) -> None:
    """Reject payloads too short for a message or not CDR little-endian."""
    if len(data) < 8:
        raise CdrError(f"{what}: payload of {len(data)} bytes is too short")
    if data[:2] != b"\x00\x01":
        raise CdrError(f"{what}: encapsulation {data[:2].hex()} is not CDR little-endian (0001)")


def read_string(data: bytes, offset: int, what: str) -> tuple[str, int]:
    """Read a CDR string whose length field starts at absolute ``offset`` (already aligned)."""
    (length,) = U32.unpack_from(data, offset)
    start = offset + 4
    end = start + length
    if length == 0 or end > len(data) or data[end - 1] != 0:
        raise CdrError(f"{what}: malformed string at byte {offset}")
    try:
        return data[start : end - 1].decode("utf-8"), end
    except UnicodeDecodeError:
        raise CdrError(f"{what}: string at byte {offset} is not valid UTF-8") from None


def make_time(sec: int, nanosec: int, what: str) -> Time:
    """A Time from decoded fields; CdrError if negative or ``nanosec`` >= 1e9."""
    if sec < 0 or nanosec >= NS:
        raise CdrError(f"{what}: stamp sec={sec} nanosec={nanosec} is not a valid time")
    return Time(sec, nanosec)


def check_end(data: bytes, offset: int, what: str) -> None:
    """Reject anything but up to 7 zero padding bytes after the last field."""
    rest = data[offset:]
    if len(rest) > 7 or rest.strip(b"\x00"):
        raise CdrError(f"{what}: {len(rest)} unexpected bytes after the message")
