"""``xacro.load_yaml``: yaml files as dicts with dotted access, and sandboxed unit tags.

``!degrees 90`` and its siblings evaluate their text with the same sandbox as ``${...}`` (only
the global symbols: ``pi``, ``radians(…)``, arithmetic), never with Python's ``eval`` on
builtins. PyYAML is imported on first use; its global loader classes are never modified.
"""

from __future__ import annotations

import math
from functools import lru_cache

from urdftk.errors import XacroError

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any

__all__ = ["UNITS", "YamlDict", "YamlList", "copy_data", "load_yaml_text", "wrap"]

#: tag -> factor to SI (radians, meters)
UNITS = {
    "!radians": 1.0,
    "!degrees": math.pi / 180.0,
    "!meters": 1.0,
    "!millimeters": 0.001,
    "!foot": 0.3048,
    "!inches": 0.0254,
}


def wrap(item: Any) -> Any:
    """Wrap dicts and lists so that nested items get dotted access too."""
    if isinstance(item, dict):
        return YamlDict(item)
    if isinstance(item, list):
        return YamlList(item)
    return item


class YamlList(list):
    """A yaml list whose items are wrapped on access."""

    def __getitem__(self, idx: Any) -> Any:
        return wrap(list.__getitem__(self, idx))

    def __iter__(self):
        for item in list.__iter__(self):
            yield wrap(item)


class YamlDict(dict):
    """A yaml mapping: ``d.key`` is ``d['key']``; a missing key raises AttributeError."""

    def __getattr__(self, item: str) -> Any:
        try:
            return wrap(dict.__getitem__(self, item))
        except KeyError:
            raise AttributeError(f"The yaml dictionary has no key '{item}'") from None

    __getitem__ = __getattr__


_ATOMS = frozenset({str, int, float, bool, type(None), bytes})


def copy_data(item: Any, memo: dict[int, Any] | None = None) -> Any:
    """Deep-copy loaded yaml (keeping the sharing that yaml aliases create), fast for plain data.

    Args:
        item: A value returned by :func:`load_yaml_text`.
        memo: Copies made so far, by ``id`` of the original.
    """
    cls = item.__class__
    if cls in _ATOMS:
        return item
    if memo is None:
        memo = {}
    done = memo.get(id(item))
    if done is not None:
        return done
    if cls is dict or cls is YamlDict:
        new = memo[id(item)] = cls()
        for k, v in dict.items(item):
            new[k] = copy_data(v, memo)
        return new
    if cls is list or cls is YamlList:
        new = memo[id(item)] = cls()
        new.extend([copy_data(v, memo) for v in list.__iter__(item)])
        return new
    import copy

    return copy.deepcopy(item, memo)


@lru_cache(maxsize=1)
def _loader_class() -> Any:
    """The yaml loader with the unit tags: a subclass, so PyYAML's own loaders stay untouched.

    Each loader instance gets the evaluation function of its expansion (``xacro_evaluate``).
    """
    import yaml

    base = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

    scalar = yaml.ScalarNode

    @lru_cache(maxsize=8192)
    def resolve_scalar(value: str, implicit: tuple[bool, bool]) -> str:
        return base.resolve(Loader, scalar, value, implicit)  # the tables are class attributes

    class Loader(base):  # type: ignore[valid-type,misc]
        xacro_evaluate: Callable[[str], Any]

        def resolve(self, kind: Any, value: Any, implicit: Any) -> str:
            """PyYAML's tag resolution, remembered per scalar text (it only reads class tables)."""
            if kind is scalar and implicit.__class__ is tuple:
                return resolve_scalar(value, implicit)
            return base.resolve(self, kind, value, implicit)

    def unit(factor: float) -> Callable:
        def construct(loader: Any, node: Any) -> float:
            text = loader.construct_scalar(node)
            try:
                return float(loader.xacro_evaluate(text)) * factor
            except SyntaxError:
                raise XacroError(f"invalid expression: {text}") from None

        return construct

    for tag, factor in UNITS.items():
        Loader.add_constructor(tag, unit(factor))
    return Loader


def load_yaml_text(stream: Any, evaluate: Callable[[str], Any], filename: str) -> Any:
    """Parse yaml with the unit tags, evaluating each tagged value with ``evaluate``.

    Args:
        stream: Text or a text file.
        evaluate: Sandboxed evaluation of a unit tag's text (global symbols only).
        filename: For error messages.

    Returns:
        The wrapped document.
    """
    try:
        import yaml
    except ImportError as e:  # pragma: no cover - pyyaml is a dependency
        raise XacroError("yaml support not available; install pyyaml") from e

    try:
        loader = _loader_class()(stream)  # as yaml.load does, with the evaluator attached
        loader.xacro_evaluate = evaluate
        try:
            node = loader.get_single_node()
            if node is None:
                return None
            try:
                return wrap(_construct_plain(loader, node, {}))
            except (_NotPlain, RecursionError):  # PyYAML's own construction: same result
                return wrap(loader.construct_document(node))
        finally:
            loader.dispose()
    except yaml.YAMLError as e:
        raise XacroError(f"{filename}: invalid yaml: {e}") from None


class _NotPlain(Exception):
    """The document has a node that PyYAML's own construction must handle."""


_YAML = "tag:yaml.org,2002:"
_SCALAR_TAGS = frozenset(_YAML + t for t in ("str", "int", "float", "bool", "null"))


def _construct_plain(loader: Any, node: Any, memo: dict[int, Any]) -> Any:
    """PyYAML's construction of a document of plain mappings, sequences and scalars, in one pass.

    PyYAML's generic construction (deferred generators, per-node bookkeeping) costs about as
    much as parsing; robot yaml files (joint limits, inertials) are plain data, so they are
    built here directly. Scalars still go through the loader's own constructors, so values are
    PyYAML's. Anything else (merge keys, unit tags, sets, timestamps, non-scalar keys...)
    raises :class:`_NotPlain`, and the caller lets PyYAML construct the whole document.
    """
    done = memo.get(id(node))
    if done is not None:
        return done  # an alias: the same object, as PyYAML gives
    tag = node.tag
    if tag in _SCALAR_TAGS:
        value = memo[id(node)] = loader.yaml_constructors[tag](loader, node)
        return value
    if tag == _YAML + "map" and node.id == "mapping":
        data: dict = {}
        memo[id(node)] = data
        for key_node, value_node in node.value:
            if key_node.tag not in _SCALAR_TAGS or key_node.id != "scalar":
                raise _NotPlain
            data[_construct_plain(loader, key_node, memo)] = _construct_plain(loader, value_node, memo)
        return data
    if tag == _YAML + "seq" and node.id == "sequence":
        items: list = []
        memo[id(node)] = items
        items.extend([_construct_plain(loader, child, memo) for child in node.value])
        return items
    raise _NotPlain
