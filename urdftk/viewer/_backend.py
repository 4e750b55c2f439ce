"""The interface a display backend (viser, meshcat) implements for the scene layer.

Node names are ``/``-separated paths; a node's pose is relative to its parent node, as in a
scene graph. Poses cross this interface as a position and an **xyzw** quaternion; a backend that
wants another order (viser: wxyz) converts on its side.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from contextlib import AbstractContextManager

import numpy as np

from urdftk.viewer._geometry import MeshPart

__all__ = ["SceneBackend"]


class SceneBackend(ABC):
    """A 3D scene in a browser: nodes with poses, meshes, labels, lines and a grid."""

    @property
    @abstractmethod
    def url(self) -> str:
        """The address to open in a browser."""

    @abstractmethod
    def batch(self) -> AbstractContextManager[None]:
        """A context in which every change is sent to the browser as one atomic update."""

    @abstractmethod
    def add_frame(
        self, name: str, position: np.ndarray, xyzw: np.ndarray, *, show_axes: bool, axes_length: float
    ) -> None:
        """Add (or replace) a coordinate-frame node, optionally drawn as RGB axes."""

    @abstractmethod
    def set_poses(self, names: Sequence[str], positions: np.ndarray, xyzw: np.ndarray) -> None:
        """Move nodes: ``positions`` (n, 3), ``xyzw`` (n, 4), relative to each node's parent."""

    @abstractmethod
    def set_axes(self, name: str, show: bool, axes_length: float) -> None:
        """Show or hide the axes of a frame node and set their length."""

    @abstractmethod
    def add_group(self, name: str, *, visible: bool = True) -> None:
        """Add an empty node used to show or hide its children together."""

    @abstractmethod
    def add_mesh(self, name: str, part: MeshPart, *, opacity: float = 1.0, visible: bool = True) -> None:
        """Add a triangle mesh node (identity pose relative to its parent)."""

    @abstractmethod
    def set_opacity(self, name: str, part: MeshPart, opacity: float) -> None:
        """Change a mesh node's opacity (1 is opaque)."""

    @abstractmethod
    def add_label(self, name: str, text: str, *, visible: bool = True) -> None:
        """Add a text label at the parent node's origin."""

    @abstractmethod
    def add_lines(
        self,
        name: str,
        segments: np.ndarray,
        rgb: tuple[float, float, float],
        *,
        width: float,
        visible: bool = True,
    ) -> None:
        """Add line segments, ``segments`` (n, 2, 3) in the parent node's frame."""

    @abstractmethod
    def add_grid(self, name: str, *, size: float, cell: float) -> None:
        """Add a ground grid on the xy plane of the root."""

    @abstractmethod
    def set_visible(self, name: str, visible: bool) -> None:
        """Show or hide a node and everything under it."""

    @abstractmethod
    def remove(self, name: str) -> None:
        """Remove a node and everything under it (no error if absent)."""

    @abstractmethod
    def show_status(self, text: str, *, error: bool) -> None:
        """Show a message to the user in the page (empty text clears it)."""

    def frame_camera(self, center: np.ndarray, radius: float) -> None:  # noqa: B027 - optional
        """Point the initial camera at a sphere (``center``, ``radius``) in the root frame."""

    @abstractmethod
    def close(self) -> None:
        """Stop serving."""
