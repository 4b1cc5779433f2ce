"""docs/report_screenshots.py: the report split into sections as a browser gets them, white space
trimmed; the browser run itself on a tiny page where Chromium is installed."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

SCRIPT = Path(__file__).resolve().parents[1] / "docs" / "report_screenshots.py"
spec = importlib.util.spec_from_file_location("report_screenshots", SCRIPT)
assert spec is not None and spec.loader is not None
screenshots = importlib.util.module_from_spec(spec)
spec.loader.exec_module(screenshots)

PAGE = (
    "<html><head><style>h2 { color: #123; }</style></head><body><h1>r</h1>"
    '<section id="section-1"><h2>1. A</h2><p>a</p></section>'
    '<section id="section-2"><h2>2. B</h2><table><tr><td>1</td></tr></table></section></body></html>'
)


def test_the_report_splits_into_its_sections_with_its_own_stylesheet():
    head, sections = screenshots.split_sections(PAGE)
    assert "h2 { color: #123; }" in head and "<body>" not in head
    assert list(sections) == ["section-1", "section-2"]
    assert sections["section-2"].startswith('<section id="section-2">') and "<td>1</td>" in sections["section-2"]


def test_white_space_below_a_section_is_cut(tmp_path):
    pixels = np.full((300, 40, 3), 255, np.uint8)
    pixels[10:50] = 0
    Image.fromarray(pixels).save(tmp_path / "shot.png")
    assert screenshots.trim_white(tmp_path / "shot.png", margin=5) == (40, 55)
    assert Image.open(tmp_path / "shot.png").size == (40, 55)


def test_a_real_browser_renders_each_section(tmp_path):
    browser = screenshots.find_browser()
    if browser is None:
        pytest.skip("no Chromium on PATH (Debian: apt install chromium): the report is not checked in a browser")
    head, sections = screenshots.split_sections(PAGE)
    page = tmp_path / "section-2.html"
    page.write_text(f"{head}<body>{sections['section-2']}</body></html>")
    screenshots.screenshot(browser, page, tmp_path / "shot.png", 400, 600)
    width, height = screenshots.trim_white(tmp_path / "shot.png")
    # the heading and table were drawn: something below the top margin is not white
    assert width == 400 and 30 < height < 600
