"""The viser backend: scene nodes in a :class:`viser.ViserServer` (xyzw -> wxyz happens here only)."""

from __future__ import annotations

import threading
from collections.abc import Iterator, Sequence
from contextlib import contextmanager

import numpy as np

from urdftk.viewer._backend import SceneBackend
from urdftk.viewer._geometry import MeshPart

__all__ = ["ViserBackend"]


def _rgb255(rgb: Sequence[float]) -> tuple[int, int, int]:
    return (
        round(255 * min(max(rgb[0], 0.0), 1.0)),
        round(255 * min(max(rgb[1], 0.0), 1.0)),
        round(255 * min(max(rgb[2], 0.0), 1.0)),
    )


class ViserBackend(SceneBackend):
    """Draws the scene with viser.

    Args:
        host: Interface to bind (viser's own default is 0.0.0.0; ours is loopback).
        port: TCP port (0: any free port).
        label: Title shown at the top of the control panel.
    """

    def __init__(self, host: str = "127.0.0.1", port: int = 8080, label: str | None = None) -> None:
        import viser

        self.server = viser.ViserServer(host=host, port=port, label=label, verbose=False)
        self._handles: dict[str, object] = {}
        self._lock = threading.RLock()
        self._depth = 0
        self._atomic: object | None = None
        self._status = self.server.gui.add_markdown("", order=-1000, visible=False)
        scene = self.server.scene
        scene.set_up_direction("+z")
        # An HDRI environment map takes ~10 s to prepare in software WebGL (headless, no GPU);
        # a hemisphere light plus viser's default lights shows colours as faithfully.
        scene.configure_environment_map(None)
        scene.configure_default_lights(True, cast_shadow=False)
        scene.add_light_hemisphere(
            "/lights/hemisphere", sky_color=(255, 255, 255), ground_color=(90, 90, 90), intensity=1.2
        )

    @property
    def url(self) -> str:
        """``http://host:port/``."""
        host = self.server.get_host()
        host = "127.0.0.1" if host in ("0.0.0.0", "") else host
        if ":" in host:
            host = f"[{host}]"
        return f"http://{host}:{self.server.get_port()}/"

    @contextmanager
    def batch(self) -> Iterator[None]:
        """Group updates in one viser ``atomic()`` block (re-entrant)."""
        with self._lock:
            if self._depth == 0:
                self._atomic = self.server.atomic()
                self._atomic.__enter__()  # type: ignore[attr-defined]
            self._depth += 1
            try:
                yield
            finally:
                self._depth -= 1
                if self._depth == 0:
                    atomic, self._atomic = self._atomic, None
                    atomic.__exit__(None, None, None)  # type: ignore[union-attr]

    def _put(self, name: str, handle: object) -> None:
        self._handles[name] = handle

    def add_frame(
        self, name: str, position: np.ndarray, xyzw: np.ndarray, *, show_axes: bool, axes_length: float
    ) -> None:
        """Add a frame node (``xyzw`` converted to viser's wxyz)."""
        x, y, z, w = (float(v) for v in xyzw)
        self._put(
            name,
            self.server.scene.add_frame(
                name,
                show_axes=show_axes,
                axes_length=max(axes_length, 1e-4),
                axes_radius=max(axes_length, 1e-4) * 0.05,
                origin_radius=max(axes_length, 1e-4) * 0.08,
                wxyz=(w, x, y, z),
                position=tuple(float(v) for v in position),
            ),
        )

    def set_poses(self, names: Sequence[str], positions: np.ndarray, xyzw: np.ndarray) -> None:
        """Move nodes; only the position or orientation that changed is sent."""
        wxyz = np.empty_like(xyzw)
        wxyz[:, 0] = xyzw[:, 3]
        wxyz[:, 1:] = xyzw[:, :3]
        handles = self._handles
        for name, p, q in zip(names, positions, wxyz, strict=True):
            h = handles.get(name)
            if h is not None:
                h.position = p  # type: ignore[attr-defined]
                h.wxyz = q  # type: ignore[attr-defined]

    def set_axes(self, name: str, show: bool, axes_length: float) -> None:
        """Show/hide a frame's axes and set their size."""
        h = self._handles.get(name)
        if h is None:
            return
        length = max(axes_length, 1e-4)
        if bool(h.show_axes) != show:  # type: ignore[attr-defined]
            h.show_axes = show  # type: ignore[attr-defined]
        if abs(float(h.axes_length) - length) > 1e-12:  # type: ignore[attr-defined]
            h.axes_length = length  # type: ignore[attr-defined]
            h.axes_radius = length * 0.05  # type: ignore[attr-defined]
            h.origin_radius = length * 0.08  # type: ignore[attr-defined]

    def add_group(self, name: str, *, visible: bool = True) -> None:
        """Add an invisible grouping node."""
        self._put(name, self.server.scene.add_frame(name, show_axes=False, visible=visible))

    def add_mesh(self, name: str, part: MeshPart, *, opacity: float = 1.0, visible: bool = True) -> None:
        """Add a mesh: one colour as a simple mesh, per-vertex colours as a trimesh (GLB)."""
        if part.vertex_colors is None:
            alpha = opacity * part.rgba[3]
            handle = self.server.scene.add_mesh_simple(
                name,
                part.vertices,
                part.faces,
                color=_rgb255(part.rgba),
                opacity=None if alpha >= 1.0 else float(alpha),
                side="double",
                visible=visible,
            )
        else:
            import trimesh

            mesh = trimesh.Trimesh(part.vertices, part.faces, vertex_colors=part.vertex_colors, process=False)
            handle = self.server.scene.add_mesh_trimesh(name, mesh, visible=visible)
        self._put(name, handle)

    def set_opacity(self, name: str, part: MeshPart, opacity: float) -> None:
        """Change the opacity of a single-colour mesh."""
        h = self._handles.get(name)
        if h is not None and part.vertex_colors is None:
            alpha = opacity * part.rgba[3]
            h.opacity = None if alpha >= 1.0 else float(alpha)  # type: ignore[attr-defined]

    def add_label(self, name: str, text: str, *, visible: bool = True) -> None:
        """Add a text label."""
        self._put(name, self.server.scene.add_label(name, text, visible=visible, font_screen_scale=0.8))

    def add_lines(
        self,
        name: str,
        segments: np.ndarray,
        rgb: tuple[float, float, float],
        *,
        width: float,
        visible: bool = True,
    ) -> None:
        """Add line segments (width in metres)."""
        self._put(
            name,
            self.server.scene.add_line_segments(
                name,
                np.asarray(segments, dtype=np.float32),
                colors=_rgb255(rgb),
                thickness=max(float(width), 1e-4),
                thickness_units="world",
                visible=visible,
            ),
        )

    def add_grid(self, name: str, *, size: float, cell: float) -> None:
        """Add the ground grid."""
        self._put(
            name,
            self.server.scene.add_grid(name, width=size, height=size, cell_size=cell, section_size=4 * cell),
        )

    def set_visible(self, name: str, visible: bool) -> None:
        """Show or hide a node."""
        h = self._handles.get(name)
        if h is not None:
            h.visible = visible  # type: ignore[attr-defined]

    def remove(self, name: str) -> None:
        """Remove a node and its descendants."""
        prefix = name + "/"
        for key in [k for k in self._handles if k == name or k.startswith(prefix)]:
            self._handles.pop(key)
        self.server.scene.remove_by_name(name)

    def show_status(self, text: str, *, error: bool) -> None:
        """Show ``text`` at the top of the panel (empty hides it)."""
        if text:
            icon = "**Error:** " if error else ""
            body = text.replace("\n", "  \n")
            self._status.content = f"{icon}{body}"
        self._status.visible = bool(text)

    def frame_camera(self, center: np.ndarray, radius: float) -> None:
        """Look at ``center`` from a diagonal, far enough to see a sphere of ``radius``."""
        r = max(float(radius), 0.2)
        c = np.asarray(center, dtype=np.float64)
        direction = np.array([1.0, 1.0, 0.6]) / np.linalg.norm([1.0, 1.0, 0.6])
        self.server.initial_camera.look_at = tuple(c)
        self.server.initial_camera.position = tuple(c + direction * r * 2.6)

    def close(self) -> None:
        """Stop the server."""
        self.server.stop()
