"""The kinematic structure of a robot as flat numpy arrays, read once from a Description.

Links are stored in depth-first order from the root (children in document order), so every link's
parent comes before it; this is also Pinocchio's joint order. Each link carries the joint that ends in
it (the root link has none, or the free-flyer when ``floating_base``). The user's coordinate vector
``q`` has one entry per *coordinate* (see :data:`COORDINATE_SUFFIXES`); mimic followers have no
coordinate and read their master's through ``multiplier`` and ``offset``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from lxml import etree

from urdftk._mimic import Mimic, resolve_mimics
from urdftk.description import Description
from urdftk.errors import DescriptionError

__all__ = [
    "COORDINATE_SUFFIXES",
    "FIXED",
    "FLOATING",
    "FLOATING_BASE_JOINT",
    "PLANAR",
    "PRISMATIC",
    "REVOLUTE",
    "JointRecord",
    "KinematicStructure",
    "build_structure",
]

FIXED, REVOLUTE, PRISMATIC, FLOATING, PLANAR = 0, 1, 2, 3, 4
_TYPE_CODES = {"fixed": FIXED, "revolute": REVOLUTE, "continuous": REVOLUTE, "prismatic": PRISMATIC}
_TYPE_CODES.update({"floating": FLOATING, "planar": PLANAR})

COORDINATE_SUFFIXES = {FLOATING: ("x", "y", "z", "qx", "qy", "qz", "qw"), PLANAR: ("x", "y", "theta")}
"""Coordinates of multi-coordinate joints, named ``<joint>/<suffix>`` in ``joint_names``."""

FLOATING_BASE_JOINT = "root_joint"
"""Name of the free-flyer joint added by ``floating_base=True`` (Pinocchio's default name)."""


class JointRecord(NamedTuple):
    """A URDF joint as the model sees it.

    Attributes:
        name: Joint name.
        type: URDF type (``revolute``, ``continuous``, ``prismatic``, ``fixed``, ``floating``, ``planar``).
        parent: Parent link (the world frame name for the floating base).
        child: Child link.
        link: Index of the child link in link order.
        coord: Index of its first coordinate in ``q`` (its master's for a mimic follower; -1 if fixed).
    """

    name: str
    type: str
    parent: str
    child: str
    link: int
    coord: int


@dataclass(frozen=True, eq=False)
class KinematicStructure:
    """Flat arrays describing the tree, indexed by link (depth-first order).

    Attributes:
        link_names: Links in depth-first order; the root first.
        world_frame: Name of the fixed frame the floating base moves in (None when fixed-based).
        joints: Every joint (movable and fixed) in link order.
        coord_names: Names of the user's coordinates (``joint_names``).
        mimic: Follower -> resolved :class:`~urdftk._mimic.Mimic`.
        parent: Parent link index, -1 for the root.
        jtype: Joint type code of the joint ending in each link.
        coord: First coordinate index read by that joint (-1 for fixed).
        mult: Mimic multiplier (1 for independent joints).
        off: Mimic offset (0 for independent joints).
        rot: Joint origin rotation ``R_o`` (n, 3, 3).
        trans: Joint origin translation ``t_o`` (n, 3).
        rk: ``R_o @ K`` with K the axis' cross-product matrix (revolute).
        rk2: ``R_o @ K @ K`` (revolute).
        dirn: ``R_o @ axis`` (prismatic), the axis in the parent frame.
        angles: Per revolute link, the index of its distinct angle ``(coord, mult, off)``; -1 otherwise.
        axis: The unit joint axis in the joint frame.
        lower: Lower limit per coordinate (continuous: -inf).
        upper: Upper limit per coordinate (continuous: +inf).
        velocity: Velocity limit per coordinate (inf when not given).
        effort: Effort limit per coordinate (inf when not given).
        angular: Per coordinate, True for angles (revolute, continuous, planar theta).
    """

    link_names: tuple[str, ...]
    world_frame: str | None
    joints: tuple[JointRecord, ...]
    coord_names: tuple[str, ...]
    mimic: dict[str, Mimic]
    parent: np.ndarray
    jtype: np.ndarray
    coord: np.ndarray
    mult: np.ndarray
    off: np.ndarray
    rot: np.ndarray
    trans: np.ndarray
    angles: np.ndarray
    axis: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray
    angular: np.ndarray

    @property
    def n_links(self) -> int:
        """Number of links."""
        return len(self.link_names)

    # Derived arrays, computed on first use by FK (computing one twice is harmless).
    @functools.cached_property
    def _k(self) -> np.ndarray:
        """The cross-product matrix ``K`` of each axis (n, 3, 3)."""
        a = self.axis
        K = np.zeros((len(a), 3, 3))
        K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -a[:, 2], a[:, 1], -a[:, 0]
        K[:, 1, 0], K[:, 2, 0], K[:, 2, 1] = a[:, 2], -a[:, 1], a[:, 0]
        return K

    @functools.cached_property
    def rk(self) -> np.ndarray:
        """``R_o @ K`` (revolute)."""
        return self.rot @ self._k

    @functools.cached_property
    def rk2(self) -> np.ndarray:
        """``R_o @ K @ K`` (revolute)."""
        return self.rk @ self._k

    @functools.cached_property
    def dirn(self) -> np.ndarray:
        """``R_o @ axis`` (prismatic), the axis in the parent frame."""
        return np.einsum("nij,nj->ni", self.rot, self.axis)


def _floats(el: etree._Element | None, attr: str, n: int, fname: str | None) -> list[float] | None:
    """``n`` floats from attribute ``attr`` of ``el``; None when the element or attribute is absent."""
    text = el.get(attr) if el is not None else None
    if text is None:
        return None
    parts = text.split()
    try:
        if n == 3 and len(parts) == 3:  # the common case, without a comprehension
            return [float(parts[0]), float(parts[1]), float(parts[2])]
        values = [float(v) for v in parts]
    except ValueError:
        values = []
    if len(values) != n:
        raise DescriptionError(f'<{el.tag} {attr}="{text}"> needs {n} numbers', fname, el.sourceline)
    return values


def _limit(el: etree._Element | None, attr: str, default: float, fname: str | None) -> float:
    text = el.get(attr) if el is not None else None
    if text is None:
        return default
    try:
        v = float(text)  # one number, blanks around it allowed: what _floats(..., 1) accepts
    except ValueError:
        v = _floats(el, attr, 1, fname)[0]  # raises the message for a malformed value
    return v if math.isfinite(v) else default


_HAS_MIMIC = etree.XPath("boolean(joint/mimic)")
"""True when some top-level ``<joint>`` has a ``<mimic>`` child (the joints resolve_mimics reads)."""

_EYE = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)


def _rpy_matrix(rpy: list[float]) -> tuple[float, ...]:
    """URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) @ Ry(pitch) @ Rx(roll), row-major."""
    cr, sr = math.cos(rpy[0]), math.sin(rpy[0])
    cp, sp = math.cos(rpy[1]), math.sin(rpy[1])
    cy, sy = math.cos(rpy[2]), math.sin(rpy[2])
    return (
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        -sp,
        cp * sr,
        cp * cr,
    )


def _coords(
    jname: str, code: int, names: list[str], lim: list[tuple[float, float, float, float, bool]]
) -> int:
    """Append the coordinates of a multi-coordinate joint; return the first one's index."""
    first = len(names)
    for suffix in COORDINATE_SUFFIXES[code]:
        names.append(f"{jname}/{suffix}")
        if suffix.startswith("q"):
            lim.append((-1.0, 1.0, math.inf, math.inf, False))
        elif suffix == "theta":
            lim.append((-math.inf, math.inf, math.inf, math.inf, True))  # an angle
        else:
            lim.append((-math.inf, math.inf, math.inf, math.inf, False))
    return first


def build_structure(description: Description, floating_base: bool = False) -> KinematicStructure:
    """Read the kinematic structure of a parsed description.

    Args:
        description: The parsed description (structure already validated).
        floating_base: Add a free-flyer between a world frame and the root link.

    Returns:
        The structure.

    Raises:
        DescriptionError: For a zero joint axis, a bad mimic, or a name clash with the floating base.
    """
    tree = description.tree
    fname = description.filename
    # One C-level query spares resolve_mimics a find() per joint when nothing mimics (it returns {}).
    mimic = resolve_mimics(tree.joints, fname) if _HAS_MIMIC(description.root) else {}
    root = tree.roots[0]
    world = None
    if floating_base:
        world = "world" if all(link.name != "world" for link in tree.links) else "floating_base_world"
        if any(j.name == FLOATING_BASE_JOINT for j in tree.joints):
            raise DescriptionError(
                f"a joint is already named '{FLOATING_BASE_JOINT}'; cannot add a floating base", fname
            )

    # Depth-first link order, children in document order; each link with the joint ending in it.
    order: list[str] = []
    incoming: list[object] = []
    children = tree.children
    stack: list[tuple[str, object]] = [(root, None)]
    while stack:
        link, j = stack.pop()
        order.append(link)
        incoming.append(j)
        kids = children.get(link)
        if kids:
            stack.extend((k.child, k) for k in reversed(kids))
    index = {name: i for i, name in enumerate(order)}
    n = len(order)

    # Per-link values gathered in plain lists; numpy arrays are made once at the end.
    parent = [-1] * n
    jtype = [FIXED] * n
    coord = [-1] * n
    mult = [1.0] * n
    off = [0.0] * n
    rot: list[tuple[float, ...]] = [_EYE] * n
    trans: list[tuple[float, ...] | list[float]] = [(0.0, 0.0, 0.0)] * n
    axis: list[tuple[float, ...]] = [(1.0, 0.0, 0.0)] * n
    coord_names: list[str] = []
    lim: list[tuple[float, float, float, float, bool]] = []
    records: list[JointRecord] = []
    own_coord: dict[str, int] = {}

    for i in range(n):
        link = order[i]
        info = incoming[i]
        if info is None:
            if floating_base:  # the root link: the free-flyer ends in it
                jtype[i] = FLOATING
                coord[i] = _coords(FLOATING_BASE_JOINT, FLOATING, coord_names, lim)
                records.append(
                    JointRecord(FLOATING_BASE_JOINT, "floating", world or "world", link, i, coord[i])
                )
            continue
        jname = info.name
        code = _TYPE_CODES[info.type]
        parent[i] = index[info.parent]
        jtype[i] = code
        origin = axis_el = limit = None  # the first of each, as find() would return
        for sub in info.element:
            tag = sub.tag
            if tag == "origin":
                origin = sub if origin is None else origin
            elif tag == "axis":
                axis_el = sub if axis_el is None else axis_el
            elif tag == "limit":
                limit = sub if limit is None else limit
        if origin is not None:
            xyz = _floats(origin, "xyz", 3, fname)
            rpy = _floats(origin, "rpy", 3, fname)
            if xyz is not None:
                trans[i] = xyz
            if rpy is not None:
                rot[i] = _rpy_matrix(rpy)
        if code in (REVOLUTE, PRISMATIC):
            ax = _floats(axis_el, "xyz", 3, fname) or (1.0, 0.0, 0.0)
            x, y, z = ax
            norm = math.sqrt(x * x + y * y + z * z)
            if not (norm > 1e-12 and math.isfinite(norm)):
                raise DescriptionError(f"joint '{jname}' has a zero or invalid <axis>", fname, info.line)
            axis[i] = (x / norm, y / norm, z / norm)
            if jname not in mimic:
                own_coord[jname] = coord[i] = len(coord_names)
                coord_names.append(jname)
                lo, hi = -math.inf, math.inf
                if info.type != "continuous":
                    lo, hi = _limit(limit, "lower", -math.inf, fname), _limit(limit, "upper", math.inf, fname)
                vel = _limit(limit, "velocity", math.inf, fname)
                eff = _limit(limit, "effort", math.inf, fname)
                lim.append((lo, hi, vel, eff, code == REVOLUTE))
        elif code in (FLOATING, PLANAR):
            coord[i] = _coords(jname, code, coord_names, lim)
        records.append(JointRecord(jname, info.type, info.parent, link, i, coord[i]))

    if mimic:
        for k, rec in enumerate(records):  # mimic followers read their master's coordinate
            m = mimic.get(rec.name)
            if m is not None:
                i = rec.link
                coord[i] = own_coord[m.master]
                mult[i], off[i] = m.multiplier, m.offset
                records[k] = JointRecord(rec.name, rec.type, rec.parent, rec.child, i, coord[i])

    angle_of = [-1] * n
    distinct: dict[tuple[int, float, float], int] = {}
    for i in range(n):
        if jtype[i] == REVOLUTE:
            angle_of[i] = distinct.setdefault((coord[i], mult[i], off[i]), len(distinct))
    rot_a = np.array(rot, dtype=float).reshape(n, 3, 3)
    axis_a = np.array(axis, dtype=float).reshape(n, 3)
    limits = np.array(lim, dtype=float).reshape(-1, 5)
    return KinematicStructure(
        link_names=tuple(order),
        world_frame=world,
        joints=tuple(records),
        coord_names=tuple(coord_names),
        mimic=mimic,
        parent=np.array(parent, dtype=np.int64),
        jtype=np.array(jtype, dtype=np.int64),
        coord=np.array(coord, dtype=np.int64),
        mult=np.array(mult, dtype=float),
        off=np.array(off, dtype=float),
        rot=rot_a,
        trans=np.array(trans, dtype=float).reshape(n, 3),
        angles=np.array(angle_of, dtype=np.int64),
        axis=axis_a,
        lower=limits[:, 0].copy(),
        upper=limits[:, 1].copy(),
        velocity=limits[:, 2].copy(),
        effort=limits[:, 3].copy(),
        angular=limits[:, 4].astype(bool),
    )
