"""Resource resolution without ROS: ``package://``, ``$(find pkg)``, ``file://`` and relative paths.

Packages are searched in this order (the first hit wins):

1. explicit folders (``-p/--package-path``, ``package_paths=``), each crawled for ``package.xml``;
2. ``ROS_PACKAGE_PATH``, crawled the same way (ROS 1 semantics);
3. ``AMENT_PREFIX_PATH``, through the ament resource index (ROS 2 semantics);
4. the workspace that encloses the input file: walk up from the file to the first folder with a
   ``package.xml`` (that package), then crawl its parent (its sibling packages);
5. robot-description packages installed with pip that ship a ROS share folder, such as
   ``example-robot-data`` (an ament prefix inside ``site-packages/cmeel.prefix``) or packages under
   ``<sys.prefix>/share``.

A crawl stops descending at a folder holding ``package.xml`` and skips hidden folders and folders
marked with ``CATKIN_IGNORE``, ``COLCON_IGNORE`` or ``AMENT_IGNORE``. A package is known by the
``<name>`` in its ``package.xml`` (and by its folder name when that differs).
"""

from __future__ import annotations

import contextlib
import os
import re
import site
import sys
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from urllib.parse import unquote

from urdftk.errors import PackageNotFound, ResourceError

__all__ = ["PackageResolver", "crawl_packages", "installed_prefixes"]

_IGNORE_MARKERS = ("CATKIN_IGNORE", "COLCON_IGNORE", "AMENT_IGNORE")
_NAME_RE = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")
_MAX_CRAWL_DIRS = 200_000


def _package_name(folder: str | Path) -> str:
    try:
        with open(os.path.join(folder, "package.xml"), "rb") as fh:
            head = fh.read(65536)
    except OSError:
        return os.path.basename(folder)
    match = _NAME_RE.search(head)
    return match.group(1).decode("utf-8", "replace") if match else os.path.basename(folder)


def crawl_packages(root: str | os.PathLike[str]) -> dict[str, Path]:
    """Find every ROS package below ``root``, as ``rospack`` crawls ``ROS_PACKAGE_PATH``.

    Args:
        root: Folder to crawl. It may itself be a package.

    Returns:
        Package name -> package folder. The first folder found for a name wins.
    """
    found: dict[str, Path] = {}
    start = os.fspath(root)
    if not os.path.isdir(start):
        return found
    visited = 0
    stack = [start]
    while stack and visited < _MAX_CRAWL_DIRS:
        folder = stack.pop()
        visited += 1
        try:
            with os.scandir(folder) as it:
                entries = list(it)
        except OSError:
            continue
        names = {e.name for e in entries}
        if not names.isdisjoint(_IGNORE_MARKERS):
            continue
        if "package.xml" in names:
            path = Path(folder)
            found.setdefault(_package_name(folder), path)
            found.setdefault(os.path.basename(folder), path)
            continue
        subdirs = sorted(e.path for e in entries if e.name[0] != "." and e.is_dir(follow_symlinks=True))
        stack.extend(reversed(subdirs))
    return found


def _direct_package(root: str | os.PathLike[str], name: str) -> Path | None:
    """``root/name`` (or ``root`` itself) when it is the package ``name``: the common case, no crawl."""
    for cand in (os.path.join(root, name), os.fspath(root)):
        if os.path.isfile(os.path.join(cand, "package.xml")) and _package_name(cand) == name:
            ignored = any(os.path.exists(os.path.join(cand, m)) for m in _IGNORE_MARKERS)
            if not ignored:
                return Path(cand)
    return None


def _ament_packages(prefix: Path) -> dict[str, Path]:
    found: dict[str, Path] = {}
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    try:
        names = sorted(os.listdir(index))
    except OSError:
        names = []
    for name in names:
        share = prefix / "share" / name
        if share.is_dir():
            found.setdefault(name, share)
    return found


def installed_prefixes() -> list[Path]:
    """Install prefixes of pip-installed description packages (ament-style ``share/`` folders).

    Returns:
        Existing prefixes: every ``site-packages/cmeel.prefix`` and ``sys.prefix``.
    """
    prefixes: list[Path] = []
    site_dirs: list[str] = []
    with contextlib.suppress(AttributeError):  # very old virtualenvs lack it
        site_dirs.extend(site.getsitepackages())
    user_site = site.getusersitepackages() if site.ENABLE_USER_SITE else None
    if user_site:
        site_dirs.append(user_site)
    site_dirs.extend(p for p in sys.path if p.endswith("site-packages"))
    for d in dict.fromkeys(site_dirs):
        cand = Path(d) / "cmeel.prefix"
        if cand.is_dir():
            prefixes.append(cand)
    prefixes.append(Path(sys.prefix))
    return list(dict.fromkeys(prefixes))


def _installed_packages(prefix: Path) -> dict[str, Path]:
    found = _ament_packages(prefix)
    share = prefix / "share"
    try:
        entries = sorted(os.listdir(share))
    except OSError:
        entries = []
    for name in entries:
        folder = share / name
        if (folder / "package.xml").is_file():
            found.setdefault(_package_name(folder), folder)
            found.setdefault(name, folder)
    return found


def _enclosing_package(source: Path) -> Path | None:
    folder = source if source.is_dir() else source.parent
    for cand in (folder, *folder.parents):
        if (cand / "package.xml").is_file():
            return cand
    return None


class _Place:
    """One search place: probed directly for ``<root>/<name>``, crawled in full on first miss."""

    __slots__ = ("crawl_root", "label", "load", "packages")

    def __init__(
        self, label: str, load: Callable[[], dict[str, Path]], crawl_root: Path | None = None
    ) -> None:
        self.label = label
        self.load = load
        self.crawl_root = crawl_root
        self.packages: dict[str, Path] | None = None

    def lookup(self, name: str) -> Path | None:
        if self.packages is None and self.crawl_root is not None:
            direct = _direct_package(self.crawl_root, name)
            if direct is not None:
                return direct
        if self.packages is None:
            self.packages = self.load()
        return self.packages.get(name)


class PackageResolver:
    """Finds ROS packages and resolves resource URIs, without ROS.

    Each search place is crawled lazily, at most once per resolver, the first time a package
    is not found in the places before it.

    Args:
        package_paths: Explicit folders, searched first (each crawled for ``package.xml``).
        source: The input file; the workspace that encloses it is searched.
        environ: Environment to read ``ROS_PACKAGE_PATH`` and ``AMENT_PREFIX_PATH`` from
            (``os.environ`` when None).
        use_installed: Whether to search pip-installed description packages.

    Example:
        >>> r = PackageResolver(["examples/robots"])  # doctest: +SKIP
        >>> r.resolve("package://robot0_description/urdf/robot0.urdf")  # doctest: +SKIP
    """

    def __init__(
        self,
        package_paths: Iterable[str | os.PathLike[str]] = (),
        *,
        source: str | os.PathLike[str] | None = None,
        environ: Mapping[str, str] | None = None,
        use_installed: bool = True,
    ) -> None:
        env = os.environ if environ is None else environ
        # Made absolute now, resolved on first use (realpath costs a system call per component).
        src = source if source is None or isinstance(source, str) else Path(source)
        if src is not None and not os.path.isabs(src):
            src = os.path.join(os.getcwd(), src)
        self._source_arg: str | Path | None = src
        self._source: Path | None = None
        self._use_installed = use_installed
        self._found: dict[str, Path] = {}
        places: list[_Place] = []
        for p in package_paths:
            path = Path(p).expanduser().resolve()
            places.append(_Place(f"-p {path}", lambda path=path: crawl_packages(path), path))
        for p in filter(None, env.get("ROS_PACKAGE_PATH", "").split(os.pathsep)):
            path = Path(p).expanduser()
            places.append(_Place(f"ROS_PACKAGE_PATH {path}", lambda path=path: crawl_packages(path), path))
        for p in filter(None, env.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
            path = Path(p).expanduser()
            places.append(_Place(f"AMENT_PREFIX_PATH {path}", lambda path=path: _ament_packages(path)))
        self._head = places
        self._all: list[_Place] | None = None

    @property
    def source(self) -> Path | None:
        """The input file (absolute, symlinks resolved), or None."""
        if self._source is None and self._source_arg is not None:
            self._source = Path(self._source_arg).resolve()
        return self._source

    @property
    def _places(self) -> list[_Place]:
        """Every search place in order; the workspace and installed ones are found on first use."""
        if self._all is None:
            places = list(self._head)
            source = self.source
            if source is not None:
                pkg = _enclosing_package(source)
                if pkg is not None:
                    ws = pkg.parent
                    places.append(
                        _Place(
                            f"workspace of {source.name}: {ws}",
                            lambda pkg=pkg, ws=ws: {
                                **crawl_packages(ws),
                                _package_name(pkg): pkg,
                            },
                        )
                    )
            if self._use_installed:
                for prefix in installed_prefixes():
                    places.append(
                        _Place(
                            f"installed packages in {prefix / 'share'}",
                            lambda p=prefix: _installed_packages(p),
                        )
                    )
            self._all = places
        return self._all

    def search_places(self) -> list[str]:
        """Describe every place searched, in search order."""
        return [p.label for p in self._places]

    def found_packages(self) -> dict[str, Path]:
        """Return the packages resolved so far by :meth:`find` (name -> folder)."""
        return dict(self._found)

    def find(self, package: str) -> Path:
        """Return the folder of ``package``.

        Args:
            package: ROS package name.

        Returns:
            The package folder (the one holding its ``package.xml``, or its ament share folder).

        Raises:
            PackageNotFound: If no search place has it; the message lists every place searched.
        """
        hit = self._found.get(package)
        if hit is not None:
            return hit
        for place in self._places:
            path = place.lookup(package)
            if path is not None:
                self._found[package] = path
                return path
        raise PackageNotFound(package, self.search_places())

    def resolve(self, uri: str, relative_to: str | os.PathLike[str] | None = None) -> Path:
        """Resolve a resource reference to a filesystem path (existence is not checked).

        Args:
            uri: ``package://pkg/rel`` (``package:///pkg/rel`` is accepted), ``file:///abs``,
                ``file://rel``, an absolute path or a path relative to ``relative_to``.
            relative_to: Folder (or file, whose folder is used) for relative references;
                defaults to the source file's folder, then the current directory.

        Returns:
            The resolved path.

        Raises:
            PackageNotFound: For a ``package://`` URI whose package is unknown.
            ResourceError: For an unsupported scheme or an empty reference.
        """
        text = uri.strip()
        if not text:
            raise ResourceError("empty resource reference")
        if text.startswith("package://"):
            # 'package:///pkg/x' (three slashes, seen in real files) is read as 'package://pkg/x';
            # `urdftk check` warns about it.
            rest = text[len("package://") :].lstrip("/")
            pkg, _, rel = rest.partition("/")
            if not pkg:
                raise ResourceError(f"'{uri}' names no package")
            return self.find(pkg) / unquote(rel)
        if text.startswith("file://"):
            text = unquote(text[len("file://") :])
        elif re.match(r"^[A-Za-z][A-Za-z0-9+.-]+://", text):
            scheme = text.split("://", 1)[0]
            raise ResourceError(
                f"unsupported URI scheme '{scheme}://' in '{uri}' (use package:// or file://)"
            )
        path = Path(text).expanduser()
        if path.is_absolute():
            return path
        if relative_to is not None:
            base = Path(relative_to)
            if base.is_file():
                base = base.parent
        elif self.source is not None:
            base = self.source.parent if not self.source.is_dir() else self.source
        else:
            base = Path.cwd()
        return base / path
