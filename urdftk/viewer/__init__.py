"""The browser viewer: robot geometry, TF frames and markers, driven by a ``tf.Buffer``.

``Viewer`` serves a page (viser by default, meshcat on request) showing a robot with its meshes
and colours, joint sliders, TF axes, names and arrows, a choice of fixed frame, and rviz-style
markers. See :class:`Viewer`.
"""

from __future__ import annotations

from urdftk.viewer._markers import MARKER_TYPES, Marker
from urdftk.viewer._viewer import Viewer

__all__ = ["MARKER_TYPES", "Marker", "Viewer"]
