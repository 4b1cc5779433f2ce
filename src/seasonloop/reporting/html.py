"""The report's HTML: content blocks (tables, images, text), sections of them, and one
self-contained page built from the sections.

Knows nothing of the study: a block holds a DataFrame, a caption or PNG paths or bytes. Images are
embedded as base64 data URIs and the style sheet is inline, so the file reads offline and can be
shared as it is.
"""

from __future__ import annotations

import base64
import html
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
Png = Path | bytes

_STYLE = """
body { font-family: sans-serif; max-width: 1200px; margin: 2em auto; padding: 0 1em; color: #222; }
h1 { border-bottom: 2px solid #444; } h2 { border-bottom: 1px solid #aaa; margin-top: 2em; }
table { border-collapse: collapse; margin: 0 0 1.5em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: right; }
th { background: #f0f0f0; }
caption, p.caption { caption-side: top; text-align: left; font-weight: bold; margin: 1em 0 0.3em; }
figure { margin: 0.5em 0 1.5em; } figure img { max-width: 100%; }
figcaption { font-size: 0.9em; color: #555; }
pre { background: #f6f6f6; padding: 1em; overflow-x: auto; font-size: 0.85em; }
"""


@dataclass(frozen=True)
class Table:
    """A DataFrame shown as an HTML table; float cells formatted with float_format."""

    caption: str
    frame: pd.DataFrame
    float_format: str = "{:.1f}"


@dataclass(frozen=True)
class Image:
    """One PNG (a file or its bytes) with a caption."""

    caption: str
    png: Png


@dataclass(frozen=True)
class Text:
    """A paragraph, or preformatted text (kept verbatim, e.g. a YAML file)."""

    text: str
    preformatted: bool = False


Block = Table | Image | Text


@dataclass(frozen=True)
class Section:
    title: str
    blocks: Sequence[Block]


def _data_uri(png: Png) -> str:
    """The PNG as a data URI; a missing file or non-PNG content is an error naming it."""
    if isinstance(png, Path):
        if not png.is_file():
            raise FileNotFoundError(f"{png}: image not found (run the stage that writes it first)")
        data, name = png.read_bytes(), str(png)
    else:
        data, name = bytes(png), "image bytes"
    if not data.startswith(PNG_SIGNATURE):
        raise ValueError(f"{name}: not a PNG image")
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def _block_html(block: Block) -> str:
    if isinstance(block, Table):
        table = block.frame.to_html(escape=True, float_format=block.float_format.format, na_rep="–", border=0)
        return f'<p class="caption">{html.escape(block.caption)}</p>\n{table}'
    if isinstance(block, Image):
        caption = html.escape(block.caption)
        return f'<figure><img src="{_data_uri(block.png)}" alt="{caption}"><figcaption>{caption}</figcaption></figure>'
    if isinstance(block, Text):
        return f"<pre>{html.escape(block.text)}</pre>" if block.preformatted else f"<p>{html.escape(block.text)}</p>"
    raise ValueError(f"unknown report block type {type(block).__name__}")


def build_report(title: str, sections: Sequence[Section]) -> str:
    """One self-contained HTML page: title, a table of contents, then each section in order."""
    if not sections:
        raise ValueError("sections is empty: nothing to report")
    contents = "".join(
        f'<li><a href="#section-{number}">{html.escape(section.title)}</a></li>'
        for number, section in enumerate(sections, 1)
    )
    body = "\n".join(
        f'<section id="section-{number}"><h2>{number}. {html.escape(section.title)}</h2>\n'
        + "\n".join(_block_html(block) for block in section.blocks)
        + "</section>"
        for number, section in enumerate(sections, 1)
    )
    return (
        f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>'
        f"<style>{_STYLE}</style></head>\n<body><h1>{html.escape(title)}</h1><nav><ol>{contents}</ol></nav>\n"
        f"{body}\n</body></html>\n"
    )
