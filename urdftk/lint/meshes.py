"""Resource rules: mesh and texture files resolve, exist, and (optionally) load with trimesh."""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from urdftk.errors import PackageNotFound, ResourceError
from urdftk.lint._base import Context, Finding, describe
from urdftk.resources import PackageResolver

__all__ = ["lint", "load_problem"]


def load_problem(path: Path) -> tuple[str, str] | None:
    """Load a mesh with trimesh and say what is wrong with it.

    Args:
        path: An existing regular file.

    Returns:
        None when the mesh loads with at least one face, else ``(severity, message)``.
    """
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh")
    except Exception as exc:  # trimesh and its loaders raise anything on a bad file
        text = " ".join(str(exc).split())[:300] or type(exc).__name__
        return "error", f"trimesh cannot load {path}: {text}"
    faces = getattr(mesh, "faces", None)
    if faces is None or len(faces) == 0:
        return "warning", f"{path} loads but has no triangles"
    return None


class _Checker:
    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx
        self.resolver = ctx.resolver or PackageResolver(source=ctx.filename)
        self.base = Path(ctx.filename).resolve().parent if ctx.filename else Path.cwd()
        self.missing_packages: dict[str, int | None] = {}
        self.loaded: dict[Path, tuple[str, str] | None] = {}

    def check(self, el: etree._Element, kind: str, load: bool) -> list[Finding]:
        uri = (el.get("filename") or "").strip()
        if not uri:
            return []
        where = describe(el)
        line = el.sourceline
        missing = "error" if kind == "mesh" else "warning"
        try:
            path = self.resolver.resolve(uri, relative_to=self.base)
        except PackageNotFound as exc:
            first = self.missing_packages.setdefault(exc.package, line)
            message = str(exc) if first == line else f"package '{exc.package}' not found (see line {first})"
            return [Finding(missing, "package-not-found", where, line, f"{uri}: {message}")]
        except ResourceError as exc:
            return [Finding(missing, "bad-uri", where, line, str(exc))]
        if not path.exists():
            return [Finding(missing, f"{kind}-not-found", where, line, f"{uri}: file {path} does not exist")]
        if not path.is_file():
            return [
                Finding(missing, f"{kind}-not-found", where, line, f"{uri}: {path} is not a regular file")
            ]
        if not load:
            return []
        key = path.resolve()
        if key not in self.loaded:
            self.loaded[key] = load_problem(key)
        problem = self.loaded[key]
        if problem is None:
            return []
        severity, message = problem
        code = "mesh-load-failed" if severity == "error" else "empty-mesh"
        return [Finding("error" if severity == "error" else "warning", code, where, line, message)]


def lint(ctx: Context) -> list[Finding]:
    """Check every ``<mesh filename>`` and ``<texture filename>``.

    A mesh that does not resolve or exist is an error; a texture, a warning. Meshes are loaded
    with trimesh only when ``ctx.load_meshes`` (each file once).

    Args:
        ctx: The document.

    Returns:
        The findings.
    """
    checker = _Checker(ctx)
    out: list[Finding] = []
    for el in ctx.root.iter("mesh", "texture"):
        uri = (el.get("filename") or "").strip()
        if uri.startswith("package:///"):
            fixed = "package://" + uri[len("package://") :].lstrip("/")
            message = f"'{uri}' has three slashes (an empty package name in ROS); write '{fixed}'"
            out.append(Finding("warning", "bad-uri", describe(el), el.sourceline, message))
        if el.tag == "mesh":
            owner = el.getparent().getparent() if el.getparent() is not None else None
            if el.getparent().tag != "geometry" or owner is None or owner.tag not in ("visual", "collision"):
                continue
            out.extend(checker.check(el, "mesh", ctx.load_meshes))
        else:
            out.extend(checker.check(el, "texture", False))
    return out
