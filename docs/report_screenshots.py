"""Screenshots of the HTML report in a real browser, one per section, at a laptop's width.

    python docs/report_screenshots.py [plots/report.html] [--out docs/results/report] [--width 1366]

Each section is rendered by headless Chromium (Debian's `chromium` package) with the report's own
stylesheet, in a page holding that section alone (a 10 MB page loaded whole and scrolled to an
anchor comes out blank in headless mode), at --width pixels and as tall as the section: a
section that reaches the window's bottom is shot again in a window twice as tall (up to
MAX_HEIGHT), so no section is cut; the screenshot is cut below the section's last non-white row. Exits 0 with a stated reason, writing
nothing, where Chromium is missing.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

BROWSERS = ("chromium", "chromium-browser", "google-chrome")
MAX_HEIGHT = 48000  # pixels: Chromium's own limit for one screenshot is near 64k
SECTION = re.compile(r'<section id="(section-\d+)">.*?</section>', re.S)


def find_browser() -> str | None:
    """The first headless-capable Chromium on PATH, None if there is none."""
    return next((path for name in BROWSERS if (path := shutil.which(name))), None)


def split_sections(html: str) -> tuple[str, dict[str, str]]:
    """(the report's <head>, section id -> that section's HTML)."""
    head = html[: html.index("<body>")]
    return head, {match.group(1): match.group(0) for match in SECTION.finditer(html)}


def content_bottom(image: Image.Image) -> int:
    """One past the screenshot's last non-white row (0 when all white)."""
    rows = np.flatnonzero((np.asarray(image.convert("RGB")) < 250).any(axis=(1, 2)))
    return int(rows[-1]) + 1 if rows.size else 0


def trim_white(path: Path, margin: int = 16) -> tuple[int, int]:
    """Cut the screenshot below its last non-white row; returns (width, height)."""
    image = Image.open(path).convert("RGB")
    last = content_bottom(image)
    bottom = min(image.height, last + margin) if last else image.height
    # 256 colours: a page of text and plots loses nothing visible, and the files shrink ~3x
    image.crop((0, 0, image.width, bottom)).quantize(256).save(path, optimize=True)
    return image.width, bottom


def screenshot(browser: str, page: Path, out: Path, width: int, height: int) -> None:
    command = [browser, "--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"]
    command += [f"--window-size={width},{height}", f"--screenshot={out}", page.as_uri()]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300)
    if result.returncode != 0 or not out.is_file():
        raise RuntimeError(f"{browser} failed on {page.name}: {result.stderr.strip().splitlines()[-1:]}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report", nargs="?", default="plots/report.html", type=Path)
    parser.add_argument("--out", default=Path("docs/results/report"), type=Path)
    parser.add_argument("--width", default=1366, type=int)
    parser.add_argument("--height", default=6000, type=int, help="first window height (doubled while too short)")
    args = parser.parse_args()
    browser = find_browser()
    if browser is None:
        print(f"skipped: no Chromium on PATH (tried {', '.join(BROWSERS)}; Debian: apt install chromium)")
        return 0
    if not args.report.is_file():
        print(f"{args.report}: no report (run dvc repro first)", file=sys.stderr)
        return 1
    head, sections = split_sections(args.report.read_text())
    args.out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        for name, body in sections.items():
            page = Path(scratch) / f"{name}.html"
            page.write_text(f"{head}<body>{body}</body></html>")
            shot = args.out / f"{name}.png"
            height = args.height
            screenshot(browser, page, shot, args.width, height)
            # the section fills the window to its bottom: it may go on below, so shoot it taller
            while content_bottom(Image.open(shot)) >= height - 4 and height < MAX_HEIGHT:
                height = min(2 * height, MAX_HEIGHT)
                screenshot(browser, page, shot, args.width, height)
            width, height = trim_white(shot)
            print(f"{shot}: {width} x {height} px")
    print(f"{args.report}: {args.report.stat().st_size / 1e6:.1f} MB, one self-contained file")
    return 0


if __name__ == "__main__":
    sys.exit(main())
