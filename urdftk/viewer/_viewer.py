"""``Viewer``: a robot, its TF tree and markers in the browser, driven by a ``tf.Buffer``.

Data flow (one direction, as everywhere in urdftk)::

    sliders / set_joint_positions ──/joint_states──▶ RobotStatePublisher ──/tf, /tf_static──▶
    TransformListener ──▶ tf.Buffer ──▶ Scene.update (batched lookup, changed poses only) ──▶ browser

With ``listen=True`` the viewer publishes nothing: /tf and /tf_static come from the transport
(another process's robot state publisher), and /joint_states only moves the (read-only) sliders.
A render thread waits on an Event set by every /tf message, so bursts coalesce into one update.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from urdftk.viewer._geometry import GeometryLoader
from urdftk.viewer._markers import Marker
from urdftk.viewer._scene import Scene

__all__ = ["Viewer"]

_TRAILING_S = 0.1  # one more look at the buffer after a burst (transports may deliver out of order)


class Viewer:
    """Show a robot and everything TF says in a browser (viser, or meshcat).

    Args:
        robot: A :class:`urdftk.Robot` (from :func:`urdftk.load`).
        backend: ``"viser"`` (default, with the control panel) or ``"meshcat"``.
        host: Interface to bind; loopback unless you ask otherwise.
        port: TCP port; 0 picks a free one.
        fixed_frame: Frame the scene is expressed in (default: the robot's root link).
        transport: The tf transport to use; default: a private in-process one.
        listen: Take /tf, /tf_static and /joint_states from ``transport`` instead of the sliders.
        rate: If given, also republish every joint state at this rate in Hz (as ROS's
            joint_state_publisher does), so that listeners joining later get /tf.

    Example:
        >>> robot = urdftk.load("examples/robots/robot0_description/urdf/robot0.urdf")  # doctest: +SKIP
        >>> with Viewer(robot, port=0) as viewer:  # doctest: +SKIP
        ...     viewer.set_joint_positions({"joint_1": 0.5})
        ...     print(viewer.url)
    """

    def __init__(
        self,
        robot: Any,
        *,
        backend: str = "viser",
        host: str = "127.0.0.1",
        port: int = 8080,
        fixed_frame: str | None = None,
        transport: Any = None,
        listen: bool = False,
        rate: float | None = None,
    ) -> None:
        import tf
        from tf.transport import TOPIC_JOINT_STATES, TOPIC_TF, TOPIC_TF_STATIC, InProcessTransport

        if backend not in ("viser", "meshcat"):
            raise ValueError(f"unknown viewer backend {backend!r}; use 'viser' or 'meshcat'")
        self._own_transport = transport is None
        self.transport = InProcessTransport() if transport is None else transport
        self.listen = listen
        self._rate = rate
        self.buffer = tf.Buffer()
        self._robot = robot
        self._q = robot.neutral()
        self._closed = False
        self._wake = threading.Event()
        self._edges_lock = threading.Lock()
        self._edges: dict[str, str] = {}  # {child: parent} received since the last update
        self._lock = threading.RLock()
        self._loader = GeometryLoader(robot.resolver, robot.source)
        if backend == "viser":
            from urdftk.viewer._viser_backend import ViserBackend

            self._backend: Any = ViserBackend(host, port, label=f"urdftk · {robot.name}")
        else:
            from urdftk.viewer._meshcat_backend import MeshcatBackend

            self._backend = MeshcatBackend(host, port)
        self.scene = Scene(self._backend, fixed_frame or robot.root_link, load_mesh=self._loader.mesh_parts)
        self._panel: Any = None
        if backend == "viser":
            from urdftk.viewer._panel import Panel

            self._panel = Panel(
                self._backend.server, self.scene, self._from_panel, self.set_fixed_frame, listen=listen
            )
        self._set_geometry(robot)
        self._listener = tf.TransformListener(self.buffer, self.transport)
        self._subs = [
            self.transport.subscribe(TOPIC_TF, tf.TFMessage, self._poke),
            self.transport.subscribe(TOPIC_TF_STATIC, tf.TFMessage, self._poke),
        ]
        self._state_pub: Any = None
        self._js_pub: Any = None
        if listen:
            self._subs.append(
                self.transport.subscribe(TOPIC_JOINT_STATES, tf.JointState, self._on_joint_state)
            )
        else:
            self._state_pub = self._make_state_publisher(robot)
        if self._panel is not None:
            self._panel.set_robot(robot, self.joint_values())
        self._thread = threading.Thread(target=self._render_loop, name="urdftk-viewer", daemon=True)
        self._thread.start()
        if not listen:
            self._publish()

    # ------------------------------------------------------------------ public API
    @property
    def url(self) -> str:
        """The address to open in a browser."""
        return self._backend.url

    @property
    def robot(self) -> Any:
        """The robot shown (replaced by :meth:`load`)."""
        return self._robot

    @property
    def fixed_frame(self) -> str | None:
        """The frame the scene is expressed in."""
        return self.scene.fixed_frame

    def set_fixed_frame(self, frame: str) -> None:
        """Express the scene in ``frame`` (any TF frame)."""
        self.scene.set_fixed_frame(frame)
        if self._panel is not None:
            self._panel.show_fixed_frame(frame)
        self._refresh(None)

    def joint_values(self) -> dict[str, float]:
        """The current independent joint values, by name."""
        return {n: float(v) for n, v in zip(self._robot.joint_names, self._q, strict=True)}

    def set_joint_positions(self, q: Mapping[str, float] | Sequence[float] | np.ndarray) -> None:
        """Set joint values (a dict by name, or an array in ``robot.joint_names`` order) and publish them."""
        if self.listen:
            raise ValueError(
                "the viewer is listening to /joint_states; publish joint states on the transport"
            )
        with self._lock:
            if isinstance(q, Mapping):
                q = {**self.joint_values(), **q}
            old, self._q = self._q, self._robot.q(q)
            moved = [n for n, a, b in zip(self._robot.joint_names, old, self._q, strict=True) if a != b]
        if self._panel is not None:
            self._panel.show_values({n: v for n, v in self.joint_values().items() if n in moved})
        self._publish(moved)

    def add_marker(self, type: str, frame_id: str, **fields: Any) -> Marker:
        """Draw an rviz-style marker in TF frame ``frame_id``; it moves with that frame.

        Args:
            type: "arrow", "sphere", "box", "cylinder", "line_strip", "text" or "mesh".
            frame_id: The TF frame the marker's pose is expressed in.
            **fields: :class:`~urdftk.viewer._markers.Marker` fields (position, orientation (xyzw),
                scale, color, points, text, mesh_resource, ns, id).

        Returns:
            The marker; adding another with the same ``(ns, id)`` replaces it.
        """
        marker = Marker(type, frame_id, **fields)
        self.scene.add_marker(marker)
        return marker

    def remove_marker(self, ns: str = "", id: int = 0) -> None:
        """Remove the marker ``(ns, id)``."""
        self.scene.remove_marker(ns, id)

    def refresh(self) -> int:
        """Update the whole scene from the buffer now, in this thread; returns the number of poses sent."""
        return self._refresh(None)

    def _refresh(self, edges: dict[str, str] | None) -> int:
        sent, restructured = self.scene.update(self.buffer, edges)
        if restructured and self._panel is not None:
            self._panel.set_frames(self.scene.frames(), self._robot.link_names)
        return sent

    def load(self, robot: Any) -> None:
        """Show another robot (e.g. after a reload), keeping joint values where joints still exist."""
        import tf

        old = self.joint_values()
        with self._lock:
            self._robot = robot
            self._q = robot.q({n: v for n, v in old.items() if n in robot.joint_names}, clip=True)
            self._loader.set_source(robot.resolver, robot.source)
            if self._state_pub is not None:
                self._state_pub.close()
            self._listener.close()
            self.buffer.clear()
            self._set_geometry(robot)
            self._listener = tf.TransformListener(self.buffer, self.transport)
            if not self.listen:
                self._state_pub = self._make_state_publisher(robot)
        if self._panel is not None:
            self._panel.set_robot(robot, self.joint_values())
        if not self.listen:
            self._publish()
        self._wake.set()

    def show_status(self, text: str, *, error: bool = False) -> None:
        """Show a message in the page (an empty text clears it)."""
        self._backend.show_status(text, error=error)

    def show(self, height: int = 480) -> Any:
        """An IPython display object embedding the viewer page (for notebooks)."""
        from IPython.display import IFrame

        return IFrame(self.url, width="100%", height=height)

    def close(self) -> None:
        """Stop the render thread, the publishers and the server."""
        if self._closed:
            return
        self._closed = True
        self._wake.set()
        self._thread.join(timeout=5)
        for sub in self._subs:
            sub.close()
        self._listener.close()
        if self._state_pub is not None:
            self._state_pub.close()
        if self._js_pub is not None:
            self._js_pub.close()
        if self._own_transport:
            self.transport.close()
        self._backend.close()

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ internals
    def _make_state_publisher(self, robot: Any) -> Any:
        from urdftk.joint_state import JointStatePublisher
        from urdftk.robot_state import RobotStatePublisher

        if self._js_pub is not None:
            self._js_pub.close()
        self._js_pub = JointStatePublisher(robot, self.transport, rate=self._rate or 10.0)
        if self._rate:
            self._js_pub.start()
        # publish_frequency=0: every slider step goes out (a rate cap would swallow the last one)
        return RobotStatePublisher(robot, self.transport, publish_frequency=0)

    def _set_geometry(self, robot: Any) -> None:
        visual = self._loader.load(robot.description, "visual")
        collision = self._loader.load(robot.description, "collision")
        problems = [p for g in (*visual.values(), *collision.values()) for p in g.problems]
        for p in problems:
            print(f"urdftk view: warning: {p}", file=sys.stderr)
        self.scene.set_geometry(visual, collision)
        self._frame_camera(robot, visual)
        if problems:
            self.show_status("\n".join(problems[:5]), error=True)

    def _frame_camera(self, robot: Any, visual: Mapping[str, Any]) -> None:
        T = robot.fk(robot.neutral())
        index = {n: i for i, n in enumerate(robot.link_names)}
        points = [T[index[link], :3, 3] for link in robot.link_names]
        for link, geom in visual.items():
            if link in index:
                for part in geom.parts:
                    lo, hi = part.vertices.min(axis=0), part.vertices.max(axis=0)
                    corners = np.array(
                        [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
                    )
                    points.extend(corners @ T[index[link], :3, :3].T + T[index[link], :3, 3])
        pts = np.asarray(points)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        self._backend.frame_camera((lo + hi) / 2, float(np.linalg.norm(hi - lo)) / 2)

    def _from_panel(self, values: dict[str, float]) -> None:
        with self._lock:
            old, self._q = self._q, self._robot.q({**self.joint_values(), **values})
            moved = [n for n, a, b in zip(self._robot.joint_names, old, self._q, strict=True) if a != b]
        self._publish(moved)

    def _publish(self, names: Sequence[str] | None = None) -> None:
        """Publish /joint_states with every joint (as joint_state_publisher does).

        Publishing only the joints that moved would be cheaper, but tf2 looks a chain up at the
        latest time *all* its links share, so stale joints would pin every lookup to the past.
        """
        if names is not None and not names:
            return
        with self._lock:
            self._js_pub.set_positions(self.joint_values())
            self._js_pub.publish()

    def _on_joint_state(self, msg: Any) -> None:
        known = set(self._robot.joint_names)
        values = {n: p for n, p in zip(msg.name, msg.position, strict=False) if n in known}
        if values:
            with self._lock:
                self._q = self._robot.q({**self.joint_values(), **values})
            if self._panel is not None:
                self._panel.show_values(values)

    def _poke(self, msg: Any) -> None:
        with self._edges_lock:
            edges = self._edges
            for t in msg.transforms:
                edges[t.child_frame_id] = t.header.frame_id
        self._wake.set()

    def _take_edges(self, full: bool) -> dict[str, str] | None:
        with self._edges_lock:
            edges, self._edges = self._edges, {}
        return None if full else edges

    def _render_loop(self) -> None:
        pending = False
        while not self._closed:
            woke = self._wake.wait(None if not pending else _TRAILING_S)
            if self._closed:
                return
            self._wake.clear()
            try:
                self._refresh(self._take_edges(full=not woke))
            except Exception as exc:  # keep drawing: report and go on
                print(f"urdftk view: warning: display update failed: {exc}", file=sys.stderr)
            pending = woke
