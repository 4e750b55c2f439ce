"""The :class:`Robot`: a Pinocchio model with named joints and frames, built from a Description.

Coordinates (``q``, in the order of :attr:`Robot.joint_names`):

* revolute and continuous joints: one angle in radians (continuous joints are unbounded; Pinocchio's
  ``(cos, sin)`` pair stays inside);
* prismatic joints: one displacement in metres;
* ``planar`` joints: ``<joint>/x``, ``<joint>/y`` (metres) and ``<joint>/theta`` (radians), motion in
  the x-y plane of the joint frame (Pinocchio's convention; the URDF ``<axis>`` of a planar joint is
  not used);
* ``floating`` joints and the ``floating_base=True`` free-flyer (named ``root_joint``):
  ``<joint>/x``, ``/y``, ``/z`` (metres, in the parent frame) then ``/qx``, ``/qy``, ``/qz``, ``/qw``
  (the orientation as an xyzw quaternion, normalized before use);
* mimic joints have no coordinate: ``follower = multiplier * master + offset`` (see
  :mod:`urdftk._mimic`; chains resolve to the root master).

FK, Jacobians and the centre of mass accept any finite configuration (arrays, or mappings as
:meth:`Robot.q` reads them); only :meth:`Robot.q` enforces limits.

Poses are ``T_root_link`` 4x4 float64 arrays: in the root link's frame for a fixed base, in the
world frame (:attr:`Robot.world_frame`) with a floating base.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from urdftk import kinematics
from urdftk._config import ConfigSpace, Limits
from urdftk._engine import Engine, Kernels
from urdftk._pinmap import check_joints, frame_ids
from urdftk._structure import build_structure
from urdftk.description import Description
from urdftk.errors import ConfigurationError, DescriptionError, LinkNotFound
from urdftk.pose import Pose
from urdftk.resources import PackageResolver

__all__ = ["Limits", "Robot"]

_PIN_FK_MAX_NV = 300
"""Above this many velocity coordinates, FK without numba uses our own code (Pinocchio's Data is O(nv^3))."""
_REFERENCES = ("world", "local", "local_world_aligned")


class Robot:
    """A robot model with a named-joint API: configurations, FK, Jacobians, batched FK.

    Build it with :func:`urdftk.load`. Attributes follow the team's Robot contract: ``name``,
    ``source``, ``urdf_text``, ``resolver``, ``description`` (yourdfpy), ``model`` (Pinocchio),
    ``link_names``, ``root_link``, ``joint_names``, ``mimic``, ``limits``; plus ``parsed`` (the
    :class:`~urdftk.description.Description` with element line numbers) and ``world_frame``.

    Example:
        >>> import urdftk  # doctest: +SKIP
        >>> robot = urdftk.load("examples/robots/robot0_description/urdf/robot0.urdf")  # doctest: +SKIP
        >>> robot.frame_pose("end_effector", {"joint_1": 0.5})  # doctest: +SKIP
    """

    def __init__(self, description: Description, *, resolver: PackageResolver, floating_base: bool = False):
        """Build the Pinocchio model from ``description.text`` and index names.

        Args:
            description: The parsed description.
            resolver: The package resolver used to load it (kept for meshes).
            floating_base: Put a free-flyer (``root_joint``) between the world and the root link.

        Raises:
            DescriptionError: If Pinocchio cannot build the model, or a mimic is invalid.
        """
        import pinocchio as pin

        self.parsed = description
        self.name: str = description.name
        self.source: Path | None = Path(description.filename) if description.filename else None
        self.urdf_text: str = description.text
        self.resolver = resolver
        self.floating_base = floating_base
        self._s = s = build_structure(description, floating_base)
        try:
            root_joint = (pin.JointModelFreeFlyer(),) if floating_base else ()
            self.model = pin.buildModelFromXML(description.text, *root_joint)
        except Exception as exc:  # Pinocchio raises bare ValueError/RuntimeError
            raise DescriptionError(f"Pinocchio cannot build the model: {exc}", description.filename) from None
        check_joints(s, self.model, description.filename)
        self.link_names: tuple[str, ...] = s.link_names
        self.root_link: str = s.link_names[0]
        self.world_frame: str | None = s.world_frame
        self.joint_names: tuple[str, ...] = s.coord_names
        self._link_index = {n: i for i, n in enumerate(s.link_names)}
        self._frame_id = frame_ids(self.model, s.link_names, pin.BODY, description.filename)
        self._all_links = np.arange(s.n_links)
        self._engine = Engine(self.name, s, self.model, description.filename)
        self._kern: Kernels | None = None

    @functools.cached_property  # this and the next two: built on first use (twice is harmless)
    def _cfg(self) -> ConfigSpace:
        return ConfigSpace(self.name, self._s)

    @functools.cached_property
    def mimic(self) -> dict[str, tuple[str, float, float]]:
        """Mimic follower -> ``(master, multiplier, offset)`` (chains resolved to the root master)."""
        return self._cfg.mimic

    @functools.cached_property
    def limits(self) -> Limits:
        """Joint limits over :attr:`joint_names`."""
        return self._cfg.limits

    @property
    def description(self) -> Any:
        """The yourdfpy ``URDF`` parsed from :attr:`urdf_text` (meshes not loaded), built on first use.

        yourdfpy (and trimesh behind it) are imported and run only when something needs them,
        such as the viewer's mesh loading; kinematics never does.
        """
        return self.parsed.urdf

    # ----------------------------------------------------------------- configurations
    @property
    def dof(self) -> int:
        """Number of coordinates (``len(joint_names)``)."""
        return len(self.joint_names)

    @property
    def mass(self) -> float:
        """Total mass in kg (sum of every link's ``<inertial><mass>``)."""
        return float(sum(inertia.mass for inertia in self.model.inertias))

    def neutral(self) -> np.ndarray:
        """Return the neutral configuration: zero clipped into the limits, identity quaternions."""
        return self._cfg.neutral()

    def random(self, rng: np.random.Generator | int | None = None, size: int | None = None) -> np.ndarray:
        """Draw configurations uniformly within the limits.

        Angles whose range is wider than a turn are drawn over one turn (within [-pi, pi] where the
        limits allow), unbounded positions over 2 m (within [-1, 1] where allowed), and quaternions
        uniformly on the unit sphere.

        Args:
            rng: A numpy Generator, or a seed.
            size: Number of configurations; None for one.

        Returns:
            A (dof,) configuration, or (size, dof) configurations (ready for :meth:`fk_batch`).
        """
        gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
        return self._cfg.random(gen, size)

    def q(self, value: Mapping[str, float] | Sequence[float] | np.ndarray, clip: bool = False) -> np.ndarray:
        """Convert a configuration given by name or as an array into a checked (dof,) array.

        Args:
            value: ``{joint: value}`` (joints not given take their neutral value; mimic followers
                may be given and must agree with their master), or an array in ``joint_names`` order.
            clip: Clip out-of-limit values into the limits instead of raising.

        Returns:
            A new float64 array; quaternion coordinates are normalized.

        Raises:
            JointNotFound: For an unknown joint name.
            ConfigurationError: Wrong length, non-finite value, out of limits, or mimic disagreement.
        """
        return self._cfg.check(value, clip)

    def _coerce(self, q: Any) -> np.ndarray:
        """Shape- and finiteness-checked float64 coordinates; limits are not enforced here."""
        return self._cfg.coerce(q)

    def joint_positions(self, q: Any) -> dict[str, float]:
        """Return the value of every one-coordinate movable joint, mimic followers included.

        This is what ``/joint_states`` carries. Floating and planar joints are left out.

        Args:
            q: A configuration (array or mapping, as :meth:`q` accepts).

        Returns:
            ``{joint_name: value}`` in link (depth-first) order.
        """
        u = self._coerce(q)
        s = self._s
        return {
            r.name: float(s.mult[r.link] * u[r.coord] + s.off[r.link])
            for r in s.joints
            if r.type in ("revolute", "continuous", "prismatic")
        }

    # ----------------------------------------------------------------- frames
    def _link(self, name: str) -> int:
        try:
            return self._link_index[name]
        except KeyError:
            raise LinkNotFound(name, self.link_names) from None

    def _kernels(self) -> Kernels | None:
        """Look up (and cache on the robot) the compiled single-configuration kernels."""
        self._kern = self._engine.kernels()
        return self._kern

    def fk(self, q: Any, *, backend: kinematics.Backend = "auto") -> np.ndarray:
        """Return every link pose ``T_root_link``.

        With numba installed (and ``backend`` ``"auto"`` or ``"numba"``) one compiled call computes
        every pose; otherwise the numpy batch code runs with one configuration.

        Args:
            q: A configuration (array in ``joint_names`` order, or a mapping).
            backend: Batched-FK backend (``"auto"``, ``"numba"``, ``"numpy"``).

        Returns:
            (n_links, 4, 4) float64 array, rows in :attr:`link_names` order.
        """
        kern = (self._kern or self._kernels()) if backend in ("auto", "numba") else None
        if kern is not None:
            out = np.empty((self._s.n_links, 4, 4))
            try:
                status = kern.one_all(q, kern.pk, out)
            except TypeError:  # not a float64 vector (a mapping, a list, another dtype): convert
                status = kern.one_all(self._cfg.coerce(q, False), kern.pk, out)
            if status:
                self._cfg.coerce(q)  # raises the shape or finiteness error
            return out
        u = self._coerce(q)
        out = np.empty((1, self._s.n_links, 4, 4))
        kinematics.fk_batch(self._s, u[None, :], self._all_links, out, backend, plan=self._engine.plan())
        return out[0]

    def frame_pose(self, name: str, q: Any) -> np.ndarray:
        """Return ``T_root_name`` of one link (4x4 float64).

        Only the link's chain is computed: by a compiled kernel when numba is installed, by
        Pinocchio otherwise.

        Args:
            name: A link name (or :attr:`world_frame` with a floating base).
            q: A configuration.

        Raises:
            LinkNotFound: For an unknown name, listing the valid ones.
        """
        i = self._link_index.get(name)
        if i is None:
            if name == self.world_frame and name is not None:
                self._coerce(q)
                return np.eye(4)
            raise LinkNotFound(name, self.link_names)
        kern = self._kern or self._kernels()
        if kern is not None:
            out = np.empty((4, 4))
            try:
                status = kern.one_link(q, kern.pk, i, out)
            except TypeError:  # not a float64 vector (a mapping, a list, another dtype): convert
                status = kern.one_link(self._cfg.coerce(q, False), kern.pk, i, out)
            if status:
                self._cfg.coerce(q)  # raises the shape or finiteness error
            return out
        u = self._coerce(q)
        if self.model.nv > _PIN_FK_MAX_NV:
            return kinematics.fk_chain(self._s, kinematics.local_transforms(self._s, u), i)
        import pinocchio as pin

        pq = self._engine.pinmap().to_pin(u)
        with self._engine.lock:
            pin.forwardKinematics(self.model, self._engine.pin_data(), pq)
            return pin.updateFramePlacement(
                self.model, self._engine.pin_data(), self._frame_id[name]
            ).homogeneous

    def pose(self, name: str, q: Any) -> Pose:
        """Return :meth:`frame_pose` as an immutable :class:`~urdftk.pose.Pose`."""
        return Pose(self.frame_pose(name, q))

    def transform(self, a: str, b: str, q: Any) -> np.ndarray:
        """Return ``T_a_b``, the pose of frame ``b`` in frame ``a`` (4x4)."""
        T_r_a = self.frame_pose(a, q)
        T_r_b = self.frame_pose(b, q)
        T_a_r = np.eye(4)
        T_a_r[:3, :3] = T_r_a[:3, :3].T
        T_a_r[:3, 3] = -T_r_a[:3, :3].T @ T_r_a[:3, 3]
        return T_a_r @ T_r_b

    def joint_transforms(self, q: Any) -> list[tuple[str, str, np.ndarray]]:
        """Return ``(parent_link, child_link, T_parent_child)`` for every movable joint (mimic included).

        With a floating base the first entry is ``(world_frame, root_link, T_world_root)``.
        """
        u = self._coerce(q)
        local = kinematics.local_transforms(self._s, u)
        return [(r.parent, r.child, local[r.link].copy()) for r in self._s.joints if r.type != "fixed"]

    def fixed_transforms(self) -> list[tuple[str, str, np.ndarray]]:
        """Return ``(parent_link, child_link, T_parent_child)`` for every fixed joint."""
        local = kinematics.local_transforms(self._s, self.neutral())
        return [(r.parent, r.child, local[r.link].copy()) for r in self._s.joints if r.type == "fixed"]

    # ----------------------------------------------------------------- derivatives and mass
    def jacobian(self, frame: str, q: Any, reference: str = "world") -> np.ndarray:
        """Return the (6, dof) Jacobian of a link frame with respect to ``q`` (linear rows first).

        Column ``j`` is the frame's spatial velocity for ``dq_j = 1``, with mimic followers moving
        with their master. ``reference`` follows Pinocchio:

        * ``"world"``: the spatial velocity in the world (root) frame, its linear part being the
          velocity of the point at the world origin;
        * ``"local"``: the body velocity, in the frame's own axes;
        * ``"local_world_aligned"``: the velocity of the frame's origin and its angular velocity, in
          world axes (``d translation / dq`` on top).

        Raises:
            LinkNotFound: For an unknown frame.
            ValueError: For an unknown ``reference``.
            KinematicsError: If the robot is too large for Pinocchio's Data.
        """
        import pinocchio as pin

        if reference not in _REFERENCES:
            raise ConfigurationError(f"reference must be one of {', '.join(_REFERENCES)}, not {reference!r}")
        self._link(frame)
        u = self._coerce(q)
        rf = getattr(pin.ReferenceFrame, reference.upper())  # WORLD, LOCAL, LOCAL_WORLD_ALIGNED
        pmap = self._engine.pinmap()
        with self._engine.lock:
            data = self._engine.pin_data()
            J = pin.computeFrameJacobian(self.model, data, pmap.to_pin(u), self._frame_id[frame], rf)
        return np.asarray(J).reshape(6, self.model.nv) @ pmap.velocity_map(u)

    def com(self, q: Any) -> np.ndarray:
        """Return the centre of mass (3,) in the root (world) frame, metres."""
        import pinocchio as pin

        u = self._coerce(q)
        pq = self._engine.pinmap().to_pin(u)
        with self._engine.lock:
            return np.array(pin.centerOfMass(self.model, self._engine.pin_data(), pq))

    # ----------------------------------------------------------------- batched FK
    def fk_batch(
        self,
        Q: np.ndarray,
        links: Sequence[str] | None = None,
        dtype: type | np.dtype = np.float64,
        out: np.ndarray | None = None,
        *,
        backend: kinematics.Backend = "auto",
    ) -> np.ndarray:
        """Compute link poses for many configurations at once (vectorized; no loop per configuration).

        Args:
            Q: (N, dof) configurations in ``joint_names`` order (not limit-checked; quaternions are
                normalized).
            links: Link names to return, in this order; all links when None.
            dtype: ``np.float64`` or ``np.float32`` output.
            out: Optional C-contiguous (N, n_links, 4, 4) array of that dtype to fill.
            backend: ``"auto"`` (numba when installed), ``"numba"`` or ``"numpy"``.

        Returns:
            (N, n_links, 4, 4) poses ``T_root_link``.

        Raises:
            ConfigurationError: Wrong shapes, dtypes or non-finite values.
            LinkNotFound: For an unknown link name.
        """
        dt = np.dtype(dtype)
        if dt not in (np.dtype(np.float64), np.dtype(np.float32)):
            raise ConfigurationError(f"dtype must be float64 or float32, not {dt}")
        Qa = np.ascontiguousarray(Q, dtype=np.float64)
        if Qa.ndim != 2 or Qa.shape[1] != self.dof:
            raise ConfigurationError(f"{self.name}: Q must have shape (N, {self.dof}), got {np.shape(Q)}")
        if not np.all(np.isfinite(Qa)):
            raise ConfigurationError(f"{self.name}: Q contains NaN or inf")
        if links is None:
            idx, plan = self._all_links, self._engine.plan()
        else:
            if isinstance(links, str):
                raise ConfigurationError("links must be a sequence of link names, not one string")
            idx = np.array([self._link(n) for n in links], dtype=np.int64)
            if len(set(idx.tolist())) != len(idx):
                raise ConfigurationError("links contains a name more than once")
            plan = None
        shape = (Qa.shape[0], len(idx), 4, 4)
        if out is None:
            out = np.empty(shape, dtype=dt)
        elif out.shape != shape or out.dtype != dt or not out.flags.c_contiguous or not out.flags.writeable:
            raise ConfigurationError(
                f"out must be a writable C-contiguous {dt} array of shape {shape}, "
                f"got {out.dtype} {out.shape}"
            )
        return kinematics.fk_batch(self._s, Qa, idx, out, backend, plan=plan, packed=self._engine.packed())

    def __repr__(self) -> str:
        return f"Robot({self.name!r}, links={len(self.link_names)}, dof={self.dof})"
