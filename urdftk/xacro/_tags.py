"""The xacro tags other than macro calls, and the two tree edits stock makes around them.

``xacro:property``, ``xacro:macro``, ``xacro:arg``, ``xacro:include``, ``xacro:if``/``unless``,
``xacro:insert_block`` and ``xacro:attribute`` behave as in stock xacro 2.1.1, including which
comments before a tag are dropped (and where stock's shared blank text node goes).
"""

from __future__ import annotations

import os
from keyword import iskeyword

from urdftk.errors import XacroError, close_names
from urdftk.xacro._context import Context, IncludeIOError
from urdftk.xacro._macros import Macro, first_element, tree_size
from urdftk.xacro._scope import NameSpace, Scope
from urdftk.xacro._share import clone, mark_static
from urdftk.xacro._tree import Comment, Element, Text, parse_xml

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

__all__ = ["MAX_DEPTH", "MAX_NODES", "Tags", "attrs_of", "index_of", "is_valid_name", "to_bool"]

MAX_DEPTH = 100  # nested macro calls, and nested includes
MAX_NODES = 3_000_000  # nodes copied from macro bodies and blocks


def to_bool(value: Any, condition: Any) -> bool:
    """Stock's truth rule: 'true'/'false' words, integers in text, else Python truth."""
    try:
        if isinstance(value, str):
            if value == "true" or value == "True":
                return True
            if value == "false" or value == "False":
                return False
            return bool(int(value))
        return bool(value)
    except Exception:
        raise XacroError(
            f'Xacro conditional "{condition}" evaluated to "{value}", which is not a boolean expression.'
        ) from None


def is_valid_name(name: Any) -> bool:
    """Whether ``name`` can be a property or macro name (a Python identifier, not a keyword)."""
    if not (isinstance(name, str) and name.isidentifier() and not iskeyword(name)):
        return False
    if name.isascii():
        return True
    import unicodedata

    return unicodedata.normalize("NFKC", name) == name


def index_of(children: list, node: Any, hint: int = 0) -> int:
    """Index of ``node`` (an element or the blank node: compared by identity), looked for near ``hint``."""
    if 0 <= hint < len(children) and children[hint] is node:
        return hint
    if hint > 4:
        try:
            return children.index(node, hint - 4)
        except ValueError:
            pass
    return children.index(node)


def attrs_of(node: Element, required: tuple[str, ...], optional: tuple[str, ...], ctx: Context) -> list[Any]:
    attrs = node.attrs
    get = attrs.get
    out = list(map(get, required))
    if None in out:
        missing = required[out.index(None)]
        raise XacroError(f"{node.tag}: missing attribute '{missing}'")
    if optional:
        out.extend(map(get, optional))
    if len(attrs) > len(out) - out.count(None):  # some attribute is neither required nor optional
        extra = [a for a in attrs if a not in required and a not in optional and not a.startswith("xmlns:")]
        if extra:
            ctx.warn(f"{node.tag}: unknown attribute(s): {', '.join(extra)}")
    return out


class Tags(Context):
    """Tag handlers; :class:`urdftk.xacro._processor.Expander` adds the walk and macro calls."""

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self.empty = Text("\n\n")  # stock's shared blank node, moved by _drop_comments
        self.hint = 0  # likely index of the node a tag handler works on
        self.include_keys: list[str] = []
        self._include_key: dict[str, str] = {}  # file name -> its absolute path (for include_keys)
        self.copied = 0
        self.parsed: dict[str, Element | None] = {}  # included file -> its shared tree, if included again

    def eval_all(self, node: Element, macros: Scope, symbols: Scope) -> None:  # pragma: no cover
        raise NotImplementedError

    def eval_children(self, parent: Element, macros: Scope, symbols: Scope) -> None:  # pragma: no cover
        raise NotImplementedError

    def parse_file(self, name: str) -> tuple[list, Element]:
        """Read and parse a file (name as stock forms it; ``root_dir`` applied)."""
        return parse_xml(self.read_text(name), name, positions=True)

    def _budget(self, nodes: int) -> None:
        self.copied += nodes
        if self.copied > MAX_NODES:
            raise XacroError(f"expansion copies more than {MAX_NODES} nodes (exponential macro expansion?)")

    def _replace(self, parent: Element, node: Any, owners: list[Element] | None) -> None:
        children = parent.children
        i = index_of(children, node, self.hint)
        if owners is None:
            del children[i]
            return
        content: list = []
        for owner in owners:
            content.extend(owner.children)
            if self.empty.parent is owner:
                self.empty.parent = parent
        children[i : i + 1] = content

    def _drop_comments(self, parent: Element, node: Any) -> None:
        children = parent.children
        i = self.hint
        if not (0 <= i < len(children) and children[i] is node):
            i = index_of(children, node, i)
        nxt = children[i + 1] if i + 1 < len(children) else None
        j = i - 1
        move = False  # stock moves its blank node unless the walk back ran off the list's start
        while j >= 0:
            prev = children[j]
            if prev.__class__ is str and prev.isspace() and prev.count("\n") <= 1:
                j -= 1
                if j < 0:
                    move = True  # (stock's prev is None here)
                    break
                prev = children[j]
            if prev.__class__ is Comment:
                del children[j]
                i -= 1
                j -= 1
                continue
            move = True
            break
        empty = self.empty
        if move and nxt is not None and nxt is not empty:
            old = empty.parent
            if old is parent:  # usually a few places before node: look back by identity
                k = i - 1
                while k >= 0 and children[k] is not empty:
                    k -= 1
                if k < 0:
                    k = index_of(children, empty, i)
                del children[k]
                if k < i:
                    i -= 1
            elif old is not None:  # usually near the end of its list: search backwards
                others = old.children
                k = len(others) - 1
                while k >= 0 and others[k] is not empty:
                    k -= 1
                if k < 0:
                    others.remove(empty)  # not there: ValueError, as before
                del others[k]
            children.insert(i + 1, empty)
            empty.parent = parent
        self.hint = i

    # -- xacro tags -------------------------------------------------------------------------
    def _insert_block(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        (name,) = attrs_of(node, ("name",), (), self)
        if "**" + name in symbols:
            block, content_only = symbols["**" + name], True
        elif "*" + name in symbols:
            block, content_only = symbols["*" + name], False
        else:
            blocks = [n.lstrip("*") for n in symbols.visible_names(blocks=True)]
            hint = close_names(name, blocks)
            extra = f" (did you mean {', '.join(map(repr, hint))}?)" if hint else ""
            raise XacroError(f'Undefined block "{name}"{extra}')
        self._budget(tree_size(block))
        block = clone(block)
        hint = self.hint
        self.eval_all(block, macros, symbols)
        self.hint = hint
        if content_only:
            self._replace(parent, node, [block])
        else:
            children = parent.children
            children[index_of(children, node, hint)] = block

    def _include(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        spec, ns, optional = attrs_of(node, ("filename",), ("ns", "optional"), self)
        if ns:
            ns = self.eval_text(ns, symbols)
            ns_macros = NameSpace(ctx=self)
            macros[ns] = ns_macros
            ns_symbols = NameSpace(symbols)
            symbols[ns] = ns_symbols
        else:
            ns_macros, ns_symbols = macros, symbols
        optional = to_bool(optional, None)
        if first_element(node.children)[1] is not None:
            self.warn("Child elements of a <xacro:include> tag are ignored")
        spec = self.abs_filename(self.eval_text(spec, symbols))
        if "*" in spec or "[" in spec or "?" in spec:
            import glob

            names = sorted(glob.glob(spec))
            if not names:
                self.warn(f'Include tag\'s filename spec "{spec}" matched no files.')
        else:
            names = [spec]
        roots = []
        hint = self.hint
        for name in names:
            self.includes.append(name)
            key = self._check_include_cycle(name)
            self.files.append(name)
            self.include_sites.append(node)
            self.include_keys.append(key)
            try:
                root = self._parse_include(name)
            except IncludeIOError:
                self.files.pop()
                self.include_sites.pop()
                self.include_keys.pop()
                if optional is True:
                    continue
                raise
            self.eval_all(root, ns_macros, ns_symbols)
            roots.append(root)
            self._import_namespaces(parent, root.attrs)
            self.files.pop()
            self.include_sites.pop()
            self.include_keys.pop()
        self.hint = hint
        self._drop_comments(parent, node)
        self._replace(parent, node, roots)

    def _parse_include(self, name: str) -> Element:
        """A fresh tree of an included file; a file included again is parsed once more, not again.

        Most files are included once: they are parsed and walked in place. The second inclusion
        keeps its tree, marked for sharing like a macro body, and every inclusion copies it.
        """
        tree = self.parsed.get(name)
        if tree is None:
            _, tree = self.parse_file(name)
            if name not in self.parsed:
                self.parsed[name] = None
                return tree
            mark_static(tree)  # shared from now on: the walk copies what it edits
            self.parsed[name] = tree
        return clone(tree)

    def _check_include_cycle(self, name: str) -> str:
        key = self._include_key.get(name)
        if key is None:  # (abspath asks the OS for the current directory every time)
            key = self._include_key[name] = os.path.normpath(os.path.abspath(self.open_path(name)))
        stack = self.include_keys
        if key in stack:
            k = stack.index(key)
            chain = " -> ".join([*[f for f in self.files if f][k:], name])
            raise XacroError(f"include cycle: {chain}")
        if len(stack) >= MAX_DEPTH:
            raise XacroError(f"includes nested more than {MAX_DEPTH} deep")
        return key

    def _import_namespaces(self, parent: Element, attrs: dict[str, str]) -> None:
        for k, v in attrs.items():
            if k.startswith("xmlns:"):
                old = parent.attrs.get(k)
                if old is not None and old != v:
                    where = self.files[-1]
                    self.warn(
                        f"inconsistent namespace redefinitions for {k}:\n old: {old}\n new: {v} ({where})"
                    )
                else:
                    parent.attrs = {**parent.attrs, k: v}

    def _property(self, parent: Element, node: Element, macros: Scope, table: Scope) -> None:
        attrs = node.attrs
        if len(attrs) == 2:  # the common form, name="n" value="v": what the general path does
            name = attrs.get("name")
            value = attrs.get("value")
            if name is not None and value is not None and "$" not in name:
                if not is_valid_name(name):
                    raise XacroError(f"Property names must be valid python identifiers: {name}")
                if name[:2] == "__":
                    raise XacroError(f"Property names must not start with double underscore:{name}")
                self._drop_comments(parent, node)
                children = parent.children  # _replace(parent, node, None), inlined
                i = self.hint
                if 0 <= i < len(children) and children[i] is node:
                    del children[i]
                else:
                    self._replace(parent, node, None)
                table.setitem(name, value, unevaluated=True)
                return
        self._drop_comments(parent, node)
        name, value, default, remove, scope, lazy = attrs_of(
            node, ("name",), ("value", "default", "remove", "scope", "lazy_eval"), self
        )
        if "$" in name:
            name = self.eval_text(name, table)
        if not is_valid_name(name):
            raise XacroError(f"Property names must be valid python identifiers: {name}")
        if name.startswith("__"):
            raise XacroError(f"Property names must not start with double underscore:{name}")
        remove = False if not remove else to_bool(self.eval_text(remove, table), remove)
        if (value is not None) + (default is not None) + bool(remove) > 1:
            raise XacroError(f"Property attributes default, value, and remove are mutually exclusive: {name}")
        if remove and name in table:
            del table[name]
            self._replace(parent, node, None)
            return
        if default is not None:
            if scope is not None:
                self.warn(f"{name}: default property value can only be defined on local scope")
            if name not in table:
                value = default
            else:
                self._replace(parent, node, None)
                return
        if value is None:
            name = "**" + name
            value = node
        self._replace(parent, node, None)
        lazy = True if not lazy else to_bool(self.eval_text(lazy, table), lazy)
        if scope == "global":
            target = table.top()
            lazy = False
        elif scope == "parent":
            target = table.parent
            lazy = False
            if not isinstance(table, NameSpace):
                while isinstance(target, NameSpace):
                    target = target.parent
            if not isinstance(target, Scope):
                raise XacroError(
                    f'property "{name}" with scope="parent" at global scope: there is no parent scope'
                )
        else:
            target = table
        if not lazy and isinstance(value, str):
            value = self.eval_text(value, table)
        target.setitem(name, value, unevaluated=lazy)

    def _macro(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        self._drop_comments(parent, node)
        name, params = attrs_of(node, ("name",), ("params",), self)
        if name == "call":
            raise XacroError("Invalid use of macro name 'call'")
        if "." in name:
            raise XacroError(f"macro names must not contain '.' (reserved for namespaces): {name}")
        if name.startswith("xacro:"):
            self.warn(f"macro names must not contain prefix 'xacro:': {name}")
            name = name[6:]
        macros[name] = Macro(name, node, params or "", self.files[-1])
        self._replace(parent, node, None)

    def _arg(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        name, default = attrs_of(node, ("name", "default"), (), self)
        if name not in self.args:
            self.args[name] = str(self.eval_text(default, symbols))
        self._drop_comments(parent, node)
        self._replace(parent, node, None)

    def _attribute(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        name, value = (self.eval_text(a, symbols) for a in attrs_of(node, ("name", "value"), (), self))
        if not name:
            raise XacroError("xacro:attribute: empty name")
        parent.attrs = {**parent.attrs, str(name): str(value)}
        self._replace(parent, node, None)

    def _if(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        self._drop_comments(parent, node)
        (cond,) = attrs_of(node, ("value",), (), self)
        keep = to_bool(self.eval_text(cond, symbols), cond)
        if node.tag == "xacro:unless":
            keep = not keep
        if keep:
            if node.children:
                hint = self.hint
                self.eval_children(node, macros, symbols)
                self.hint = hint
            self._replace(parent, node, [node])
        else:
            self._replace(parent, node, None)
