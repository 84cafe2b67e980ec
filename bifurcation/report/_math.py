"""Readable maths in the HTML report, with no network and no script.

The report's texts write exponents and subscripts the way a plain-text reader reads them: ``e^{πα/ω}``,
``ν^(1−r)``, ``ν^−(α−ω)²``, ``Σ_(k≤2)``, ``x_{n}``. In HTML these become ``<sup>``/``<sub>`` elements (every
browser sets them, offline), everything else is escaped. The Markdown report keeps the plain form.
"""

from __future__ import annotations

import html
import unicodedata

__all__ = ["inline_html"]

_OPEN = {"{": "}", "(": ")"}
# a bare exponent runs over these characters (ν^−r, x^2, e^−αt0): letters, digits, signs, primes
_BARE = set("0123456789.+-−′*·/") | {chr(c) for c in range(0x370, 0x400)}


def _group(text: str, start: int) -> tuple[str, int]:
    """The script starting at ``text[start]`` and the index after it: a balanced {…} or (…) group
    (braces dropped, parentheses kept only when something else follows inside), else a bare run."""
    if start >= len(text):
        return "", start
    opener = text[start]
    if opener in _OPEN:
        closer, depth = _OPEN[opener], 0
        for i in range(start, len(text)):
            if text[i] == opener:
                depth += 1
            elif text[i] == closer:
                depth -= 1
                if depth == 0:
                    return text[start + 1:i], i + 1
        return "", start   # unbalanced: leave the text as it is
    end = start
    # a sign may lead a bare exponent that is itself a group: ν^−(α−ω)²
    while end < len(text) and text[end] in "−-+":
        end += 1
    if end < len(text) and text[end] in _OPEN and end > start:
        inner, after = _group(text, end)
        if after > end:
            while after < len(text) and text[after] in "²³⁴":
                after += 1
            return text[start:end] + "(" + inner + ")" + text[end + len(inner) + 2:after], after
    while end < len(text) and (text[end].isalnum() or text[end] in _BARE) and text[end] not in "−-+" \
            or (end < len(text) and end == start and text[end] in "−-+"):
        end += 1
    return text[start:end], end


def _short_subscript(text: str, at: int) -> str:
    """The index after ``_`` at ``at`` if it subscripts a one-letter symbol (ν_f, U̇_max, a_k), else ""."""
    j = at - 1
    while j >= 0 and unicodedata.combining(text[j]):   # U̇ is U + a combining dot
        j -= 1
    if j < 0 or not text[j].isalpha() or (j > 0 and (text[j - 1].isalnum() or text[j - 1] == "_")):
        return ""
    end = at + 1
    while end < len(text) and text[end].isalnum():
        end += 1
    token = text[at + 1:end]
    return token if 0 < len(token) <= 3 else ""


def inline_html(text) -> str:
    """``text`` as HTML: escaped, with ``^…`` and ``_{…}``/``_(…)`` as superscripts and subscripts."""
    text = str(text)
    out, i = [], 0
    while i < len(text):
        ch = text[i]
        if ch in "^_" and i > 0 and not text[i - 1].isspace():
            if ch == "_" and (i + 1 >= len(text) or text[i + 1] not in _OPEN):
                token = _short_subscript(text, i)
                if token:   # ν_f, U̇_max, a_k: a one-letter symbol with a short index
                    out.append(f"<sub>{html.escape(token)}</sub>")
                    i += 1 + len(token)
                else:       # snake_case names (nu_f, slip_duration) stay as they are
                    out.append(html.escape(ch))
                    i += 1
                continue
            script, after = _group(text, i + 1)
            if script and after > i + 1:
                tag = "sup" if ch == "^" else "sub"
                out.append(f"<{tag}>{inline_html(script)}</{tag}>")
                i = after
                continue
        out.append(html.escape(ch))
        i += 1
    return "".join(out)
