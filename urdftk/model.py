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

import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from urdftk import kinematics
from urdftk._pinmap import build_pinmap
from urdftk._structure import FLOATING, build_structure
from urdftk.description import Description
from urdftk.errors import (
    ConfigurationError,
    DescriptionError,
    JointNotFound,
    KinematicsError,
    LinkNotFound,
)
from urdftk.pose import Pose
from urdftk.resources import PackageResolver

__all__ = ["Limits", "Robot"]

_PIN_FK_MAX_NV = 300
"""Above this many velocity coordinates, single FK uses our own code (Pinocchio's Data is O(nv^3))."""
_PIN_DATA_MAX_NV = 500
"""Above this, Jacobians and the centre of mass are refused (Pinocchio's Data would need gigabytes)."""
_REFERENCES = ("world", "local", "local_world_aligned")


@dataclass(frozen=True, eq=False)
class Limits:
    """Joint limits over :attr:`Robot.joint_names` (read-only arrays).

    Attributes:
        lower: Lower position limits (continuous joints and positions of free joints: ``-inf``).
        upper: Upper position limits (``+inf`` when unbounded).
        velocity: Velocity limits (``inf`` when not given).
        effort: Effort limits (``inf`` when not given).
    """

    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray


def _readonly(a: np.ndarray) -> np.ndarray:
    b = np.array(a, dtype=np.float64)
    b.setflags(write=False)
    return b


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
        self.description = description.urdf
        self.name: str = description.name
        self.source: Path | None = Path(description.filename) if description.filename else None
        self.urdf_text: str = description.text
        self.resolver = resolver
        self.floating_base = floating_base
        self._s = s = build_structure(description, floating_base)
        try:
            if floating_base:
                self.model = pin.buildModelFromXML(description.text, pin.JointModelFreeFlyer())
            else:
                self.model = pin.buildModelFromXML(description.text)
        except Exception as exc:  # Pinocchio raises bare ValueError/RuntimeError
            raise DescriptionError(f"Pinocchio cannot build the model: {exc}", description.filename) from None
        self._map = build_pinmap(s, self.model, description.filename)
        self.link_names: tuple[str, ...] = s.link_names
        self.root_link: str = s.link_names[0]
        self.world_frame: str | None = s.world_frame
        self.joint_names: tuple[str, ...] = s.coord_names
        self.mimic: dict[str, tuple[str, float, float]] = {
            f: (m.master, m.multiplier, m.offset) for f, m in s.mimic.items()
        }
        self.limits = Limits(
            _readonly(s.lower), _readonly(s.upper), _readonly(s.velocity), _readonly(s.effort)
        )
        self._link_index = {n: i for i, n in enumerate(s.link_names)}
        self._coord_index = {n: i for i, n in enumerate(s.coord_names)}
        self._frame_id = {}
        for link in s.link_names:
            fid = self.model.getFrameId(link, pin.BODY)
            if fid >= self.model.nframes:
                raise DescriptionError(f"Pinocchio has no frame for link '{link}'", description.filename)
            self._frame_id[link] = fid
        self._all_links = np.arange(s.n_links)
        self._all_plan = kinematics.make_plan(s, self._all_links)
        self._quat_coords = [int(s.coord[i]) + 3 for i in np.flatnonzero(s.jtype == FLOATING)]
        self._lock = threading.Lock()
        self._data: Any = None

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
        q = np.clip(np.zeros(self.dof), self.limits.lower, self.limits.upper)
        for c in self._quat_coords:
            q[c : c + 4] = (0.0, 0.0, 0.0, 1.0)
        return q

    def random(self, rng: np.random.Generator | int | None = None) -> np.ndarray:
        """Draw a configuration uniformly within the limits.

        Angles whose range is wider than a turn are drawn over one turn (within [-pi, pi] where the
        limits allow), unbounded positions over 2 m (within [-1, 1] where allowed), and quaternions
        uniformly on the unit sphere.

        Args:
            rng: A numpy Generator, or a seed.

        Returns:
            (dof,) configuration.
        """
        gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
        lo, hi = self.limits.lower.copy(), self.limits.upper.copy()
        ang = self._s.angular
        wide = ang & ~(hi - lo <= 2 * np.pi)  # unbounded or wider than a turn: one turn is enough
        lo = np.where(wide, np.clip(-np.pi, lo, np.maximum(lo, hi - 2 * np.pi)), lo)
        hi = np.where(wide, lo + 2 * np.pi, hi)
        free = ~ang & ~np.isfinite(hi - lo)
        lo = np.where(free, np.clip(-1.0, lo, np.maximum(lo, hi - 2.0)), lo)
        hi = np.where(free, lo + 2.0, hi)
        q = gen.uniform(lo, hi)
        for c in self._quat_coords:
            v = gen.normal(size=4)
            q[c : c + 4] = v / np.linalg.norm(v)
        return q

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
        if isinstance(value, Mapping):
            q = self._from_mapping(value)
        else:
            q = np.array(value, dtype=np.float64)
            if q.shape != (self.dof,):
                raise ConfigurationError(
                    f"{self.name}: expected {self.dof} joint values in joint_names order, got shape {q.shape}"
                )
        if not np.all(np.isfinite(q)):
            bad = [self.joint_names[i] for i in np.flatnonzero(~np.isfinite(q))]
            raise ConfigurationError(f"{self.name}: non-finite value for joint(s) {', '.join(bad)}")
        for c in self._quat_coords:
            norm = np.linalg.norm(q[c : c + 4])
            if not norm > 1e-12:
                raise ConfigurationError(f"{self.name}: quaternion of {self.joint_names[c][:-3]} is zero")
            q[c : c + 4] /= norm
        lo, hi = self.limits.lower, self.limits.upper
        outside = (q < lo - 1e-9) | (q > hi + 1e-9)
        if np.any(outside):
            if not clip:
                items = [
                    f"{self.joint_names[i]}={q[i]:.6g} not in [{lo[i]:.6g}, {hi[i]:.6g}]"
                    for i in np.flatnonzero(outside)
                ]
                raise ConfigurationError(
                    f"{self.name}: out of limits: {'; '.join(items)} "
                    "(use clip=True, or --clip on the command line, to clip)"
                )
            q = np.clip(q, lo, hi)
        return q

    def _from_mapping(self, value: Mapping[str, float]) -> np.ndarray:
        q = self.neutral()
        given: set[int] = set()
        followers: list[tuple[str, float]] = []
        for name, v in value.items():
            i = self._coord_index.get(name)
            if i is not None:
                q[i] = float(v)
                given.add(i)
            elif name in self.mimic:
                followers.append((name, float(v)))
            else:
                raise JointNotFound(name, [*self.joint_names, *self.mimic])
        for name, v in followers:
            master, mult, off = self.mimic[name]
            i = self._coord_index[master]
            if i not in given and mult != 0.0:
                q[i] = (v - off) / mult
                given.add(i)
            elif abs(mult * q[i] + off - v) > 1e-6:
                raise ConfigurationError(
                    f"{self.name}: mimic joint {name}={v:.6g} disagrees with its master {master}={q[i]:.6g} "
                    f"(expected {mult * q[i] + off:.6g}); give the master only"
                )
        return q

    def _coerce(self, q: Any) -> np.ndarray:
        """Shape- and finiteness-checked float64 coordinates; limits are not enforced here."""
        if type(q) is np.ndarray and q.shape == (self.dof,) and q.dtype == np.float64:
            u = q
        elif isinstance(q, Mapping):
            u = self._from_mapping(q)
        else:
            u = np.asarray(q, dtype=np.float64)
            if u.shape != (self.dof,):
                raise ConfigurationError(
                    f"{self.name}: expected {self.dof} joint values in joint_names order, got shape {u.shape}"
                )
        if not np.isfinite(u).all():
            raise ConfigurationError(f"{self.name}: configuration contains NaN or inf")
        return u

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

    def _pin_data(self):
        if self._data is None:
            if self.model.nv > _PIN_DATA_MAX_NV:
                raise KinematicsError(
                    f"{self.name}: {self.model.nv} velocity coordinates; "
                    "Pinocchio's Data needs O(nv^3) memory, "
                    f"so Jacobians and the centre of mass are limited to {_PIN_DATA_MAX_NV} coordinates"
                )
            try:
                self._data = self.model.createData()
            except MemoryError:
                raise KinematicsError(f"{self.name}: not enough memory for Pinocchio's Data") from None
        return self._data

    def fk(self, q: Any, *, backend: kinematics.Backend = "auto") -> np.ndarray:
        """Return every link pose ``T_root_link``.

        Args:
            q: A configuration (array in ``joint_names`` order, or a mapping).
            backend: Batched-FK backend (``"auto"``, ``"numba"``, ``"numpy"``).

        Returns:
            (n_links, 4, 4) float64 array, rows in :attr:`link_names` order.
        """
        u = self._coerce(q)
        out = np.empty((1, self._s.n_links, 4, 4))
        kinematics.fk_batch(self._s, u[None, :], self._all_links, out, backend, plan=self._all_plan)
        return out[0]

    def frame_pose(self, name: str, q: Any) -> np.ndarray:
        """Return ``T_root_name`` of one link (4x4 float64).

        Args:
            name: A link name (or :attr:`world_frame` with a floating base).
            q: A configuration.

        Raises:
            LinkNotFound: For an unknown name, listing the valid ones.
        """
        if name == self.world_frame and name is not None:
            self._coerce(q)
            return np.eye(4)
        fid = self._frame_id.get(name)
        if fid is None:
            self._link(name)
        u = self._coerce(q)
        if self.model.nv > _PIN_FK_MAX_NV:
            s = self._s
            return kinematics.fk_chain(s, kinematics.local_transforms(s, u), self._link_index[name])
        import pinocchio as pin

        pq = self._map.to_pin(u)
        with self._lock:
            data = self._pin_data()
            pin.forwardKinematics(self.model, data, pq)
            return pin.updateFramePlacement(self.model, data, fid).homogeneous

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
        rf = {
            "world": pin.ReferenceFrame.WORLD,
            "local": pin.ReferenceFrame.LOCAL,
            "local_world_aligned": pin.ReferenceFrame.LOCAL_WORLD_ALIGNED,
        }[reference]
        with self._lock:
            data = self._pin_data()
            J = pin.computeFrameJacobian(self.model, data, self._map.to_pin(u), self._frame_id[frame], rf)
        return np.asarray(J).reshape(6, self.model.nv) @ self._map.velocity_map(u)

    def com(self, q: Any) -> np.ndarray:
        """Return the centre of mass (3,) in the root (world) frame, metres."""
        import pinocchio as pin

        u = self._coerce(q)
        with self._lock:
            return np.array(pin.centerOfMass(self.model, self._pin_data(), self._map.to_pin(u)))

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
            idx, plan = self._all_links, self._all_plan
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
        return kinematics.fk_batch(self._s, Qa, idx, out, backend, plan=plan)

    def __repr__(self) -> str:
        return f"Robot({self.name!r}, links={len(self.link_names)}, dof={self.dof})"
