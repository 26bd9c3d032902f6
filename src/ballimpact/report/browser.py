"""Open a report in a real headless browser (Chromium from the distribution's packages) and say
what it showed: console errors, failed loads, script exceptions, each figure's rendered size, and
a screenshot of the whole page.

The browser is driven over the DevTools protocol on a pipe (`--remote-debugging-pipe`: JSON
messages ending in a NUL byte on file descriptors 3 and 4), so nothing beyond the standard
library and the browser is needed.
"""

from __future__ import annotations

import base64
import json
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from ..errors import InputError

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "chrome")
#: JavaScript run in the page: the rendered width and height (CSS px) of each figure's SVG
_FIGURE_SIZES = ("Array.from(document.querySelectorAll('figure svg')).map(s => {"
                 "const b = s.getBoundingClientRect(); return [b.width, b.height]; })")


def find_browser() -> str | None:
    for name in BROWSERS:
        path = shutil.which(name)
        if path:
            return path
    return None


class _Pipe:
    """DevTools protocol over the browser's pipe: commands with ids, events kept as they come."""

    def __init__(self, write_fd: int, read_fd: int):
        self.write_fd, self.read_fd = write_fd, read_fd
        self.buffer = b""
        self.events: list[dict[str, Any]] = []
        self.next_id = 0

    def send(self, method: str, params: dict | None = None, session: str | None = None,
             timeout_s: float = 60.0) -> dict[str, Any]:
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.write_fd, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            reply = self._read()
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)
        raise TimeoutError(f"{method}: no answer from the browser in {timeout_s:g} s")

    def wait_for(self, method: str, timeout_s: float = 60.0) -> None:
        deadline = time.monotonic() + timeout_s
        while not any(e.get("method") == method for e in self.events):
            if time.monotonic() > deadline:
                raise TimeoutError(f"the browser sent no {method} in {timeout_s:g} s")
            self.events.append(self._read())

    def _read(self) -> dict[str, Any]:
        while b"\0" not in self.buffer:
            chunk = os.read(self.read_fd, 1 << 16)
            if not chunk:
                raise RuntimeError("the browser closed its pipe")
            self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)


def check_page(html_path: str | Path, screenshot: str | Path | None = None, *,
               width_px: int = 1280, browser: str | None = None,
               timeout_s: float = 60.0) -> dict[str, Any]:
    """Load `html_path` in headless Chromium; return `console_errors` (console errors and
    warnings, uncaught exceptions, failed loads), `figures` (rendered [width, height] of each
    figure's SVG, CSS px) and `page_height_px`; write a PNG of the whole page to `screenshot`.
    Raises `InputError` when no browser is installed (`apt-get install chromium`)."""
    browser = browser or find_browser()
    if browser is None:
        raise InputError("no Chromium found (tried " + ", ".join(BROWSERS) + "): "
                         "apt-get install chromium")
    page = Path(html_path).resolve()
    if not page.is_file():
        raise InputError(f"html_path: {page} does not exist")
    to_browser_read, to_browser_write = os.pipe()
    from_browser_read, from_browser_write = os.pipe()
    profile = tempfile.mkdtemp(prefix="ballimpact-chromium-")

    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--remote-debugging-pipe",
             "--no-first-run", "--no-default-browser-check", f"--user-data-dir={profile}",
             "--hide-scrollbars"]
    # the protocol's pipe is fd 3 (the browser reads) and fd 4 (it writes); bash puts our ends
    # there (dash takes one-digit descriptors only), so no Python code runs between fork and
    # exec, which JAX's threads would not survive
    process = subprocess.Popen(
        ["bash", "-c", f'exec "$0" "$@" 3<&{to_browser_read} 4>&{from_browser_write}',
         browser, *flags],
        stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        pass_fds=(to_browser_read, from_browser_write))
    os.close(to_browser_read)
    os.close(from_browser_write)
    pipe = _Pipe(to_browser_write, from_browser_read)
    try:
        target = pipe.send("Target.createTarget", {"url": "about:blank"}, timeout_s=timeout_s)
        session = pipe.send("Target.attachToTarget", {"targetId": target["targetId"],
                                                      "flatten": True})["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            pipe.send(f"{domain}.enable", session=session)
        pipe.send("Emulation.setDeviceMetricsOverride", {"width": width_px, "height": 900,
                                                         "deviceScaleFactor": 1,
                                                         "mobile": False}, session=session)
        pipe.send("Page.navigate", {"url": page.as_uri()}, session=session)
        pipe.wait_for("Page.loadEventFired", timeout_s)
        sizes = pipe.send("Runtime.evaluate", {"expression": _FIGURE_SIZES,
                                               "returnByValue": True},
                          session=session)["result"]["value"]
        metrics = pipe.send("Page.getLayoutMetrics", session=session)
        height = int(metrics["cssContentSize"]["height"])
        if screenshot is not None:
            shot = pipe.send("Page.captureScreenshot", {
                "format": "png", "captureBeyondViewport": True,
                "clip": {"x": 0, "y": 0, "width": width_px, "height": height, "scale": 1}},
                session=session, timeout_s=timeout_s)
            Path(screenshot).write_bytes(base64.b64decode(shot["data"]))
        return {"console_errors": _errors(pipe.events), "figures": sizes,
                "page_height_px": height, "browser": browser}
    finally:
        os.close(to_browser_write)
        os.close(from_browser_read)
        process.kill()
        process.wait()
        shutil.rmtree(profile, ignore_errors=True)


def _errors(events: list[dict[str, Any]]) -> list[str]:
    found = []
    for event in events:
        method, params = event.get("method"), event.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "warning",
                                                                           "assert"):
            found.append("console." + params["type"] + ": " + " ".join(
                str(a.get("value", a.get("description", ""))) for a in params.get("args", [])))
        elif method == "Runtime.exceptionThrown":
            details = params["exceptionDetails"]
            found.append("exception: " + details.get("exception", {}).get(
                "description", details.get("text", "")))
        elif method == "Log.entryAdded" and params["entry"].get("level") in ("error", "warning"):
            found.append(f"{params['entry'].get('source')}: {params['entry'].get('text')}")
    return found
