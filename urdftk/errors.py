"""The exception hierarchy of urdftk: one root, :class:`UrdftkError`.

Every error says what went wrong, where (``file:line`` when there is a file), and what to do.
The CLI turns any :class:`UrdftkError` into one line on stderr and exit status 2.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = [
    "ConfigurationError",
    "DescriptionError",
    "JointNotFound",
    "KinematicsError",
    "LinkNotFound",
    "MimicWarning",
    "NameNotFound",
    "PackageNotFound",
    "ResourceError",
    "UrdftkError",
    "XacroError",
    "close_names",
    "format_location",
]


def format_location(filename: str | None, line: int | None = None, column: int | None = None) -> str:
    """Format ``file:line:col`` (parts that are unknown are left out).

    Args:
        filename: The file name, or None when the text did not come from a file.
        line: 1-based line number, if known.
        column: 1-based column number, if known.

    Returns:
        A location string such as ``robot.urdf:12:4``; ``<string>`` when no file is known.
    """
    loc = filename or "<string>"
    if line:
        loc += f":{line}"
        if column:
            loc += f":{column}"
    return loc


def close_names(name: str, candidates: Iterable[str], n: int = 3) -> list[str]:
    """Return up to ``n`` names from ``candidates`` that look like ``name`` (for "did you mean")."""
    import difflib  # only on the error path: keeps start-up light

    return difflib.get_close_matches(name, list(candidates), n=n, cutoff=0.6)


class UrdftkError(Exception):
    """Root of every error raised by urdftk."""


class ResourceError(UrdftkError):
    """A ``package://``, ``file://``, ``$(find)`` or relative path could not be resolved."""


class PackageNotFound(ResourceError):
    """A ROS package name could not be found on any search path.

    Attributes:
        package: The package that was asked for.
        searched: Every place that was searched, in order.
    """

    def __init__(self, package: str, searched: Iterable[str]):
        self.package = package
        self.searched = list(searched)
        where = "; ".join(self.searched) if self.searched else "(no search paths)"
        super().__init__(
            f"package '{package}' not found. Searched: {where}. "
            f"Add its parent folder with -p/--package-path or ROS_PACKAGE_PATH."
        )


class DescriptionError(UrdftkError):
    """A robot description (URDF text) is malformed or cannot be built.

    Attributes:
        filename: The file the text came from, if any.
        line: 1-based line of the offending element, if known.
        column: 1-based column, if known.
    """

    def __init__(
        self, message: str, filename: str | None = None, line: int | None = None, column: int | None = None
    ):
        self.filename = filename
        self.line = line
        self.column = column
        self.message = message
        prefix = format_location(filename, line, column) + ": " if (filename or line) else ""
        super().__init__(prefix + message)


class ConfigurationError(UrdftkError, ValueError):
    """A joint configuration has the wrong length, a non-finite value, or a value out of limits."""


class KinematicsError(UrdftkError):
    """A kinematic quantity cannot be computed for this robot (for example: too many joints)."""


class MimicWarning(UserWarning):
    """A ``<mimic>`` element was repaired (its target was found under the follower's name prefix)."""


class XacroError(UrdftkError):
    """A xacro file could not be expanded (syntax, undefined names, refused expressions, cycles)."""


class NameNotFound(UrdftkError, KeyError):
    """A name (link, joint, frame) is not known; the message lists the valid names.

    Attributes:
        name: The name that was asked for.
        valid: The valid names.
    """

    kind = "name"

    def __init__(self, name: str, valid: Iterable[str]):
        self.name = name
        self.valid = list(valid)
        hint = close_names(name, self.valid)
        shown = ", ".join(self.valid[:50]) + (", ..." if len(self.valid) > 50 else "")
        msg = f"unknown {self.kind} '{name}'"
        if hint:
            msg += f" (did you mean {', '.join(repr(h) for h in hint)}?)"
        msg += f". Valid {self.kind}s: {shown}"
        super().__init__(msg)

    def __str__(self) -> str:
        return str(self.args[0])


class LinkNotFound(NameNotFound):
    """A link or frame name is not part of the robot."""

    kind = "frame"


class JointNotFound(NameNotFound):
    """A joint name is not part of the robot."""

    kind = "joint"
