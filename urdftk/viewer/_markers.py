"""rviz-style markers: arrows, spheres, boxes, cylinders, line strips, text and meshes in any TF frame.

A :class:`Marker` is an immutable value shaped like ``visualization_msgs/Marker``: a type, the
TF frame it is expressed in, a pose in that frame (quaternion **xyzw**), a scale, a colour, and
the type-specific fields. The viewer attaches it to its frame, so it moves with TF.
Scale follows rviz: arrow = (length, shaft diameter, head diameter) (or, with two ``points``,
(shaft diameter, head diameter, head length)); sphere/box = size along x, y, z; cylinder =
(diameter x, diameter y, height along z); line strip = (width, -, -); text = (-, -, height);
mesh = per-axis scale.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from urdftk.viewer._geometry import MeshPart

__all__ = ["MARKER_TYPES", "Marker", "MarkerItem", "marker_items"]

MARKER_TYPES = ("arrow", "box", "cylinder", "line_strip", "mesh", "sphere", "text")
"""The marker types :meth:`Viewer.add_marker` accepts."""


def _vec(values: Sequence[float], n: int, what: str) -> tuple[float, ...]:
    out = tuple(float(v) for v in values)
    if len(out) != n or not all(np.isfinite(out)):
        raise ValueError(f"marker {what} must be {n} finite numbers, got {values!r}")
    return out


@dataclass(frozen=True)
class Marker:
    """A marker, as in rviz (``visualization_msgs/Marker``).

    Attributes:
        type: One of :data:`MARKER_TYPES`.
        frame_id: The TF frame the pose is expressed in.
        position: Position in ``frame_id`` (metres).
        orientation: Orientation in ``frame_id``, quaternion xyzw.
        scale: Size, per type (see the module docstring).
        color: RGBA in 0..1.
        points: Points for ``line_strip`` (and two-point ``arrow``), in the marker's pose frame.
        text: The text of a ``text`` marker.
        mesh_resource: ``package://``, ``file://`` or path of a ``mesh`` marker.
        ns: Namespace; ``(ns, id)`` identifies the marker (adding again replaces it).
        id: Identifier within ``ns``.
    """

    type: str
    frame_id: str
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    orientation: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)
    scale: tuple[float, float, float] = (0.1, 0.1, 0.1)
    color: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 1.0)
    points: tuple[tuple[float, float, float], ...] = ()
    text: str = ""
    mesh_resource: str = ""
    ns: str = ""
    id: int = 0

    def __post_init__(self) -> None:
        if self.type not in MARKER_TYPES:
            raise ValueError(f"unknown marker type {self.type!r}; expected one of {MARKER_TYPES}")
        if not self.frame_id:
            raise ValueError("a marker needs a frame_id (the TF frame it is expressed in)")
        object.__setattr__(self, "position", _vec(self.position, 3, "position"))
        q = np.asarray(_vec(self.orientation, 4, "orientation (xyzw)"))
        norm = float(np.linalg.norm(q))
        if norm < 1e-9:
            raise ValueError("marker orientation is a zero quaternion")
        object.__setattr__(self, "orientation", tuple(float(v) for v in q / norm))
        object.__setattr__(self, "scale", _vec(self.scale, 3, "scale"))
        object.__setattr__(self, "color", _vec(self.color, 4, "color (rgba)"))
        object.__setattr__(self, "points", tuple(_vec(p, 3, "point") for p in self.points))
        if self.type == "line_strip" and len(self.points) < 2:
            raise ValueError("a line_strip marker needs at least two points")
        if self.type == "mesh" and not self.mesh_resource:
            raise ValueError("a mesh marker needs mesh_resource")

    @property
    def key(self) -> tuple[str, int]:
        """``(ns, id)``: the marker's identity."""
        return (self.ns, self.id)


@dataclass(frozen=True)
class MarkerItem:
    """One thing to draw for a marker: ``kind`` is "mesh", "label" or "lines"."""

    kind: str
    part: MeshPart | None = None
    text: str = ""
    segments: np.ndarray | None = None
    width: float = 0.0


def _part(mesh: Any, rgba: tuple[float, float, float, float], T: np.ndarray | None = None) -> MeshPart:
    if T is not None:
        mesh = mesh.copy()
        mesh.apply_transform(T)
    return MeshPart(
        np.asarray(mesh.vertices, dtype=np.float32), np.asarray(mesh.faces, dtype=np.uint32), rgba
    )


def _arrow(
    start: np.ndarray, end: np.ndarray, shaft_d: float, head_d: float, head_len: float, rgba: Any
) -> MeshPart:
    import trimesh

    axis = end - start
    length = float(np.linalg.norm(axis))
    if length < 1e-12:
        raise ValueError("arrow marker has zero length")
    head_len = min(head_len, length)
    shaft = trimesh.creation.cylinder(radius=shaft_d / 2, height=length - head_len, sections=16)
    shaft.apply_translation((0, 0, (length - head_len) / 2))
    head = trimesh.creation.cone(radius=head_d / 2, height=head_len, sections=16)
    head.apply_translation((0, 0, length - head_len))
    mesh = trimesh.util.concatenate([shaft, head])
    z = axis / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, np.cross(z, x), z, start
    return _part(mesh, rgba, T)


def marker_items(marker: Marker, load_mesh: Any = None) -> list[MarkerItem]:
    """What to draw for ``marker``, in its pose frame.

    Args:
        marker: The marker.
        load_mesh: ``callable(resource) -> list[MeshPart]`` for ``mesh`` markers.

    Returns:
        The items; meshes take the marker colour unless a mesh file brings its own.
    """
    import trimesh

    sx, sy, sz = marker.scale
    rgba = marker.color
    t = marker.type
    if t == "arrow":
        if len(marker.points) >= 2:
            start, end = np.asarray(marker.points[0]), np.asarray(marker.points[1])
            return [MarkerItem("mesh", _arrow(start, end, sx, sy, sz or 0.3 * sy, rgba))]
        return [MarkerItem("mesh", _arrow(np.zeros(3), np.array([sx, 0, 0]), sy, sz, 0.23 * sx, rgba))]
    if t == "sphere":
        return [
            MarkerItem("mesh", _part(trimesh.creation.icosphere(2, 0.5), rgba, np.diag([sx, sy, sz, 1.0])))
        ]
    if t == "box":
        return [MarkerItem("mesh", _part(trimesh.creation.box(extents=(sx, sy, sz)), rgba))]
    if t == "cylinder":
        cyl = trimesh.creation.cylinder(radius=0.5, height=1.0, sections=32)
        return [MarkerItem("mesh", _part(cyl, rgba, np.diag([sx, sy, sz, 1.0])))]
    if t == "line_strip":
        pts = np.asarray(marker.points, dtype=np.float32)
        return [MarkerItem("lines", segments=np.stack([pts[:-1], pts[1:]], axis=1), width=sx)]
    if t == "text":
        return [MarkerItem("label", text=marker.text)]
    if load_mesh is None:
        raise ValueError("mesh markers need a mesh loader")
    parts = load_mesh(marker.mesh_resource)
    scale = np.asarray(marker.scale, dtype=np.float32)
    return [MarkerItem("mesh", MeshPart(p.vertices * scale, p.faces, p.rgba, p.vertex_colors)) for p in parts]
