"""Sharing macro bodies between calls: which parts evaluation can change, and cheap copies.

A macro body (or a file included more than once) is marked once (:func:`mark_static`): its
unchanging subtrees are then shared by every expansion instead of copied, and the parts that
only evaluate attributes and text get a ``plan`` (see :class:`urdftk.xacro._tree.Element`).
"""

from __future__ import annotations

from urdftk.xacro._tree import Comment, Element, Text

__all__ = ["clone", "copy_shallow", "mark_static"]


def copy_shallow(el: Element) -> Element:
    """Copy an element and its child list, not the children (the walk copies those it edits).

    The child list of a ``fixed`` element is shared, as nothing ever edits it.

    Args:
        el: The element (usually a ``shared`` one).

    Returns:
        The copy (not ``shared``).
    """
    if el.fixed:
        new = Element(el.tag, el.attrs, el.line, el.file, el.children)
        new.fixed = True
        return new
    return Element(el.tag, el.attrs, el.line, el.file, el.children.copy())


def clone(el: Element) -> Element:
    """Deep-copy an element: new elements and lists; text, comments and attribute dicts are shared.

    Shared parts are never mutated in place (edits replace them in their list); static subtrees
    and the child lists of ``fixed`` elements are shared too.

    Args:
        el: The element to copy.

    Returns:
        The copy.
    """
    if el.fixed:  # nothing ever edits this list: share it
        new = Element(el.tag, el.attrs, el.line, el.file, el.children)
        new.fixed = True
        return new
    new = Element(el.tag, el.attrs, el.line, el.file)
    kids = new.children
    for c in el.children:
        cls = c.__class__
        if cls is Element:
            if not c.static:
                c = clone(c)
        elif cls is Text:
            c = c.data
        kids.append(c)
    return new


def _plain_attrs(attrs: dict[str, str]) -> bool:
    """Whether evaluation leaves these attributes as they are (no ``$``, no xacro attribute).

    Conservative: any attribute name containing "xacro" (``xacro:*``, ``xmlns:xacro``) counts.
    """
    for k, v in attrs.items():  # noqa: SIM110 (a loop: no generator frame for one or two items)
        if "$" in v or "xacro" in k:
            return False
    return True


def mark_static(el: Element) -> int:
    """Set ``static``, ``fixed``, ``pure`` (and ``plan``) below ``el`` and on it; return its node count."""
    attrs = el.attrs
    pure = el.tag[:6] != "xacro:"
    plain = pure and (not attrs or _plain_attrs(attrs))
    children = el.children
    size = 1 + len(children)
    fixed = True
    dynamic = None  # indices of the children that evaluation changes
    i = -1
    for c in children:
        i += 1
        cls = c.__class__
        if cls is str:
            if "$" in c:
                fixed = False
                if dynamic is None:
                    dynamic = [i]
                else:
                    dynamic.append(i)
            continue
        if cls is Element:
            if c.children:
                size += mark_static(c) - 1
                if c.static:
                    continue
                child_pure = c.pure
            else:  # a leaf (most are), inlined
                c.fixed = True
                c.shared = True
                child_pure = c.pure = c.tag[:6] != "xacro:"
                a = c.attrs
                if child_pure and (not a or _plain_attrs(a)):
                    c.static = True
                    continue
                c.static = False
                if child_pure:
                    c.plan = (True, ())
            fixed = False
            if dynamic is None:
                dynamic = [i]
            else:
                dynamic.append(i)
            if not child_pure:
                pure = False
        elif cls is Comment:
            if "xacro:eval-comments" in c.data:
                fixed = pure = False
            elif "$" in c.data:
                fixed = False
        elif cls is Text:
            fixed = pure = False
    static = plain and fixed
    el.fixed = fixed
    el.static = static
    el.pure = pure
    el.shared = True
    if pure and not static:
        el.plan = (not plain, () if dynamic is None else tuple(dynamic))
    return size
