"""Small pieces of the report's HTML shared by its sections: escaped text, numbers, figures opening full size."""

from __future__ import annotations

import base64
import html
import math

__all__ = ["esc", "num", "figure_block", "verdict_cell"]


def esc(value: object) -> str:
    """``value`` as text, escaped for HTML."""
    return html.escape(str(value))


def num(value: float | None, digits: int = 4) -> str:
    """A number for a table: ``digits`` significant digits, exponent form when very large or small, – for none."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    if value == 0:
        return "0"
    if abs(value) >= 1e5 or abs(value) < 1e-3:
        return f"{value:.{digits - 1}e}"
    return f"{value:.{digits}g}"


def verdict_cell(passed: bool, reason: str = "") -> str:
    """passed / FAILED, with the reason (cut to 200 characters) under it."""
    verdict = '<span class="pass">passed</span>' if passed else '<span class="fail">FAILED</span>'
    return verdict + (f"<small>{esc(reason[:200])}</small>" if reason else "")


def _img(png: bytes, alt: str) -> str:
    data = base64.b64encode(png).decode()
    return f'<img alt="{html.escape(alt)}" src="data:image/png;base64,{data}">'


def figure_block(png: bytes, alt: str, key: str, caption: str, back: str, attributes: str = "") -> str:
    """A figure whose image is a link to itself full size: in the page (its data sits there once), the figure
    fills the window while its view anchor is the target, and "close" goes back to ``back``."""
    view = "view-" + "".join(c if c.isalnum() or c in "-_" else "-" for c in key)
    return (f'<figure{attributes}><span class=view id="{view}"></span>'
            f'<a class=open href="#{view}" title="open full size">{_img(png, alt)}</a>'
            f'<figcaption>{caption} <a class=close href="#{back}">close</a></figcaption></figure>')
