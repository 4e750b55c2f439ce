"""Robot geometry for the viewer: every visual/collision element of a link as coloured triangle meshes.

Primitives (box, cylinder, sphere) and mesh files (STL, OBJ/MTL, DAE, GLB, PLY...) all become
:class:`MeshPart` values: vertices already expressed in the link frame (the ``<origin>`` and the
mesh ``scale`` are baked in), triangles, and a colour. Colours follow rviz: a mesh part that has
its own material (Collada effect, MTL ``Kd``, glTF base colour, vertex colours, a texture sampled
at its UVs) keeps it; otherwise the URDF ``<material>`` colour applies (looked up by name among
the robot's top-level materials when the visual only names it); otherwise a neutral grey.

Mesh files are found with the robot's :class:`~urdftk.resources.PackageResolver`, the same
resolution every other part of urdftk uses.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from urdftk.errors import ResourceError

__all__ = [
    "COLLISION_RGBA",
    "DEFAULT_RGBA",
    "GeometryLoader",
    "LinkGeometry",
    "MeshPart",
]

DEFAULT_RGBA = (0.8, 0.8, 0.8, 1.0)
"""Colour of a visual that has neither a URDF material nor a mesh material (rviz's default)."""

COLLISION_RGBA = (0.55, 0.25, 0.85, 1.0)
"""Colour of collision geometry (a purple that no example robot uses, so it stands out)."""

_CYLINDER_SECTIONS = 32


@dataclass(frozen=True)
class MeshPart:
    """One uniformly described triangle mesh, in its link's frame.

    Attributes:
        vertices: ``(n, 3)`` float32 positions in metres, in the link frame.
        faces: ``(m, 3)`` uint32 vertex indices.
        rgba: The part's colour, components in 0..1.
        vertex_colors: ``(n, 4)`` uint8 per-vertex colours (textures, coloured PLY), or None.
    """

    vertices: np.ndarray
    faces: np.ndarray
    rgba: tuple[float, float, float, float]
    vertex_colors: np.ndarray | None = None


@dataclass(frozen=True)
class LinkGeometry:
    """All visual or all collision geometry of one link.

    Attributes:
        link: The link (and TF frame) name.
        kind: ``"visual"`` or ``"collision"``.
        parts: The meshes.
        problems: Messages for elements that could not be loaded (missing mesh files...).
    """

    link: str
    kind: str
    parts: tuple[MeshPart, ...]
    problems: tuple[str, ...] = ()


def _origin(element: Any) -> np.ndarray:
    origin = getattr(element, "origin", None)
    return np.eye(4) if origin is None else np.asarray(origin, dtype=np.float64)


def _transformed(vertices: np.ndarray, T: np.ndarray) -> np.ndarray:
    return (vertices @ T[:3, :3].T + T[:3, 3]).astype(np.float32)


def _material_rgba(
    material: Any, named: dict[str, tuple[float, ...]]
) -> tuple[float, float, float, float] | None:
    """The colour a URDF ``<material>`` gives, or None."""
    if material is None:
        return None
    color = getattr(material, "color", None)
    rgba = getattr(color, "rgba", None) if color is not None else None
    if rgba is None and getattr(material, "name", None):
        rgba = named.get(material.name)
    if rgba is None:
        return None
    r, g, b, a = (float(v) for v in rgba)
    return (r, g, b, a)


def _own_colour(mesh: Any) -> tuple[tuple[float, float, float, float] | None, np.ndarray | None]:
    """A trimesh part's own colour: (uniform rgba or None, per-vertex uint8 colours or None)."""
    visual = getattr(mesh, "visual", None)
    if visual is None:
        return None, None
    kind = getattr(visual, "kind", None)
    if kind == "texture":
        material = getattr(visual, "material", None)
        image = getattr(material, "image", None) or getattr(material, "baseColorTexture", None)
        if image is not None and getattr(visual, "uv", None) is not None:
            try:
                colors = np.asarray(visual.to_color().vertex_colors, dtype=np.uint8)
            except Exception:  # a broken texture falls back to the material colour
                colors = None
            if colors is not None and colors.shape == (len(mesh.vertices), 4):
                return None, colors
        main = getattr(material, "main_color", None)
        if main is not None:
            c = np.asarray(main, dtype=np.float64) / 255.0
            return (float(c[0]), float(c[1]), float(c[2]), float(c[3])), None
        return None, None
    if kind in ("vertex", "face"):
        colors = np.asarray(visual.vertex_colors, dtype=np.uint8)
        if len(colors) and np.all(colors == colors[0]):
            c = colors[0] / 255.0
            return (float(c[0]), float(c[1]), float(c[2]), float(c[3])), None
        return None, colors
    return None, None


class GeometryLoader:
    """Loads link geometry for one robot, caching mesh files by (path, mtime, size).

    Args:
        resolver: Resolves ``package://`` and relative mesh references (``robot.resolver``).
        source: The file the description came from (relative mesh paths are relative to it).
    """

    def __init__(self, resolver: Any, source: str | os.PathLike[str] | None = None) -> None:
        self._resolver = resolver
        self._base = Path(source).parent if source else Path.cwd()
        self._cache: dict[tuple[str, int, int], list[tuple[np.ndarray, np.ndarray, Any]]] = {}

    def set_source(self, resolver: Any, source: str | os.PathLike[str] | None) -> None:
        """Use a new resolver and base folder (after a reload); the mesh cache is kept."""
        self._resolver = resolver
        self._base = Path(source).parent if source else Path.cwd()

    def resolve(self, filename: str) -> Path:
        """Turn a mesh reference into a path."""
        return Path(self._resolver.resolve(filename, relative_to=self._base))

    def _mesh_file(self, path: Path) -> list[tuple[np.ndarray, np.ndarray, Any]]:
        """(vertices, faces, trimesh part) per part of a mesh file, in the file's frame."""
        import trimesh

        try:
            st = path.stat()
        except OSError:
            raise ResourceError(f"mesh file {path} does not exist") from None
        key = (str(path), st.st_mtime_ns, st.st_size)
        cached = self._cache.get(key)
        if cached is not None:
            return cached
        try:
            scene = trimesh.load(str(path), force="scene")
        except Exception as exc:  # trimesh raises many types for bad files
            raise ResourceError(f"cannot read mesh {path}: {exc}") from None
        parts = []
        for node in scene.graph.nodes_geometry:
            T, geom_name = scene.graph[node]
            mesh = scene.geometry[geom_name]
            if not hasattr(mesh, "faces") or len(mesh.faces) == 0:
                continue
            verts = _transformed(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(T))
            parts.append((verts, np.asarray(mesh.faces, dtype=np.uint32), mesh))
        self._cache[key] = parts
        return parts

    def mesh_parts(self, resource: str, rgba: tuple[float, float, float, float]) -> list[MeshPart]:
        """The parts of one mesh file (in its own frame); parts without a material get ``rgba``."""
        parts = []
        for verts, faces, mesh in self._mesh_file(self.resolve(resource)):
            own, colors = _own_colour(mesh)
            parts.append(MeshPart(verts, faces, own or rgba, colors))
        return parts

    def _element_parts(
        self, element: Any, urdf_rgba: tuple[float, float, float, float] | None, collision: bool
    ) -> list[MeshPart]:
        import trimesh

        T = _origin(element)
        g = element.geometry
        fallback = COLLISION_RGBA if collision else (urdf_rgba or DEFAULT_RGBA)
        if g is None:
            return []
        prim = None
        if g.box is not None:
            prim = trimesh.creation.box(extents=np.asarray(g.box.size, dtype=np.float64))
        elif g.cylinder is not None:
            prim = trimesh.creation.cylinder(
                radius=float(g.cylinder.radius), height=float(g.cylinder.length), sections=_CYLINDER_SECTIONS
            )
        elif g.sphere is not None:
            prim = trimesh.creation.icosphere(subdivisions=2, radius=float(g.sphere.radius))
        if prim is not None:
            return [
                MeshPart(_transformed(prim.vertices, T), np.asarray(prim.faces, dtype=np.uint32), fallback)
            ]
        if g.mesh is None:
            return []
        path = self.resolve(g.mesh.filename)
        scale = np.ones(3) if g.mesh.scale is None else np.broadcast_to(np.asarray(g.mesh.scale, float), (3,))
        out = []
        for verts, faces, mesh in self._mesh_file(path):
            v = _transformed(verts * scale, T)
            f = faces if np.prod(scale) > 0 else faces[:, ::-1]
            rgba, colors = (None, None) if collision else _own_colour(mesh)
            out.append(MeshPart(v, np.ascontiguousarray(f), rgba or fallback, colors))
        return out

    def load(
        self, description: Any, kind: str, links: Iterable[str] | None = None
    ) -> dict[str, LinkGeometry]:
        """Load the ``kind`` ("visual" or "collision") geometry of every link.

        Args:
            description: The yourdfpy URDF (``robot.description``).
            kind: ``"visual"`` or ``"collision"``.
            links: Only these links (default: all).

        Returns:
            Link name -> geometry, for links that have any geometry or problems. An element that
            cannot be loaded is reported in ``problems`` and skipped; the rest of the robot loads.
        """
        if kind not in ("visual", "collision"):
            raise ValueError(f"kind must be 'visual' or 'collision', got {kind!r}")
        robot = description.robot
        named = {
            m.name: tuple(m.color.rgba) for m in (robot.materials or []) if m.color is not None and m.name
        }
        wanted = None if links is None else set(links)
        result: dict[str, LinkGeometry] = {}
        for link in robot.links:
            if wanted is not None and link.name not in wanted:
                continue
            elements = link.collisions if kind == "collision" else link.visuals
            parts: list[MeshPart] = []
            problems: list[str] = []
            for element in elements or []:
                rgba = (
                    None if kind == "collision" else _material_rgba(getattr(element, "material", None), named)
                )
                try:
                    parts.extend(self._element_parts(element, rgba, kind == "collision"))
                except ResourceError as exc:
                    problems.append(f"link '{link.name}' {kind}: {exc}")
            if parts or problems:
                result[link.name] = LinkGeometry(link.name, kind, tuple(parts), tuple(problems))
        return result
