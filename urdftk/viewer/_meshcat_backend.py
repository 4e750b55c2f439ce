"""The meshcat backend: meshcat's browser viewer, served by urdftk on the address it is given.

meshcat's own server (``meshcat.servers.zmqserver``) binds its web port on every interface and
needs a ZeroMQ hop; this backend serves meshcat's static viewer and its websocket from a tornado
server bound to ``host`` only, and sends meshcat's own command messages (``meshcat.commands``)
straight to the browsers. Late browsers get the whole scene replayed (meshcat's ``SceneTree``).
Meshes are sent as triangle meshes with the colours urdftk extracted (Collada materials included).
"""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from urdftk.viewer._backend import SceneBackend
from urdftk.viewer._geometry import MeshPart
from urdftk.viewer._poses import xyzw_to_matrix

__all__ = ["MeshcatBackend"]

_PREFIX = "/meshcat"


def _hex(rgb: Sequence[float]) -> int:
    r, g, b = (round(255 * min(max(c, 0.0), 1.0)) for c in rgb[:3])
    return (r << 16) | (g << 8) | b


class _Server:
    """A tornado app (static viewer + websocket) on its own thread and event loop."""

    def __init__(self, host: str, port: int) -> None:
        import meshcat
        from meshcat.servers.tree import SceneTree

        self.tree = SceneTree()
        self.sockets: set = set()
        self._root = str(Path(meshcat.__file__).parent / "viewer" / "dist")
        self._loop = asyncio.new_event_loop()
        self._started = threading.Event()
        self._error: BaseException | None = None
        self._http = None
        self.port = port
        self._thread = threading.Thread(
            target=self._run, args=(host, port), name="urdftk-meshcat", daemon=True
        )
        self._thread.start()
        self._started.wait()
        if self._error is not None:
            raise OSError(f"cannot serve meshcat on {host}:{port}: {self._error}")

    def _run(self, host: str, port: int) -> None:
        import tornado.web
        import tornado.websocket

        server = self

        class Socket(tornado.websocket.WebSocketHandler):
            def open(self) -> None:
                server.sockets.add(self)
                server.replay(self)

            def on_message(self, message: object) -> None:  # the viewer sends nothing we need
                return

            def on_close(self) -> None:
                server.sockets.discard(self)

        asyncio.set_event_loop(self._loop)
        try:
            app = tornado.web.Application(
                [
                    (
                        r"/static/(.*)",
                        tornado.web.StaticFileHandler,
                        {"path": self._root, "default_filename": "index.html"},
                    ),
                    (r"/", Socket),
                ]
            )
            self._http = app.listen(port, address=host)
            sock = next(iter(self._http._sockets.values()))  # type: ignore[attr-defined]
            self.port = sock.getsockname()[1]
        except BaseException as exc:  # reported by __init__
            self._error = exc
            self._started.set()
            return
        self._started.set()
        self._loop.run_forever()

    def replay(self, socket: object) -> None:
        from meshcat.servers.tree import walk

        for node in walk(self.tree):
            for data in (
                ([node.object] if node.object is not None else [])
                + list(node.properties)
                + ([node.transform] if node.transform is not None else [])
            ):
                socket.write_message(data, binary=True)  # type: ignore[attr-defined]

    def _record(self, kind: str, path: str, data: bytes) -> None:
        from meshcat.servers.tree import SceneTree, find_node

        parts = [p for p in path.split("/") if p]
        if kind == "delete":
            if parts:
                parent = find_node(self.tree, parts[:-1])
                if parts[-1] in parent:
                    del parent[parts[-1]]
            else:
                self.tree = SceneTree()
            return
        node = find_node(self.tree, parts)
        if kind == "set_object":
            node.object, node.properties = data, []
        elif kind == "set_transform":
            node.transform = data
        elif kind == "set_property":
            node.properties.append(data)

    def _dispatch(self, commands: list[tuple[str, str, bytes]]) -> None:
        for kind, path, data in commands:
            self._record(kind, path, data)
            for socket in list(self.sockets):
                socket.write_message(data, binary=True)

    def send(self, commands: list[tuple[str, str, bytes]]) -> None:
        if commands and not self._loop.is_closed():
            self._loop.call_soon_threadsafe(self._dispatch, commands)

    def stop(self) -> None:
        def _stop() -> None:
            if self._http is not None:
                self._http.stop()
            for socket in list(self.sockets):
                socket.close()
            self._loop.stop()

        if self._loop.is_running():
            self._loop.call_soon_threadsafe(_stop)
            self._thread.join(timeout=5)


class MeshcatBackend(SceneBackend):
    """Draws the scene with meshcat's viewer (no GUI panel: joint updates come from TF).

    Args:
        host: Interface to bind.
        port: TCP port (0: any free port).
    """

    def __init__(self, host: str = "127.0.0.1", port: int = 7000) -> None:
        self._host = host
        self._server = _Server(host, port)
        self._lock = threading.RLock()
        self._depth = 0
        self._pending: list[tuple[str, str, bytes]] = []
        self._parts: dict[str, MeshPart] = {}
        self._axes: dict[str, tuple[bool, float]] = {}
        self.status = ""
        self._command("set_property", "/Grid", property="visible", value=False)

    @property
    def url(self) -> str:
        """``http://host:port/static/``."""
        host = f"[{self._host}]" if ":" in self._host else self._host
        return f"http://{host}:{self._server.port}/static/"

    def _command(self, kind: str, name: str, **fields: object) -> None:
        import umsgpack

        path = name if name.startswith("/Grid") else _PREFIX + name
        msg: dict[str, object] = {"type": kind, "path": path, **fields}
        data = umsgpack.packb(msg)
        with self._lock:
            self._pending.append((kind, path, data))
            if self._depth == 0:
                pending, self._pending = self._pending, []
                self._server.send(pending)

    @contextmanager
    def batch(self) -> Iterator[None]:
        """Send everything queued inside the block in one go."""
        with self._lock:
            self._depth += 1
            try:
                yield
            finally:
                self._depth -= 1
                if self._depth == 0:
                    pending, self._pending = self._pending, []
                    self._server.send(pending)

    def _set_object(self, name: str, obj: object) -> None:
        self._command("set_object", name, object=obj.lower())  # type: ignore[attr-defined]

    def _set_transform(self, name: str, T: np.ndarray) -> None:
        self._command("set_transform", name, matrix=[float(v) for v in T.T.flatten()])

    def add_frame(
        self, name: str, position: np.ndarray, xyzw: np.ndarray, *, show_axes: bool, axes_length: float
    ) -> None:
        """Add a frame node: a transform, with a triad child for the axes."""
        self._command("delete", name)
        self._set_transform(name, xyzw_to_matrix(position, xyzw))
        self._axes[name] = (False, 0.0)
        self.set_axes(name, show_axes, axes_length)

    def set_poses(self, names: Sequence[str], positions: np.ndarray, xyzw: np.ndarray) -> None:
        """Move nodes."""
        for name, p, q in zip(names, positions, xyzw, strict=True):
            self._set_transform(name, xyzw_to_matrix(p, q))

    def set_axes(self, name: str, show: bool, axes_length: float) -> None:
        """Show/hide a triad of ``axes_length``."""
        from meshcat import geometry as g

        if self._axes.get(name) == (show, axes_length):
            return
        if show:
            self._set_object(name + "/@axes", g.triad(max(axes_length, 1e-4)))
        else:
            self._command("delete", name + "/@axes")
        self._axes[name] = (show, axes_length)

    def add_group(self, name: str, *, visible: bool = True) -> None:
        """Add a grouping node."""
        self._command("delete", name)
        self._set_transform(name, np.eye(4))
        self.set_visible(name, visible)

    def _mesh_object(self, part: MeshPart, opacity: float) -> object:
        from meshcat import geometry as g

        colors = None if part.vertex_colors is None else part.vertex_colors[:, :3].astype(np.float32) / 255.0
        alpha = float(opacity * part.rgba[3])
        material = g.MeshLambertMaterial(
            color=0xFFFFFF if colors is not None else _hex(part.rgba),
            opacity=alpha,
            vertexColors=colors is not None,
        )
        return g.Mesh(g.TriangularMeshGeometry(part.vertices, part.faces, color=colors), material)

    def add_mesh(self, name: str, part: MeshPart, *, opacity: float = 1.0, visible: bool = True) -> None:
        """Add a triangle mesh with its colour."""
        self._parts[name] = part
        self._set_object(name, self._mesh_object(part, opacity))
        if not visible:
            self.set_visible(name, False)

    def set_opacity(self, name: str, part: MeshPart, opacity: float) -> None:
        """Re-send the mesh with a new opacity."""
        self._set_object(name, self._mesh_object(part, opacity))

    def add_label(self, name: str, text: str, *, visible: bool = True) -> None:
        """Meshcat has no text labels: nothing is drawn."""

    def add_lines(
        self,
        name: str,
        segments: np.ndarray,
        rgb: tuple[float, float, float],
        *,
        width: float,
        visible: bool = True,
    ) -> None:
        """Add line segments."""
        from meshcat import geometry as g

        pts = np.asarray(segments, dtype=np.float32).reshape(-1, 3).T
        self._set_object(name, g.LineSegments(g.PointsGeometry(pts), g.LineBasicMaterial(color=_hex(rgb))))
        if not visible:
            self.set_visible(name, False)

    def add_grid(self, name: str, *, size: float, cell: float) -> None:
        """Show meshcat's own grid."""
        self._command("set_property", "/Grid", property="visible", value=True)

    def set_visible(self, name: str, visible: bool) -> None:
        """Show or hide a node."""
        self._command("set_property", name, property="visible", value=bool(visible))

    def remove(self, name: str) -> None:
        """Delete a node and its descendants."""
        prefix = name + "/"
        for key in [k for k in self._parts if k == name or k.startswith(prefix)]:
            del self._parts[key]
        for key in [k for k in self._axes if k == name or k.startswith(prefix)]:
            del self._axes[key]
        self._command("delete", name)

    def show_status(self, text: str, *, error: bool) -> None:
        """Remember the status (meshcat has no panel to show it in)."""
        self.status = text

    def close(self) -> None:
        """Stop serving."""
        self._server.stop()
