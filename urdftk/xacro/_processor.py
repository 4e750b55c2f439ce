"""The expander: walks the tree in document order, as stock xacro 2.1.1 does, node for node.

Every tree edit stock makes is made here too (including the shared blank text node that stock
moves around when it drops comments before xacro tags), because the pretty-printed output
depends on exactly which text nodes end up next to each other.
"""

from __future__ import annotations

import os
from typing import Any

from urdftk.errors import XacroError, close_names, format_location
from urdftk.xacro._context import Context, IncludeIOError
from urdftk.xacro._macros import Macro, first_element, resolve_macro, tree_size
from urdftk.xacro._scope import NameSpace, Scope
from urdftk.xacro._symbols import make_root
from urdftk.xacro._tree import Comment, Element, Text, XmlSyntaxError, clone, parse_xml

__all__ = ["MAX_CALLS", "MAX_DEPTH", "MAX_NODES", "Expander", "is_valid_name", "standalone_context", "to_bool"]

MAX_DEPTH = 100  # nested macro calls
MAX_CALLS = 200_000  # macro calls in one expansion
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
    import keyword
    import unicodedata

    return (
        isinstance(name, str)
        and name.isidentifier()
        and not keyword.iskeyword(name)
        and (name.isascii() or unicodedata.normalize("NFKC", name) == name)
    )


def _index(children: list, node: Any, hint: int = 0) -> int:
    if 0 <= hint < len(children) and children[hint] is node:
        return hint
    return children.index(node)


def _attrs(node: Element, required: list[str], optional: list[str], ctx: Context) -> list[Any]:
    attrs = node.attrs
    out = []
    for a in required:
        if a not in attrs:
            raise XacroError(f"{node.tag}: missing attribute '{a}'")
        out.append(attrs[a])
    out.extend(attrs.get(a) for a in optional)
    extra = [a for a in attrs if a not in required and a not in optional and not a.startswith("xmlns:")]
    if extra:
        ctx.warn(f"{node.tag}: unknown attribute(s): {', '.join(extra)}")
    return out


def standalone_context() -> Expander:
    """An expansion context for scopes used outside an expansion (compatibility API)."""
    ex = Expander()
    return ex


class Expander(Context):
    """One expansion of one document (see :class:`Context` for the arguments)."""

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self.root = make_root(self)
        self.empty = Text("\n\n")  # stock's shared blank node, moved by _drop_comments
        self.calls = 0
        self.hint = 0  # likely index of the node a tag handler works on
        self.include_keys: list[str] = []
        self.copied = 0
        self._tags = {
            "xacro:insert_block": self._insert_block,
            "xacro:include": self._include,
            "xacro:property": self._property,
            "xacro:macro": self._macro,
            "xacro:arg": self._arg,
            "xacro:attribute": self._attribute,
            "xacro:if": self._if,
            "xacro:unless": self._if,
            "xacro:call": self._dynamic_call,
        }

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

    def parse_file(self, name: str) -> tuple[list, Element]:
        """Read and parse a file (name as stock forms it; ``root_dir`` applied)."""
        return parse_xml(self.read_text(name), name)

    # -- errors -----------------------------------------------------------------------------
    def _locate(self, err: XacroError, file: str | None, line: int) -> None:
        if getattr(err, "located", False):
            return
        err.located = True  # type: ignore[attr-defined]
        err.xacro_files = list(self.files)  # type: ignore[attr-defined]
        err.xacro_macros = [(m.body.attrs.get("name", m.name), m.def_file) for m, _ in self.macro_stack]  # type: ignore[attr-defined]
        trace = []
        calls = list(reversed(self.macro_stack))
        for m, call in calls[:4]:
            trace.append(f"  in macro '{m.name}' called at {format_location(call.file, call.line)}")
        if len(calls) > 4:
            trace.append(f"  ... and {len(calls) - 4} more macro calls")
        for site in reversed(self.include_sites[-4:]):
            trace.append(f"  included from {format_location(site.file, site.line)}")
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
        if node.children:
            self.eval_children(node, macros, symbols)

    def _eval_attrs(self, node: Element, symbols: Scope) -> None:
        new = {}
        for k, v in node.attrs.items():
            if k[:6] == "xacro:":
                continue
            if "$" in v:
                try:
                    v = str(self.eval_text(v, symbols))
                except XacroError as e:
                    self._locate(e, node.file, node.line)
                    raise
            new[k] = v
        new.pop("xmlns:xacro", None)
        node.attrs = new

    def eval_children(self, parent: Element, macros: Scope, symbols: Scope) -> None:
        """Process the children of ``parent`` in order, expanding xacro tags in place."""
        children = parent.children
        i = 0
        node: Any = None
        eval_comments = False
        tags = self._tags
        try:
            while i < len(children):
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
                    tag = node.tag
                    if tag[:6] != "xacro:":
                        if node.static:
                            i += 1
                            continue
                        self.eval_all(node, macros, symbols)
                        # nested edits can only take the shared blank node out of this list
                        if i >= len(children) or children[i] is not node:
                            i = children.index(node)
                        i += 1
                        continue
                    n_before = len(children)
                    nxt = children[i + 1] if i + 1 < n_before else None
                    self.hint = i
                    handler = tags.get(tag)
                    if handler is not None:
                        handler(parent, node, macros, symbols)
                    elif tag == "xacro:element":
                        name = self.eval_text(_attrs(node, ["xacro:name"], [], self)[0], symbols)
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
                    i = i + 1 + len(children) - n_before
                    if not (0 <= i < len(children) and children[i] is nxt):
                        break  # nxt (stock's shared blank node) moved to another list: stock stops too
                    continue
                if cls is Comment:
                    data = node.data
                    if "xacro:eval-comments" in data:
                        eval_comments = "xacro:eval-comments:off" not in data
                        del children[i]
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
    def _replace(self, parent: Element, node: Any, owners: list[Element] | None) -> None:
        children = parent.children
        i = _index(children, node, self.hint)
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
        i = _index(children, node, self.hint)
        nxt = children[i + 1] if i + 1 < len(children) else None
        j = i - 1
        while j >= 0:
            prev = children[j]
            if prev.__class__ is str and prev.isspace() and prev.count("\n") <= 1:
                j -= 1
                prev = children[j] if j >= 0 else None
            if prev is not None and prev.__class__ is Comment:
                del children[j]
                i -= 1
                j -= 1
                continue
            empty = self.empty
            if nxt is not None and nxt is not empty:
                old = empty.parent
                if old is not None:
                    old.children.remove(empty)
                children.insert(_index(children, node, i) + 1, empty)
                empty.parent = parent
            self.hint = i
            return
        self.hint = i

    # -- xacro tags -------------------------------------------------------------------------
    def _insert_block(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        (name,) = _attrs(node, ["name"], [], self)
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
            children[_index(children, node, hint)] = block

    def _include(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        spec, ns, optional = _attrs(node, ["filename"], ["ns", "optional"], self)
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
            self._check_include_cycle(name)
            self.files.append(name)
            self.include_sites.append(node)
            self.include_keys.append(os.path.normpath(os.path.abspath(self.open_path(name))))
            try:
                _, root = self.parse_file(name)
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

    def _check_include_cycle(self, name: str) -> None:
        key = os.path.normpath(os.path.abspath(self.open_path(name)))
        stack = self.include_keys
        if key in stack:
            k = stack.index(key)
            chain = " -> ".join([*[f for f in self.files if f][k:], name])
            raise XacroError(f"include cycle: {chain}")
        if len(stack) >= MAX_DEPTH:
            raise XacroError(f"includes nested more than {MAX_DEPTH} deep")

    def _import_namespaces(self, parent: Element, attrs: dict[str, str]) -> None:
        for k, v in attrs.items():
            if k.startswith("xmlns:"):
                old = parent.attrs.get(k)
                if old is not None and old != v:
                    self.warn(f"inconsistent namespace redefinitions for {k}:\n old: {old}\n new: {v} ({self.files[-1]})")
                else:
                    parent.attrs = {**parent.attrs, k: v}

    def _property(self, parent: Element, node: Element, macros: Scope, table: Scope) -> None:
        self._drop_comments(parent, node)
        name, value, default, remove, scope, lazy = _attrs(
            node, ["name"], ["value", "default", "remove", "scope", "lazy_eval"], self
        )
        name = self.eval_text(name, table)
        if not is_valid_name(name):
            raise XacroError(f"Property names must be valid python identifiers: {name}")
        if name.startswith("__"):
            raise XacroError(f"Property names must not start with double underscore:{name}")
        remove = to_bool(self.eval_text(remove or "false", table), remove)
        if sum([value is not None, default is not None, remove]) > 1:
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
        lazy = to_bool(self.eval_text(lazy or "true", table), lazy)
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
                raise XacroError(f'property "{name}" with scope="parent" at global scope: there is no parent scope')
        else:
            target = table
        if not lazy and isinstance(value, str):
            value = self.eval_text(value, table)
        target.setitem(name, value, unevaluated=lazy)

    def _macro(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        self._drop_comments(parent, node)
        name, params = _attrs(node, ["name"], ["params"], self)
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
        name, default = _attrs(node, ["name", "default"], [], self)
        if name not in self.args:
            self.args[name] = str(self.eval_text(default, symbols))
        self._drop_comments(parent, node)
        self._replace(parent, node, None)

    def _attribute(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        name, value = (self.eval_text(a, symbols) for a in _attrs(node, ["name", "value"], [], self))
        if not name:
            raise XacroError("xacro:attribute: empty name")
        parent.attrs = {**parent.attrs, str(name): str(value)}
        self._replace(parent, node, None)

    def _if(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        self._drop_comments(parent, node)
        (cond,) = _attrs(node, ["value"], [], self)
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

    def _dynamic_call(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        (name,) = _attrs(node, ["macro"], [], self)
        if not name:
            raise XacroError("xacro:call is missing the 'macro' attribute")
        name = str(self.eval_text(name, symbols))
        node.attrs = {k: v for k, v in node.attrs.items() if k != "macro"}
        node.tag = "xacro:" + name
        if node.tag == "xacro:call":
            self._dynamic_call(parent, node, macros, symbols)
        else:
            self._call(parent, node, macros, symbols)

    def _budget(self, nodes: int) -> None:
        self.copied += nodes
        if self.copied > MAX_NODES:
            raise XacroError(f"expansion copies more than {MAX_NODES} nodes (exponential macro expansion?)")

    def _call(self, parent: Element, node: Element, macros: Scope, symbols: Scope) -> None:
        name = node.tag[6:]
        hint = self.hint
        try:
            scoped_macros, scoped_symbols, m = resolve_macro(name, macros, symbols)
        except KeyError:
            known = macros.visible_names()
            hint = close_names(name, known)
            extra = f" (did you mean {', '.join('xacro:' + h for h in hint)}?)" if hint else ""
            raise XacroError(f"unknown macro name: {node.tag}{extra}") from None
        if not isinstance(m, Macro):
            raise XacroError(f"unknown macro name: {node.tag} ('{name}' is not a macro)")
        self.calls += 1
        if self.calls > MAX_CALLS:
            raise XacroError(f"more than {MAX_CALLS} macro calls (exponential macro expansion?)")
        self._budget(m.size)
        if len(self.macro_stack) >= MAX_DEPTH:
            raise XacroError(self._cycle_message(m))
        body = clone(m.body)
        self.macro_stack.append((m, node))
        local = Scope(scoped_symbols)
        local_macros = Scope(scoped_macros)
        params = list(m.params)
        for k, v in node.attrs.items():
            if k not in params:
                hint = close_names(k, [p for p in params if p[0] != "*"])
                extra = f" (did you mean {', '.join(map(repr, hint))}?)" if hint else ""
                raise XacroError(f'Invalid parameter "{k}" of macro {m.name}{extra}')
            params.remove(k)
            local.setitem(k, self.eval_text(v, symbols) if "$" in v else v, unevaluated=False)
        if node.children:
            self.eval_children(node, macros, symbols)
        children = node.children
        bi, block = first_element(children)
        for p in [p for p in params if p[0] == "*"]:
            if block is None:
                raise XacroError(f"Not enough blocks for macro {m.name} (missing {p})")
            params.remove(p)
            local[p] = block
            bi, block = first_element(children, bi + 1)
        if block is not None:
            raise XacroError(f'Unused block "{block.tag}" in call of macro {m.name}')
        for p in [p for p in params if p[0] != "*"]:
            fwd, default = m.defaults.get(p, (None, None))
            if fwd is not None or default is not None:
                local.setitem(p, self._default(fwd, default, symbols), unevaluated=False)
                params.remove(p)
        if params:
            raise XacroError(f"Undefined parameters [{','.join(params)}] of macro {m.name}")
        self.eval_all(body, local_macros, local)
        self.hint = hint
        self._drop_comments(parent, node)
        self._import_namespaces(parent, body.attrs)
        self._replace(parent, node, [body])
        self.macro_stack.pop()

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
