"""Live reload: load a robot while recording every file it was built from, and watch those files.

:func:`load_robot` is :func:`urdftk.load` plus the list of files read (the .urdf/.xacro and every
xacro include). :class:`FileWatcher` checks their modification stamps on a background thread
(``Event.wait`` between checks, so closing it is immediate) and calls back once per change.
"""

from __future__ import annotations

import os
import sys
import threading
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

__all__ = ["FileWatcher", "load_robot"]

_Stamp = tuple[int, int] | None


def load_robot(
    path: str | os.PathLike[str],
    args: Mapping[str, str] | None = None,
    package_paths: Iterable[str | os.PathLike[str]] = (),
    *,
    with_includes: bool = False,
) -> tuple[Any, tuple[Path, ...]]:
    """Load a robot from a .urdf/.xacro file and list the files it depends on.

    Args:
        path: The robot file.
        args: xacro arguments.
        package_paths: Extra package folders, searched first.
        with_includes: Also list the files xacro includes (expands the file once more).

    Returns:
        ``(robot, files)``: the :class:`urdftk.Robot` and the input file followed by its includes.

    Raises:
        UrdftkError: Whatever loading raises (with file:line).
    """
    import urdftk

    robot = urdftk.load(path, args=dict(args or {}), package_paths=list(package_paths))
    files: tuple[Path, ...] = (Path(path),)
    if with_includes:
        from urdftk import xacro

        result = xacro.expand(path, dict(args or {}), resolver=robot.resolver, verbosity=0)
        files = (Path(path), *result.includes)
    return robot, files


def _stamp(path: Path) -> _Stamp:
    try:
        st = path.stat()
    except OSError:
        return None
    return (st.st_mtime_ns, st.st_size)


class FileWatcher:
    """Calls ``on_change()`` (on its own thread) when any watched file changes or disappears.

    Args:
        files: The files to watch.
        on_change: Called with no arguments after a change; it may call :meth:`set_files`.
        interval: Seconds between checks.
    """

    def __init__(self, files: Iterable[Path], on_change: Callable[[], None], interval: float = 0.25) -> None:
        self._on_change = on_change
        self._interval = interval
        self._lock = threading.Lock()
        self._stamps: dict[Path, _Stamp] = {}
        self.set_files(files)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="urdftk-watch", daemon=True)
        self._thread.start()

    def set_files(self, files: Iterable[Path]) -> None:
        """Watch these files from now on (their current state is the reference)."""
        with self._lock:
            self._stamps = {Path(f): _stamp(Path(f)) for f in files}

    @property
    def files(self) -> tuple[Path, ...]:
        """The files being watched."""
        with self._lock:
            return tuple(self._stamps)

    def _run(self) -> None:
        while not self._stop.wait(self._interval):
            with self._lock:
                changed = False
                for f, old in self._stamps.items():
                    new = _stamp(f)
                    if new != old:
                        self._stamps[f] = new
                        changed = True
            if changed:
                try:
                    self._on_change()
                except Exception as exc:  # never let the watcher die
                    print(f"urdftk view: warning: reload failed: {exc}", file=sys.stderr)

    def close(self) -> None:
        """Stop watching."""
        self._stop.set()
        self._thread.join(timeout=5)
