"""The backend-neutral scene: a mirror of the TF tree, with robot geometry, axes, names and markers.

Every TF frame is a node whose pose is ``T_parent_child`` as TF says it, under its TF parent;
each tree's root node is placed at ``T_fixed_root``, so the whole scene is expressed in the fixed
frame and choosing another fixed frame moves only the root nodes. A joint update therefore sends
one pose per transform that changed, whatever the size of the subtree it moves.

:meth:`Scene.update` reads a ``tf.Buffer`` with one batched lookup per tree and sends only the
poses that changed, in one atomic batch. All methods are thread-safe.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from urdftk.viewer._backend import SceneBackend
from urdftk.viewer._geometry import LinkGeometry, MeshPart
from urdftk.viewer._markers import Marker, marker_items
from urdftk.viewer._poses import matrices_to_pose, rigid_inverse_mul

__all__ = ["ROOT_NODE", "DisplayOptions", "Scene", "node_segment"]

ROOT_NODE = "/tf"
_EPS = 1e-9
_FEW_EDGES = 8  # above this, one batched lookup per tree beats one per parent
_ARROW_RGB = (0.95, 0.75, 0.1)


def node_segment(frame: str) -> str:
    """A frame name made safe as one segment of a scene-node path."""
    return frame.replace("/", "%2F") or "%empty"


@dataclass
class DisplayOptions:
    """What the scene shows (the panel edits these through :meth:`Scene.set_options`)."""

    show_visual: bool = True
    show_collision: bool = False
    alpha: float = 1.0
    show_axes: bool = True
    axes_length: float = 0.1
    show_names: bool = False
    show_arrows: bool = False


class Scene:
    """TF tree + robot geometry + markers, drawn by a :class:`SceneBackend`.

    Args:
        backend: Where to draw.
        fixed_frame: The frame the scene is expressed in (default: the first TF root seen).
        load_mesh: ``callable(resource, rgba) -> list[MeshPart]`` for mesh markers.
    """

    def __init__(
        self,
        backend: SceneBackend,
        fixed_frame: str | None = None,
        load_mesh: Callable[[str, tuple[float, float, float, float]], list[MeshPart]] | None = None,
    ) -> None:
        self._lock = threading.RLock()
        self._backend = backend
        self._fixed = fixed_frame
        self._load_mesh = load_mesh
        self.options = DisplayOptions()
        self._parents: dict[str, str | None] = {}
        self._paths: dict[str, str] = {}
        self._order: list[str] = []
        self._index: dict[str, int] = {}
        self._local = np.zeros((0, 4, 4))
        self._root_visible: dict[str, bool] = {}
        self._geometry: dict[str, dict[str, LinkGeometry]] = {"visual": {}, "collision": {}}
        self._markers: dict[tuple[str, int], Marker] = {}
        self._frame_axes: dict[str, bool] = {}
        self._link_visible: dict[str, bool] = {}
        backend.add_grid("/grid", size=4.0, cell=0.25)

    # ------------------------------------------------------------------ queries
    @property
    def fixed_frame(self) -> str | None:
        """The frame the scene is expressed in."""
        return self._fixed

    def frames(self) -> list[str]:
        """The TF frames mirrored so far, in first-seen order."""
        with self._lock:
            return list(self._order)

    def node_of(self, frame: str) -> str | None:
        """The scene-node path of ``frame`` (None if not in the scene)."""
        with self._lock:
            return self._paths.get(frame)

    def local_pose(self, frame: str) -> np.ndarray | None:
        """The last pose sent for ``frame``'s node: ``T_parent_frame``, or ``T_fixed_frame`` for a root."""
        with self._lock:
            i = self._index.get(frame)
            return None if i is None else self._local[i].copy()

    # ------------------------------------------------------------------ settings
    def set_fixed_frame(self, frame: str) -> None:
        """Express the scene in ``frame`` (takes effect at the next :meth:`update`)."""
        with self._lock:
            self._fixed = frame
            for root in self._root_visible:
                i = self._index[root]
                self._local[i] = np.nan  # force the root poses to be re-sent

    def set_options(self, **changes: object) -> None:
        """Change :class:`DisplayOptions` fields and redraw what they affect."""
        with self._lock:
            old = DisplayOptions(**vars(self.options))
            for key, value in changes.items():
                if not hasattr(self.options, key):
                    raise ValueError(f"unknown display option {key!r}")
                setattr(self.options, key, value)
            o, b = self.options, self._backend
            with b.batch():
                if (o.show_axes, o.axes_length) != (old.show_axes, old.axes_length):
                    for f in self._order:
                        b.set_axes(
                            self._paths[f], o.show_axes and self._frame_axes.get(f, True), o.axes_length
                        )
                if o.show_names != old.show_names:
                    for f in self._order:
                        b.set_visible(self._paths[f] + "/@name", o.show_names)
                if o.show_arrows != old.show_arrows:
                    self._draw_arrows(self._order)
                if (o.show_visual, o.show_collision) != (old.show_visual, old.show_collision):
                    for f in self._order:
                        self._apply_link_visibility(f)
                if o.alpha != old.alpha:
                    for link, geom in self._geometry["visual"].items():
                        if link in self._paths:
                            for i, part in enumerate(geom.parts):
                                b.set_opacity(f"{self._paths[link]}/@visual/{i}", part, o.alpha)

    def set_frame_axes(self, frame: str, show: bool) -> None:
        """Show or hide the axes of one frame."""
        with self._lock:
            self._frame_axes[frame] = show
            if frame in self._paths:
                o = self.options
                self._backend.set_axes(self._paths[frame], o.show_axes and show, o.axes_length)

    def set_link_visible(self, link: str, visible: bool) -> None:
        """Show or hide one link's geometry (its axes and children are unaffected)."""
        with self._lock:
            self._link_visible[link] = visible
            if link in self._paths:
                self._apply_link_visibility(link)

    def set_geometry(self, visual: Mapping[str, LinkGeometry], collision: Mapping[str, LinkGeometry]) -> None:
        """Replace the robot geometry (per link name = TF frame name)."""
        with self._lock, self._backend.batch():
            for kind in ("visual", "collision"):
                for link in self._geometry[kind]:
                    if link in self._paths:
                        self._backend.remove(f"{self._paths[link]}/@{kind}")
            self._geometry = {"visual": dict(visual), "collision": dict(collision)}
            for f in self._order:
                self._add_geometry(f)

    # ------------------------------------------------------------------ markers
    def add_marker(self, marker: Marker) -> None:
        """Add or replace the marker ``(marker.ns, marker.id)``; drawn once its frame is in TF."""
        items = marker_items(
            marker, (lambda res: self._load_mesh(res, marker.color)) if self._load_mesh else None
        )
        with self._lock, self._backend.batch():
            self._remove_marker_node(marker.key)
            self._markers[marker.key] = marker
            self._draw_marker(marker, items)

    def remove_marker(self, ns: str, id: int) -> None:
        """Remove a marker (no error if absent)."""
        with self._lock:
            self._remove_marker_node((ns, id))
            self._markers.pop((ns, id), None)

    def _marker_node(self, marker: Marker) -> str | None:
        parent = self._paths.get(marker.frame_id)
        return None if parent is None else f"{parent}/@markers/{node_segment(marker.ns)}:{marker.id}"

    def _remove_marker_node(self, key: tuple[str, int]) -> None:
        old = self._markers.get(key)
        node = self._marker_node(old) if old else None
        if node:
            self._backend.remove(node)

    def _draw_marker(self, marker: Marker, items: list | None = None) -> None:
        node = self._marker_node(marker)
        if node is None:
            return
        if items is None:
            items = marker_items(
                marker, (lambda res: self._load_mesh(res, marker.color)) if self._load_mesh else None
            )
        b = self._backend
        b.add_frame(
            node, np.asarray(marker.position), np.asarray(marker.orientation), show_axes=False, axes_length=0
        )
        for i, item in enumerate(items):
            if item.kind == "mesh":
                b.add_mesh(f"{node}/{i}", item.part, opacity=marker.color[3])
            elif item.kind == "label":
                b.add_label(f"{node}/{i}", item.text)
            else:
                b.add_lines(f"{node}/{i}", item.segments, marker.color[:3], width=item.width)

    # ------------------------------------------------------------------ drawing helpers
    def _apply_link_visibility(self, f: str) -> None:
        o, shown = self.options, self._link_visible.get(f, True)
        if f in self._geometry["visual"]:
            self._backend.set_visible(f"{self._paths[f]}/@visual", o.show_visual and shown)
        if f in self._geometry["collision"]:
            self._backend.set_visible(f"{self._paths[f]}/@collision", o.show_collision and shown)

    def _add_geometry(self, f: str) -> None:
        node, o, b = self._paths[f], self.options, self._backend
        shown = self._link_visible.get(f, True)
        for kind, on in (("visual", o.show_visual), ("collision", o.show_collision)):
            geom = self._geometry[kind].get(f)
            if geom is None:
                continue
            b.add_group(f"{node}/@{kind}", visible=on and shown)
            alpha = o.alpha if kind == "visual" else 0.85
            for i, part in enumerate(geom.parts):
                b.add_mesh(f"{node}/@{kind}/{i}", part, opacity=alpha)

    def _draw_arrows(self, frames: list[str]) -> None:
        b = self._backend
        for f in frames:
            p = self._parents.get(f)
            if p is None or p not in self._paths:
                continue
            name = f"{self._paths[p]}/@arrow/{node_segment(f)}"
            t = self._local[self._index[f], :3, 3]
            if not self.options.show_arrows or not np.all(np.isfinite(t)) or float(np.linalg.norm(t)) < 1e-6:
                b.remove(name)
                continue
            seg = np.stack([np.zeros(3), t])[None].astype(np.float32)
            b.add_lines(name, seg, _ARROW_RGB, width=max(self.options.axes_length * 0.05, 0.002))

    def _build_frame(self, f: str) -> None:
        node, o = self._paths[f], self.options
        b = self._backend
        b.add_frame(
            node, np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]),
            show_axes=o.show_axes and self._frame_axes.get(f, True), axes_length=o.axes_length,
        )  # fmt: skip
        b.add_label(node + "/@name", f, visible=o.show_names)
        self._add_geometry(f)
        for marker in self._markers.values():
            if marker.frame_id == f:
                self._draw_marker(marker)

    # ------------------------------------------------------------------ structure
    @staticmethod
    def _path_of(f: str, parents: Mapping[str, str | None], memo: dict[str, str]) -> str:
        chain: list[str] = []
        g = f
        while g not in memo:
            chain.append(g)
            p = parents.get(g)
            if p is None or p not in parents or len(chain) > len(parents):
                base = ROOT_NODE
                break
            g = p
        else:
            base = memo[g]
        for h in reversed(chain):
            base = f"{base}/{node_segment(h)}"
            memo[h] = base
        return memo[f]

    def _restructure(self, frames: list[str], parents: dict[str, str | None]) -> None:
        memo: dict[str, str] = {}
        paths = {f: self._path_of(f, parents, memo) for f in frames}
        changed = [f for f in frames if self._paths.get(f) != paths[f]]
        gone = [f for f in self._paths if f not in paths]
        b = self._backend
        for f in changed + gone:
            if f in self._paths:
                b.remove(self._paths[f])
        old_local = {f: self._local[i] for f, i in self._index.items()}
        self._parents, self._paths, self._order = dict(parents), paths, list(frames)
        self._index = {f: i for i, f in enumerate(frames)}
        self._local = np.full((len(frames), 4, 4), np.nan)
        for f, i in self._index.items():
            if f not in changed and f in old_local:
                self._local[i] = old_local[f]
        self._root_visible = {f: self._root_visible.get(f, True) for f in frames if parents.get(f) is None}
        for f in sorted(changed, key=lambda g: paths[g].count("/")):
            self._build_frame(f)

    # ------------------------------------------------------------------ update
    def update(self, buffer: object, edges: Mapping[str, str] | None = None) -> tuple[int, bool]:
        """Bring the scene up to date with ``buffer`` (a ``tf.Buffer``).

        Args:
            buffer: The TF buffer.
            edges: ``{child: parent}`` of the transforms received since the last update; only
                those are looked up (plus the roots' poses in the fixed frame). None: everything.

        Returns:
            ``(number of poses sent, whether frames were added or re-parented)``.
        """
        with self._lock, self._backend.batch():
            known = edges is not None and all(
                self._parents.get(c.lstrip("/"), "") == p.lstrip("/") for c, p in edges.items()
            )
            if known and self._fixed is not None:
                if len(edges) > _FEW_EDGES:  # type: ignore[arg-type]
                    return self._apply(np.arange(len(self._order)), self._compute_local(buffer), False), False
                rows = self._edge_rows(buffer, edges)  # type: ignore[arg-type]
                return self._apply(rows[0], rows[1], False), False
            frames = buffer.frames()  # type: ignore[attr-defined]
            parents = {f: buffer.get_parent(f) for f in frames}  # type: ignore[attr-defined]
            restructured = frames != self._order or parents != self._parents
            if restructured:
                self._restructure(frames, parents)
            if not frames:
                return 0, restructured
            if self._fixed is None:
                self._fixed = next(f for f in frames if parents[f] is None)
            new = self._compute_local(buffer)
            return self._apply(np.arange(len(frames)), new, restructured), restructured

    def _apply(self, rows: np.ndarray, new: np.ndarray, restructured: bool) -> int:
        """Send the poses of ``rows`` (indices into the frame order) that differ from what was sent."""
        old = self._local[rows]
        changed = ~np.all(np.abs(new - old) <= _EPS, axis=(1, 2)) & np.all(np.isfinite(new), axis=(1, 2))
        sel = np.flatnonzero(changed)
        idx = rows[sel]
        moved_t = [
            self._order[i]
            for i, k in zip(idx, sel, strict=True)
            if not np.allclose(new[k, :3, 3], old[k, :3, 3])
        ]
        self._local[idx] = new[sel]
        if len(idx):
            pos, quat = matrices_to_pose(new[sel])
            self._backend.set_poses([self._paths[self._order[i]] for i in idx], pos, quat)
        for root in self._root_visible:
            i = self._index[root]
            hit = np.flatnonzero(rows == i)
            if not len(hit):
                continue
            ok = bool(np.all(np.isfinite(new[hit[0]])))
            if ok != self._root_visible[root] or restructured:
                self._root_visible[root] = ok
                self._backend.set_visible(self._paths[root], ok)
        if self.options.show_arrows and (moved_t or restructured):
            self._draw_arrows(self._order if restructured else moved_t)
        return len(idx)

    def _edge_rows(self, buffer: object, edges: Mapping[str, str]) -> tuple[np.ndarray, np.ndarray]:
        """Look up only the received edges (grouped by parent) and every root in the fixed frame."""
        lookup = buffer.lookup_transforms  # type: ignore[attr-defined]
        by_parent: dict[str, list[str]] = {}
        for child, parent in edges.items():
            by_parent.setdefault(parent.lstrip("/"), []).append(child.lstrip("/"))
        rows: list[int] = []
        mats: list[np.ndarray] = []
        for parent, children in by_parent.items():
            rows.extend(self._index[c] for c in children)
            mats.append(lookup(parent, children, fill_missing=True))
        roots = list(self._root_visible)
        rows.extend(self._index[r] for r in roots)
        mats.append(lookup(self._fixed, roots, fill_missing=True))
        return np.asarray(rows, dtype=np.intp), np.concatenate(mats)

    def _compute_local(self, buffer: object) -> np.ndarray:
        """``T_parent_f`` for every frame (``T_fixed_f`` for roots); NaN where TF cannot say."""
        n = len(self._order)
        out = np.full((n, 4, 4), np.nan)
        roots: dict[str, list[int]] = {}
        for i, f in enumerate(self._order):
            g, hops = f, 0
            while self._parents.get(g) is not None and hops <= n:
                g, hops = self._parents[g], hops + 1  # type: ignore[assignment]
            roots.setdefault(g, []).append(i)
        lookup = buffer.lookup_transforms  # type: ignore[attr-defined]
        for root, members in roots.items():
            names = [self._order[i] for i in members]
            T_root = lookup(root, names, fill_missing=True)
            pos = {f: k for k, f in enumerate(names)}
            child = [k for k, f in enumerate(names) if self._parents.get(f) is not None]
            if child:
                par = [pos[self._parents[names[k]]] for k in child]  # type: ignore[index]
                out[[members[k] for k in child]] = rigid_inverse_mul(T_root[par], T_root[child])
        root_names = list(roots)
        T_fixed = lookup(self._fixed, root_names, fill_missing=True)
        out[[self._index[r] for r in root_names]] = T_fixed
        return out
