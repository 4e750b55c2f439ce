"""The kinematic structure of a robot as flat numpy arrays, read once from a Description.

Links are stored in depth-first order from the root (children in document order), so every link's
parent comes before it; this is also Pinocchio's joint order. Each link carries the joint that ends in
it (the root link has none, or the free-flyer when ``floating_base``). The user's coordinate vector
``q`` has one entry per *coordinate* (see :data:`COORDINATE_SUFFIXES`); mimic followers have no
coordinate and read their master's through ``multiplier`` and ``offset``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

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


@dataclass(frozen=True)
class JointRecord:
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


def _skew(a: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


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
    rk: np.ndarray
    rk2: np.ndarray
    dirn: np.ndarray
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


def _floats(el: etree._Element | None, attr: str, n: int, fname: str | None) -> np.ndarray | None:
    """``n`` floats from attribute ``attr`` of ``el``; None when the element or attribute is absent."""
    text = el.get(attr) if el is not None else None
    if text is None:
        return None
    try:
        values = np.array(text.split(), dtype=float)
    except ValueError:
        values = np.empty(0)
    if values.shape != (n,):
        raise DescriptionError(f"<{el.tag} {attr}=\"{text}\"> needs {n} numbers", fname, el.sourceline)
    return values


def _limit(el: etree._Element | None, attr: str, default: float, fname: str | None) -> float:
    value = _floats(el, attr, 1, fname)
    if value is None:
        return default
    v = float(value[0])
    return v if math.isfinite(v) else default


def _rpy_matrix(rpy: np.ndarray) -> np.ndarray:
    """URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) @ Ry(pitch) @ Rx(roll)."""
    cr, sr = math.cos(rpy[0]), math.sin(rpy[0])
    cp, sp = math.cos(rpy[1]), math.sin(rpy[1])
    cy, sy = math.cos(rpy[2]), math.sin(rpy[2])
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


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
    mimic = resolve_mimics(tree.joints, fname)
    root = tree.roots[0]
    link_set = {link.name for link in tree.links}
    world = None
    if floating_base:
        world = "world" if "world" not in link_set else "floating_base_world"
        if any(j.name == FLOATING_BASE_JOINT for j in tree.joints):
            raise DescriptionError(
                f"a joint is already named '{FLOATING_BASE_JOINT}'; cannot add a floating base", fname
            )

    order: list[str] = []
    joint_of: dict[str, str | None] = {root: FLOATING_BASE_JOINT if floating_base else None}
    stack = [root]
    while stack:
        link = stack.pop()
        order.append(link)
        kids = tree.children.get(link, [])
        for j in kids:
            joint_of[j.child] = j.name
        stack.extend(j.child for j in reversed(kids))
    index = {name: i for i, name in enumerate(order)}
    n = len(order)

    parent = np.full(n, -1, dtype=np.int64)
    jtype = np.zeros(n, dtype=np.int64)
    coord = np.full(n, -1, dtype=np.int64)
    mult = np.ones(n)
    off = np.zeros(n)
    rot = np.tile(np.eye(3), (n, 1, 1))
    trans = np.zeros((n, 3))
    axis = np.zeros((n, 3))
    axis[:, 0] = 1.0
    coord_names: list[str] = []
    lim: list[tuple[float, float, float, float, bool]] = []
    records: list[JointRecord] = []
    own_coord: dict[str, int] = {}

    def add_coords(jname: str, code: int) -> int:
        first = len(coord_names)
        for suffix in COORDINATE_SUFFIXES[code]:
            coord_names.append(f"{jname}/{suffix}")
            if suffix.startswith("q"):
                lim.append((-1.0, 1.0, math.inf, math.inf, False))
            elif suffix == "theta":
                lim.append((-math.inf, math.inf, math.inf, math.inf, True))  # an angle
            else:
                lim.append((-math.inf, math.inf, math.inf, math.inf, False))
        return first

    for i, link in enumerate(order):
        jname = joint_of[link]
        if jname is None:
            continue
        if jname == FLOATING_BASE_JOINT and link == root and floating_base:
            jtype[i] = FLOATING
            coord[i] = add_coords(jname, FLOATING)
            records.append(JointRecord(jname, "floating", world or "world", link, i, int(coord[i])))
            continue
        info = tree.parent_joint[link][0]
        code = _TYPE_CODES[info.type]
        parent[i] = index[info.parent]
        jtype[i] = code
        origin = info.element.find("origin")
        xyz = _floats(origin, "xyz", 3, fname)
        rpy = _floats(origin, "rpy", 3, fname)
        if xyz is not None:
            trans[i] = xyz
        if rpy is not None:
            rot[i] = _rpy_matrix(rpy)
        if code in (REVOLUTE, PRISMATIC):
            ax = _floats(info.element.find("axis"), "xyz", 3, fname)
            ax = np.array((1.0, 0.0, 0.0)) if ax is None else ax
            norm = float(np.linalg.norm(ax))
            if not (norm > 1e-12 and math.isfinite(norm)):
                raise DescriptionError(f"joint '{jname}' has a zero or invalid <axis>", fname, info.line)
            axis[i] = ax / norm
            if jname not in mimic:
                own_coord[jname] = len(coord_names)
                coord_names.append(jname)
                limit = info.element.find("limit")
                lo, hi = -math.inf, math.inf
                if info.type != "continuous":
                    lo, hi = _limit(limit, "lower", -math.inf, fname), _limit(limit, "upper", math.inf, fname)
                vel = _limit(limit, "velocity", math.inf, fname)
                eff = _limit(limit, "effort", math.inf, fname)
                lim.append((lo, hi, vel, eff, code == REVOLUTE))
                coord[i] = own_coord[jname]
        elif code in (FLOATING, PLANAR):
            coord[i] = add_coords(jname, code)
        records.append(JointRecord(jname, info.type, info.parent, link, i, int(coord[i])))

    for rec in records:  # mimic followers read their master's coordinate
        if rec.name in mimic:
            m = mimic[rec.name]
            i = rec.link
            coord[i] = own_coord[m.master]
            mult[i], off[i] = m.multiplier, m.offset
    records = [
        JointRecord(r.name, r.type, r.parent, r.child, r.link, int(coord[r.link])) if r.name in mimic else r
        for r in records
    ]

    angles = np.full(n, -1, dtype=np.int64)
    distinct: dict[tuple[int, float, float], int] = {}
    for i in np.flatnonzero(jtype == REVOLUTE):
        key = (int(coord[i]), float(mult[i]), float(off[i]))
        angles[i] = distinct.setdefault(key, len(distinct))
    K = np.array([_skew(a) for a in axis]) if n else np.zeros((0, 3, 3))
    rk = rot @ K
    rk2 = rk @ K
    dirn = np.einsum("nij,nj->ni", rot, axis)
    limits = np.array(lim, dtype=float).reshape(-1, 5)
    return KinematicStructure(
        link_names=tuple(order),
        world_frame=world,
        joints=tuple(records),
        coord_names=tuple(coord_names),
        mimic=mimic,
        parent=parent,
        jtype=jtype,
        coord=coord,
        mult=mult,
        off=off,
        rot=rot,
        trans=trans,
        rk=rk,
        rk2=rk2,
        dirn=dirn,
        angles=angles,
        axis=axis,
        lower=limits[:, 0].copy(),
        upper=limits[:, 1].copy(),
        velocity=limits[:, 2].copy(),
        effort=limits[:, 3].copy(),
        angular=limits[:, 4].astype(bool),
    )
