"""The expander: walks the tree in document order, as stock xacro 2.1.1 does, node for node.

Every tree edit stock makes is made here too (including the shared blank text node that stock
moves around when it drops comments before xacro tags), because the pretty-printed output
depends on exactly which text nodes end up next to each other.
"""

from __future__ import annotations

import os

from urdftk.errors import XacroError, close_names, format_location
from urdftk.xacro._macros import Macro, first_element, resolve_macro
from urdftk.xacro._scope import Scope, literal
from urdftk.xacro._share import copy_shallow
from urdftk.xacro._symbols import make_root
from urdftk.xacro._tags import MAX_DEPTH, MAX_NODES, Tags, attrs_of, index_of, is_valid_name, to_bool
from urdftk.xacro._tree import Comment, Element, Text, XmlSyntaxError, line_of

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

__all__ = [
    "MAX_CALLS",
    "MAX_DEPTH",
    "MAX_NODES",
    "Expander",
    "is_valid_name",
    "standalone_context",
    "to_bool",
]

MAX_CALLS = 200_000  # macro calls in one expansion

# Tags whose handlers never edit the tag element itself: one from a macro body needs no copy.
_READ_ONLY = frozenset(
    ["xacro:property", "xacro:arg", "xacro:include", "xacro:insert_block", "xacro:attribute"]
)


def standalone_context() -> Expander:
    """An expansion context for scopes used outside an expansion (compatibility API)."""
    ex = Expander()
    return ex


class Expander(Tags):
    """One expansion of one document (see :class:`Context` for the arguments)."""

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self.root = make_root(self)
        self.calls = 0

    # -- entry points ---------------------------------------------------------------------
    def process(self, top: list, root: Element, filename: str | None) -> list:
        """Expand a parsed document in place; return its document-level nodes."""
        self.files = [filename]
        self.include_keys = [os.path.normpath(os.path.abspath(self.open_path(filename)))] if filename else []
        tns = root.attrs.get("xacro:targetNamespace")
        if tns:
            attrs = {k: v for k, v in root.attrs.items() if k != "xacro:targetNamespace"}
            attrs["xmlns"] = tns
            root.attrs = attrs
        try:
            self.eval_all(root, Scope(ctx=self), Scope(self.root, ctx=self))
        except RecursionError:
            raise XacroError(
                f"{filename or '<string>'}: the document or its macros nest too deeply to expand"
            ) from None
        return top

    def release(self) -> None:
        """Drop what refers back to the expansion (global symbols, parsed trees) once it is done.

        The symbol table's functions refer to the expansion: without this, the expansion and
        every tree it parsed would wait for Python's cyclic garbage collector.
        """
        self.root = {}
        self.parsed = {}
        self._eval_scope = None
        self.empty.parent = None
        self.macro_stack = []

    # -- errors -----------------------------------------------------------------------------
    def _locate(self, err: XacroError, file: str | None, line: int) -> None:
        if getattr(err, "located", False):
            return
        line = line_of(file, line)
        file = str(file) if file is not None else None  # (a plain name, not a SourceName)
        err.located = True  # type: ignore[attr-defined]
        err.xacro_files = list(self.files)  # type: ignore[attr-defined]
        err.xacro_macros = [(m.body.attrs.get("name", m.name), m.def_file) for m, _ in self.macro_stack]  # type: ignore[attr-defined]
        trace = []
        calls = list(reversed(self.macro_stack))
        for m, call in calls[:4]:
            where = format_location(call.file, line_of(call.file, call.line))
            trace.append(f"  in macro '{m.name}' called at {where}")
        if len(calls) > 4:
            trace.append(f"  ... and {len(calls) - 4} more macro calls")
        for site in reversed(self.include_sites[-4:]):
            trace.append(f"  included from {format_location(site.file, line_of(site.file, site.line))}")
        text = err.args[0] if err.args else str(err)
        err.message = text  # type: ignore[attr-defined]
        if isinstance(err, XmlSyntaxError):
            err.args = ("\n".join([text, *trace]),)
            return
        err.filename, err.line = file, line  # type: ignore[attr-defined]
        err.args = ("\n".join([f"{format_location(file, line)}: {text}", *trace]),)

    # -- the walk ---------------------------------------------------------------------------
    def eval_all(self, node: Element, macros: Scope, symbols: Scope) -> None:
        """Evaluate an element's attributes, then its children."""
        if node.static:
            return
        attrs = node.attrs
        if attrs:
            for k, v in attrs.items():
                if "$" in v or k[:6] == "xacro:" or k == "xmlns:xacro":
                    self._eval_attrs(node, symbols)
                    break
        if node.children and not node.fixed:
            self.eval_children(node, macros, symbols)

    def _eval_attrs(self, node: Element, symbols: Scope) -> None:
        new = {}
        eval_text = self.eval_text
        try:
            for k, v in node.attrs.items():
                if k[0] == "x" and k[:6] == "xacro:":
                    continue
                if "$" in v:
                    v = eval_text(v, symbols)
                    if v.__class__ is not str:
                        v = str(v)
                new[k] = v
        except XacroError as e:
            self._locate(e, node.file, node.line)
            raise
        new.pop("xmlns:xacro", None)
        node.attrs = new

    def _instantiate(self, el: Element, symbols: Scope) -> Element:
        """Expand a ``pure`` subtree of a macro body: what the walk does to it, without its dispatch.

        The walk would copy each element, evaluate its attributes, then its text children in
        order; a pure subtree has nothing else (no xacro tag, no comment to evaluate), and its
        ``plan`` says which attributes and children change.
        """
        if el.fixed:
            new = Element(el.tag, el.attrs, el.line, el.file, el.children)
            new.fixed = True
            if el.plan[0]:
                self._eval_attrs(new, symbols)
            return new
        kids = el.children.copy()
        new = Element(el.tag, el.attrs, el.line, el.file, kids)
        dynamic_attrs, dynamic = el.plan
        if dynamic_attrs:
            self._eval_attrs(new, symbols)
        try:
            for i in dynamic:
                c = kids[i]
                if c.__class__ is str:
                    kids[i] = str(self.eval_text(c, symbols))
                else:
                    kids[i] = self._instantiate(c, symbols)
        except XacroError as e:
            self._locate(e, new.file, new.line)
            raise
        return new

    def eval_children(self, parent: Element, macros: Scope, symbols: Scope) -> None:
        """Process the children of ``parent`` in order, expanding xacro tags in place."""
        children = parent.children
        i = 0
        node: Any = None
        eval_comments = False
        tags = _TAGS
        n = len(children)  # kept up to date after every edit that changes it
        try:
            while i < n:
                node = children[i]
                cls = node.__class__
                if cls is str:
                    if "$" in node:
                        node = children[i] = str(self.eval_text(node, symbols))
                    if eval_comments and node.strip():
                        eval_comments = False
                    i += 1
                    continue
                if cls is Element:
                    eval_comments = False
                    # part of a macro body: skip it if static, else copy it first (unless it is a
                    # xacro tag whose handler only reads it)
                    if node.shared and (node.static or node.tag not in _READ_ONLY):
                        if node.static:
                            i += 1
                            continue
                        if node.pure:
                            children[i] = self._instantiate(node, symbols)
                            i += 1
                            continue
                        if node.fixed:  # copy_shallow, inlined
                            new = Element(node.tag, node.attrs, node.line, node.file, node.children)
                            new.fixed = True
                        else:
                            new = Element(node.tag, node.attrs, node.line, node.file, node.children.copy())
                        node = children[i] = new
                    tag = node.tag
                    if tag[:6] != "xacro:":  # eval_all, inlined (node is not static here)
                        attrs = node.attrs
                        if attrs:
                            for k, v in attrs.items():
                                if "$" in v or k[:6] == "xacro:" or k == "xmlns:xacro":
                                    self._eval_attrs(node, symbols)
                                    break
                        if node.children and not node.fixed:
                            self.eval_children(node, macros, symbols)
                            # nested edits can only take the shared blank node out of this list
                            n = len(children)
                            if i >= n or children[i] is not node:
                                i = i - 1 if 0 < i <= n and children[i - 1] is node else children.index(node)
                        i += 1
                        continue
                    n_before = n
                    nxt = children[i + 1] if i + 1 < n else None
                    self.hint = i
                    handler = tags.get(tag)
                    if handler is not None:
                        handler(self, parent, node, macros, symbols)
                    elif tag == "xacro:element":
                        name = self.eval_text(attrs_of(node, ("xacro:name",), (), self)[0], symbols)
                        if not name:
                            raise XacroError("xacro:element: empty name")
                        node.attrs = {k: v for k, v in node.attrs.items() if k != "xacro:name"}
                        node.tag = str(name)
                        continue  # process the renamed element again
                    else:
                        self._call(parent, node, macros, symbols)
                    if nxt is None:
                        break
                    # every edit is before nxt, so its new index follows from the length change
                    n = len(children)
                    i = i + 1 + n - n_before
                    if not (0 <= i < n and children[i] is nxt):
                        break  # nxt (stock's shared blank node) moved to another list: stock stops too
                    continue
                if cls is Comment:
                    data = node.data
                    if "xacro:eval-comments" in data:
                        eval_comments = "xacro:eval-comments:off" not in data
                        del children[i]
                        n -= 1
                        continue
                    if eval_comments and "$" in data:
                        children[i] = Comment(str(self.eval_text(data, symbols)), node.line)
                elif cls is Text and eval_comments and node.data.strip():
                    eval_comments = False
                i += 1
        except XacroError as e:
            if node.__class__ is Element:
                self._locate(e, node.file, node.line)
            else:
                self._locate(e, parent.file, getattr(node, "line", 0) or parent.line)
            raise

    # -- tree edits (stock's replace_node and remove_previous_comments) ------------------------
    def _dynamic_call(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        (name,) = attrs_of(node, ("macro",), (), self)
        if not name:
            raise XacroError("xacro:call is missing the 'macro' attribute")
        name = str(self.eval_text(name, symbols))
        node.attrs = {k: v for k, v in node.attrs.items() if k != "macro"}
        node.tag = "xacro:" + name
        if node.tag == "xacro:call":
            self._dynamic_call(parent, node, macros, symbols)
        else:
            self._call(parent, node, macros, symbols)

    def _call(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        name = node.tag[6:]
        hint = self.hint
        try:
            try:  # resolve_macro, inlined for a name without a namespace
                m = macros[name]
                scoped_macros, scoped_symbols = macros, symbols
            except KeyError:
                scoped_macros, scoped_symbols, m = resolve_macro(name, macros, symbols)
        except KeyError:
            known = macros.visible_names()
            hint = close_names(name, known)
            extra = f" (did you mean {', '.join('xacro:' + h for h in hint)}?)" if hint else ""
            raise XacroError(f"unknown macro name: {node.tag}{extra}") from None
        if m.__class__ is not Macro:
            raise XacroError(f"unknown macro name: {node.tag} ('{name}' is not a macro)")
        self.calls += 1
        if self.calls > MAX_CALLS:
            raise XacroError(f"more than {MAX_CALLS} macro calls (exponential macro expansion?)")
        size = m._size
        self.copied += size if size is not None else m.size  # _budget, inlined
        if self.copied > MAX_NODES:
            self._budget(0)
        stack = self.macro_stack
        if len(stack) >= MAX_DEPTH:
            raise XacroError(self._cycle_message(m))
        src = m.body
        body = copy_shallow(src)  # the walk copies the rest as it goes
        stack.append((m, node))
        local = Scope(scoped_symbols)
        local_macros = Scope(scoped_macros)
        given = node.attrs
        if given:
            param_set = m.param_set
            root = local.root
            for k, v in given.items():
                if k not in param_set:
                    hint = close_names(k, [p for p in m.params if p[0] != "*"])
                    extra = f" (did you mean {', '.join(map(repr, hint))}?)" if hint else ""
                    raise XacroError(f'Invalid parameter "{k}" of macro {m.name}{extra}')
                if "$" in v:
                    v = self.eval_text(v, symbols)
                if k in root:  # Scope.setitem(k, v, unevaluated=False), inlined (local is new)
                    self.warn(f"redefining global symbol: {k}")
                dict.__setitem__(local, k, literal(v))
        children = node.children
        if children:
            self.eval_children(node, macros, symbols)
            bi, block = first_element(children)
        else:
            bi, block = 0, None
        for p in m.blocks:
            if block is None:
                raise XacroError(f"Not enough blocks for macro {m.name} (missing {p})")
            local[p] = block
            bi, block = first_element(children, bi + 1)
        if block is not None:
            raise XacroError(f'Unused block "{block.tag}" in call of macro {m.name}')
        missing = None
        defaults = m.defaults
        plain, skip = m.plain, given
        if m.dups:  # as stock: each argument given takes one occurrence of its name off the list
            rest = list(m.params)
            for k in given:
                rest.remove(k)
            plain, skip = [p for p in rest if p[0] != "*"], {}
        for p in plain:
            if p in skip:
                continue
            fwd, default = defaults.get(p, (None, None))
            if fwd is not None or default is not None:
                local.setitem(p, self._default(fwd, default, symbols), unevaluated=False)
            elif missing is None:
                missing = [p]
            else:
                missing.append(p)
        if missing:
            raise XacroError(f"Undefined parameters [{','.join(missing)}] of macro {m.name}")
        for k, v in body.attrs.items():  # eval_all, inlined (the body is a fresh copy)
            if "$" in v or k[:6] == "xacro:" or k == "xmlns:xacro":
                self._eval_attrs(body, local)
                break
        if body.children and not body.fixed:
            self.eval_children(body, local_macros, local)
        self.hint = hint
        self._drop_comments(parent, node)
        if m.has_ns or body.attrs is not src.attrs:  # (an include in the body may add some)
            self._import_namespaces(parent, body.attrs)
        children = parent.children  # _replace(parent, node, [body]), inlined
        i = self.hint
        if not (0 <= i < len(children) and children[i] is node):
            i = index_of(children, node, i)
        children[i : i + 1] = body.children
        if self.empty.parent is body:
            self.empty.parent = parent
        stack.pop()

    def _default(self, forward: str | None, default: str | None, symbols: Scope) -> Any:
        if forward is None:
            return self.eval_text(default, symbols)
        try:
            return symbols[forward]
        except KeyError:
            if default is not None:
                return self.eval_text(default, symbols)
            raise XacroError(f"Undefined property to forward: {forward}") from None

    def _cycle_message(self, m: Macro) -> str:
        names = [mm.name for mm, _ in self.macro_stack] + [m.name]
        last = names[-1]
        k = len(names) - 2
        while k >= 0 and names[k] != last:
            k -= 1
        if k >= 0:
            cycle = names[k:]
            return (
                f"macro recursion cycle: {' -> '.join(cycle)} ({MAX_DEPTH} nested macro calls without "
                "reaching an end); make the recursion stop, e.g. with xacro:if"
            )
        shown = " -> ".join([*names[:3], "...", *names[-2:]])
        return f"macro calls nested more than {MAX_DEPTH} deep: {shown}"


# tag -> handler (functions, not bound methods: an expansion holding its own bound methods
# would be a reference cycle)
_TAGS = {
    "xacro:insert_block": Expander._insert_block,
    "xacro:include": Expander._include,
    "xacro:property": Expander._property,
    "xacro:macro": Expander._macro,
    "xacro:arg": Expander._arg,
    "xacro:attribute": Expander._attribute,
    "xacro:if": Expander._if,
    "xacro:unless": Expander._if,
    "xacro:call": Expander._dynamic_call,
}
