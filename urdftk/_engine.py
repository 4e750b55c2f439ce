"""Per-robot computing state behind :class:`~urdftk.model.Robot`: Pinocchio's Data, FK kernels, maps.

Single-configuration FK (:meth:`Robot.fk`, :meth:`Robot.frame_pose`) runs the compiled kernels of
:mod:`urdftk._fk_numba` when numba is installed: one call with five arguments, no Pinocchio
round trip, no per-link Python objects. Without numba, ``frame_pose`` uses Pinocchio and ``fk`` the
numpy batch code. Everything is built lazily and owned by one robot (no module-level state).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from urdftk import kinematics
from urdftk._pinmap import PinMap, build_pinmap
from urdftk._structure import KinematicStructure
from urdftk.errors import KinematicsError

__all__ = ["PIN_DATA_MAX_NV", "Engine", "Kernels"]

PIN_DATA_MAX_NV = 500
"""Above this, Jacobians and the centre of mass are refused (Pinocchio's Data would need gigabytes)."""


class Kernels(NamedTuple):
    """The compiled single-configuration kernels and the packed structure they read.

    Attributes:
        pk: The packed structure (:func:`urdftk._fk_numba.pack`).
        one_all: :func:`urdftk._fk_numba.fk_one_all`.
        one_link: :func:`urdftk._fk_numba.fk_one_link`.
    """

    pk: np.ndarray
    one_all: Callable[..., bool]
    one_link: Callable[..., bool]


class Engine:
    """Pinocchio's Data (guarded by a lock) and the FK kernels of one robot.

    Args:
        name: The robot's name (for error messages).
        struct: Its kinematic structure.
        model: Its ``pinocchio.Model``.
        filename: The description's file, for error messages.
    """

    def __init__(self, name: str, struct: KinematicStructure, model: Any, filename: str | None = None):
        """Keep references; nothing is computed until first use."""
        self.name = name
        self.struct = struct
        self.model = model
        self.filename = filename
        self.lock = threading.Lock()
        self._data: Any = None
        self._kernels: Kernels | None = None
        self._numba: bool | None = None
        self._pinmap: PinMap | None = None
        self._plan: tuple[np.ndarray, np.ndarray] | None = None

    def pinmap(self) -> PinMap:
        """The user -> Pinocchio coordinate map, built on first use (twice from two threads is harmless)."""
        if self._pinmap is None:
            self._pinmap = build_pinmap(self.struct, self.model, self.filename)
        return self._pinmap

    def plan(self) -> tuple[np.ndarray, np.ndarray]:
        """The FK plan over every link (:func:`urdftk.kinematics.make_plan`), made on first use."""
        if self._plan is None:
            self._plan = kinematics.make_plan(self.struct, np.arange(self.struct.n_links))
        return self._plan

    def kernels(self) -> Kernels | None:
        """The compiled kernels, or None when numba is not installed (first call compiles or loads)."""
        if self._kernels is None and self._numba is not False:
            self._numba = kinematics.has_numba()
            if self._numba:
                from urdftk import _fk_numba

                pk = _fk_numba.pack(self.struct)
                self._kernels = Kernels(pk, _fk_numba.fk_one_all, _fk_numba.fk_one_link)
        return self._kernels

    def packed(self) -> np.ndarray | None:
        """The packed structure for the batched kernel, or None without numba."""
        k = self.kernels()
        return None if k is None else k.pk

    def pin_data(self) -> Any:
        """Pinocchio's Data, created on first use; hold :attr:`lock` while using it.

        Raises:
            KinematicsError: If the model is too large for Pinocchio's O(nv^3) Data.
        """
        if self._data is None:
            if self.model.nv > PIN_DATA_MAX_NV:
                raise KinematicsError(
                    f"{self.name}: {self.model.nv} velocity coordinates; "
                    "Pinocchio's Data needs O(nv^3) memory, "
                    f"so Jacobians and the centre of mass are limited to {PIN_DATA_MAX_NV} coordinates"
                )
            try:
                self._data = self.model.createData()
            except MemoryError:
                raise KinematicsError(f"{self.name}: not enough memory for Pinocchio's Data") from None
        return self._data
