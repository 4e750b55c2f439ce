"""The configuration space of a :class:`~urdftk.model.Robot`: limits, draws and checked conversions.

See :mod:`urdftk.model` for the meaning of each coordinate.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from urdftk._structure import FLOATING, KinematicStructure
from urdftk.errors import ConfigurationError, JointNotFound

__all__ = ["ConfigSpace", "Limits"]

_F64 = np.dtype(np.float64)


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


class ConfigSpace:
    """Coordinates of one robot: names, limits, and conversion of user input into checked arrays.

    Args:
        name: The robot's name (for error messages).
        struct: Its kinematic structure.
    """

    def __init__(self, name: str, struct: KinematicStructure):
        """Index the coordinates of ``struct``."""
        self.name = name
        self.joint_names = struct.coord_names
        self.dof = len(struct.coord_names)
        self.shape = (self.dof,)
        self.mimic: dict[str, tuple[str, float, float]] = {
            f: (m.master, m.multiplier, m.offset) for f, m in struct.mimic.items()
        }
        s = struct
        self.limits = Limits(*(_readonly(a) for a in (s.lower, s.upper, s.velocity, s.effort)))
        self.angular = s.angular
        self.index = {n: i for i, n in enumerate(s.coord_names)}
        self.quat_coords = [int(s.coord[i]) + 3 for i in np.flatnonzero(s.jtype == FLOATING)]

    def neutral(self) -> np.ndarray:
        """Zero clipped into the limits, identity quaternions."""
        q = np.clip(np.zeros(self.dof), self.limits.lower, self.limits.upper)
        for c in self.quat_coords:
            q[c : c + 4] = (0.0, 0.0, 0.0, 1.0)
        return q

    def random(self, gen: np.random.Generator, size: int | None = None) -> np.ndarray:
        """A uniform draw within the limits (see :meth:`urdftk.model.Robot.random`)."""
        lo, hi = self.limits.lower.copy(), self.limits.upper.copy()
        ang = self.angular
        wide = ang & ~(hi - lo <= 2 * np.pi)  # unbounded or wider than a turn: one turn is enough
        lo = np.where(wide, np.clip(-np.pi, lo, np.maximum(lo, hi - 2 * np.pi)), lo)
        hi = np.where(wide, lo + 2 * np.pi, hi)
        free = ~ang & ~np.isfinite(hi - lo)
        lo = np.where(free, np.clip(-1.0, lo, np.maximum(lo, hi - 2.0)), lo)
        hi = np.where(free, lo + 2.0, hi)
        shape = self.shape if size is None else (int(size), *self.shape)
        q = gen.uniform(lo, hi, size=shape)
        for c in self.quat_coords:
            v = gen.normal(size=(*shape[:-1], 4))
            q[..., c : c + 4] = v / np.linalg.norm(v, axis=-1, keepdims=True)
        return q

    def check(self, value: Mapping[str, float] | Sequence[float] | np.ndarray, clip: bool) -> np.ndarray:
        """Convert and check a configuration, enforcing limits (see :meth:`urdftk.model.Robot.q`)."""
        if isinstance(value, Mapping):
            q = self.from_mapping(value)
        else:
            q = np.array(value, dtype=np.float64)
            if q.shape != self.shape:
                raise self._shape_error(q.shape)
        if not np.all(np.isfinite(q)):
            bad = [self.joint_names[i] for i in np.flatnonzero(~np.isfinite(q))]
            raise ConfigurationError(f"{self.name}: non-finite value for joint(s) {', '.join(bad)}")
        for c in self.quat_coords:
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

    def from_mapping(self, value: Mapping[str, float]) -> np.ndarray:
        """``{joint: value}`` to an array; absent joints are neutral, followers set their master."""
        q = self.neutral()
        given: set[int] = set()
        followers: list[tuple[str, float]] = []
        for name, v in value.items():
            i = self.index.get(name)
            if i is not None:
                q[i] = float(v)
                given.add(i)
            elif name in self.mimic:
                followers.append((name, float(v)))
            else:
                raise JointNotFound(name, [*self.joint_names, *self.mimic])
        for name, v in followers:
            master, mult, off = self.mimic[name]
            i = self.index[master]
            if i not in given and mult != 0.0:
                q[i] = (v - off) / mult
                given.add(i)
            elif abs(mult * q[i] + off - v) > 1e-6:
                raise ConfigurationError(
                    f"{self.name}: mimic joint {name}={v:.6g} disagrees with its master {master}={q[i]:.6g} "
                    f"(expected {mult * q[i] + off:.6g}); give the master only"
                )
        return q

    def coerce(self, q: Any, check_finite: bool = True) -> np.ndarray:
        """Shape-checked float64 coordinates (finite unless ``check_finite`` is False); no limits.

        A float64 array of the right shape is returned as is, without a copy.
        """
        if type(q) is np.ndarray and q.shape == self.shape and q.dtype is _F64:
            u = q
        elif isinstance(q, Mapping):
            u = self.from_mapping(q)
        else:
            u = np.asarray(q, dtype=np.float64)
            if u.shape != self.shape:
                raise self._shape_error(u.shape)
        if check_finite and not np.isfinite(u).all():
            raise self.non_finite()
        return u

    def non_finite(self) -> ConfigurationError:
        """The error for a configuration containing NaN or inf."""
        return ConfigurationError(f"{self.name}: configuration contains NaN or inf")

    def _shape_error(self, shape: tuple[int, ...]) -> ConfigurationError:
        return ConfigurationError(
            f"{self.name}: expected {self.dof} joint values in joint_names order, got shape {shape}"
        )
