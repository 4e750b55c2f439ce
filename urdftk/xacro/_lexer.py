"""Split attribute and text values into literal text, ``${expr}``, ``$(subst)`` and ``$$`` escapes.

The token rules are stock xacro's, tried in this order at each position:

* ``$$…${`` or ``$$…$(`` (two or more ``$``): the text minus its first ``$`` (an escape);
* ``${`` up to the first ``}``: an expression;
* ``$(`` up to the first ``)``: a substitution argument;
* literal text: a run without ``$``, a ``$`` followed by anything but ``{``, ``(`` or ``$``,
  or a final ``$``.

Results are cached per string, so the many identical values of macro bodies are split once.
"""

from __future__ import annotations

import re
from functools import lru_cache

from urdftk.errors import XacroError

__all__ = ["EXPR", "SUBST", "TEXT", "tokenize"]

TEXT = 0
EXPR = 1
SUBST = 2

_TOKEN = re.compile(
    r"(?P<esc>\$\$+[{(])|\$\{(?P<expr>[^}]*)\}|\$\((?P<subst>[^)]*)\)|(?P<text>[^$]+|\$[^{($]+|\$$)"
)


@lru_cache(maxsize=16384)
def tokenize(text: str) -> tuple[tuple[int, str], ...]:
    """Split ``text`` into ``(kind, value)`` tokens (kind TEXT, EXPR or SUBST).

    For EXPR and SUBST the value is the inside of the braces; escapes become TEXT.

    Raises:
        XacroError: At a ``$`` that starts nothing valid (e.g. an unclosed ``${``).
    """
    out: list[tuple[int, str]] = []
    pos = 0
    n = len(text)
    match = _TOKEN.match
    while pos < n:
        m = match(text, pos)
        if m is None:
            raise XacroError(f"invalid expression: {text[pos:]}")
        kind = m.lastgroup
        if kind == "text":
            out.append((TEXT, m.group(kind)))
        elif kind == "expr":
            out.append((EXPR, m.group(kind)))
        elif kind == "subst":
            out.append((SUBST, m.group(kind)))
        else:
            out.append((TEXT, m.group(kind)[1:]))
        pos = m.end()
    return tuple(out)
