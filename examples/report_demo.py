"""The demo report (thesis chapter 7 on the built-in SYNTHETIC multi-speed set), opened in
headless Chromium: console errors, each figure's rendered size, and a screenshot of the page's
top for docs/report.md. Prints JSON.

    python examples/report_demo.py [OUT_DIR] [SCREENSHOT.png]
"""

import json
import sys
from pathlib import Path

from ballimpact.cli import main as ballimpact
from ballimpact.report.browser import check_page


def main(out: str = "report-demo", screenshot: str = "report-screenshot.png") -> None:
    code = ballimpact(["report", "--builtin", "speeds", "--out", out])
    if code:
        sys.exit(code)
    full = Path(out) / "page.png"
    seen = check_page(Path(out) / "report.html", full)
    _top(full, Path(screenshot), 2400)
    print(json.dumps({**seen, "screenshot": screenshot}, indent=1))
    if seen["console_errors"]:
        sys.exit(1)


def _top(page: Path, out: Path, height_px: int) -> None:
    """The page's top `height_px` at half size (tables, the NRMSE bars, the overlays)."""
    from PIL import Image

    image = Image.open(page)
    top = image.crop((0, 0, image.width, min(height_px, image.height)))
    top.resize((top.width // 2, top.height // 2), Image.LANCZOS).save(out, optimize=True)


if __name__ == "__main__":
    main(*sys.argv[1:3])
