"""The viser control panel: joint sliders (joint_state_publisher_gui) and rviz-like display options.

The panel holds no robot state of its own: sliders call ``on_joints(values)`` with a dict of
independent joint values, and display options go straight to the :class:`~urdftk.viewer._scene.Scene`.
Values assigned from Python (``client is None``) never echo back as user input.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from urdftk.viewer._scene import Scene

__all__ = ["Panel"]

_CONTINUOUS_RANGE = math.pi
_UNBOUNDED_PRISMATIC = 1.0


def _slider_range(lower: float, upper: float, continuous: bool) -> tuple[float, float]:
    if continuous or not (math.isfinite(lower) and math.isfinite(upper)):
        if continuous:
            return -_CONTINUOUS_RANGE, _CONTINUOUS_RANGE
        return -_UNBOUNDED_PRISMATIC, _UNBOUNDED_PRISMATIC
    if upper <= lower:
        return lower - 1e-3, lower + 1e-3
    return lower, upper


class Panel:
    """Builds and owns the GUI controls of one viewer.

    Args:
        server: The ``viser.ViserServer``.
        scene: The scene whose display options the controls change.
        on_joints: Called with ``{joint: value}`` when the user moves a slider or presses a button.
        on_fixed_frame: Called with a frame name when the user picks a fixed frame.
        listen: True when joint values come from the network (sliders are read-only).
    """

    def __init__(
        self,
        server: Any,
        scene: Scene,
        on_joints: Callable[[dict[str, float]], None],
        on_fixed_frame: Callable[[str], None],
        *,
        listen: bool = False,
    ) -> None:
        self._server = server
        self._scene = scene
        self._on_joints = on_joints
        self._on_fixed_frame = on_fixed_frame
        self._listen = listen
        self._sliders: dict[str, Any] = {}
        self._joint_folder: Any = None
        self._frame_boxes: dict[str, Any] = {}
        self._link_boxes: dict[str, Any] = {}
        self._neutral: dict[str, float] = {}
        self._robot: Any = None
        self._lock = threading.RLock()  # GUI containers may be entered by one thread at a time
        gui = server.gui
        self._tabs = gui.add_tab_group(order=0)
        self._joints_tab = self._tabs.add_tab("Joints")
        self._display_tab = self._tabs.add_tab("Display")
        self._build_display()

    # ------------------------------------------------------------------ joints
    def set_robot(self, robot: Any, values: Mapping[str, float]) -> None:
        """(Re)build the joint sliders for ``robot``, starting at ``values``."""
        with self._lock:
            self._build_joints(robot, values)

    def _build_joints(self, robot: Any, values: Mapping[str, float]) -> None:
        self._robot = robot
        if self._joint_folder is not None:
            self._joint_folder.remove()
        self._sliders = {}
        gui = self._server.gui
        neutral = robot.neutral()
        self._neutral = {n: float(v) for n, v in zip(robot.joint_names, neutral, strict=True)}
        with self._joints_tab, gui.add_folder("Joints", order=1) as folder:
            self._joint_folder = folder
            if not self._listen:
                random_b = gui.add_button("Randomize")
                center_b = gui.add_button("Center")
                random_b.on_click(lambda _e: self._randomize())
                center_b.on_click(lambda _e: self._center())
            lower, upper = robot.limits.lower, robot.limits.upper
            continuous = self._continuous(robot)
            for i, name in enumerate(robot.joint_names):
                lo, hi = _slider_range(float(lower[i]), float(upper[i]), name in continuous)
                value = float(np.clip(values.get(name, self._neutral[name]), lo, hi))
                slider = gui.add_slider(
                    name, min=lo, max=hi, step=(hi - lo) / 1000.0, initial_value=value, disabled=self._listen
                )
                slider.on_update(self._slider_changed)
                self._sliders[name] = slider

    @staticmethod
    def _continuous(robot: Any) -> set[str]:
        joints = getattr(robot.description, "joint_map", {})
        return {n for n, j in joints.items() if getattr(j, "type", "") == "continuous"}

    def _slider_changed(self, event: Any) -> None:
        if event.client is None:  # assigned from Python: not user input
            return
        self._on_joints({n: float(s.value) for n, s in self._sliders.items()})

    def show_values(self, values: Mapping[str, float]) -> None:
        """Move the sliders to ``values`` without reporting them as user input."""
        with self._server.atomic():
            for name, value in values.items():
                slider = self._sliders.get(name)
                if slider is not None:
                    v = float(min(max(value, slider.min), slider.max))
                    if v != slider.value:
                        slider.value = v

    def _push(self, values: dict[str, float]) -> None:
        self.show_values(values)
        self._on_joints({n: float(s.value) for n, s in self._sliders.items()})

    def _randomize(self) -> None:
        rng = np.random.default_rng()
        values = {n: float(rng.uniform(s.min, s.max)) for n, s in self._sliders.items()}
        self._push(values)

    def _center(self) -> None:
        values = {
            n: (s.min + s.max) / 2 if n not in self._neutral else self._neutral[n]
            for n, s in self._sliders.items()
        }
        self._push(
            {n: float(np.clip(v, self._sliders[n].min, self._sliders[n].max)) for n, v in values.items()}
        )

    # ------------------------------------------------------------------ display
    def _build_display(self) -> None:
        gui, scene = self._server.gui, self._scene
        o = scene.options
        with self._display_tab:
            self._fixed = gui.add_dropdown("Fixed frame", options=(scene.fixed_frame or "(none)",))
            self._fixed.on_update(
                lambda e: e.client is not None and self._on_fixed_frame(str(self._fixed.value))
            )
            with gui.add_folder("Robot model"):
                visual = gui.add_checkbox("Visual", o.show_visual)
                collision = gui.add_checkbox("Collision", o.show_collision)
                alpha = gui.add_slider("Alpha", min=0.0, max=1.0, step=0.05, initial_value=o.alpha)
                visual.on_update(lambda _e: scene.set_options(show_visual=bool(visual.value)))
                collision.on_update(lambda _e: scene.set_options(show_collision=bool(collision.value)))
                alpha.on_update(lambda _e: scene.set_options(alpha=float(alpha.value)))
                self._links_folder = gui.add_folder("Links", expand_by_default=False)
            with gui.add_folder("TF"):
                axes = gui.add_checkbox("Show axes", o.show_axes)
                size = gui.add_slider("Axes size", min=0.01, max=0.5, step=0.01, initial_value=o.axes_length)
                names = gui.add_checkbox("Show names", o.show_names)
                arrows = gui.add_checkbox("Show arrows", o.show_arrows)
                axes.on_update(lambda _e: scene.set_options(show_axes=bool(axes.value)))
                size.on_update(lambda _e: scene.set_options(axes_length=float(size.value)))
                names.on_update(lambda _e: scene.set_options(show_names=bool(names.value)))
                arrows.on_update(lambda _e: scene.set_options(show_arrows=bool(arrows.value)))
                self._frames_folder = gui.add_folder("Frames", expand_by_default=False)

    def set_frames(self, frames: Sequence[str], links: Sequence[str]) -> None:
        """Refresh the fixed-frame choices, the per-frame axes boxes and the per-link boxes."""
        with self._lock:
            self._add_frame_boxes(frames, links)

    def _add_frame_boxes(self, frames: Sequence[str], links: Sequence[str]) -> None:
        gui, scene = self._server.gui, self._scene
        options = tuple(frames) or ("(none)",)
        if tuple(self._fixed.options) != options:
            current = scene.fixed_frame
            self._fixed.options = options
            if current in options:
                self._fixed.value = current
        with self._frames_folder:
            for f in frames:
                if f not in self._frame_boxes:
                    box = gui.add_checkbox(f, True)
                    box.on_update(lambda _e, f=f, box=box: scene.set_frame_axes(f, bool(box.value)))
                    self._frame_boxes[f] = box
        with self._links_folder:
            for link in links:
                if link not in self._link_boxes:
                    box = gui.add_checkbox(link, True)
                    box.on_update(
                        lambda _e, link=link, box=box: scene.set_link_visible(link, bool(box.value))
                    )
                    self._link_boxes[link] = box

    def show_fixed_frame(self, frame: str) -> None:
        """Reflect a fixed frame chosen from Python in the dropdown."""
        if frame in self._fixed.options:
            self._fixed.value = frame
