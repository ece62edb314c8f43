"""A small client of headless Chromium over the DevTools protocol, for the `browser` tier and
the pictures of the docs (bench/report_screenshot.py): Debian's `chromium` (never a browser
downloaded), started with a fresh profile and the flags that keep it off the network, driven
over its websocket (`websockets`, the `test` extra).

    with Chromium() as browser:
        browser.open(Path("report.html").as_uri())
        browser.wait_for("window.scriptcReport && window.scriptcReport.ready")
        browser.evaluate("1 + 1")            # 2
        browser.mouse_move(300, 400)          # a real mouse event at page coordinates
        browser.problems                      # console errors, exceptions, failed loads
        browser.screenshot()                  # PNG bytes
"""

from __future__ import annotations

import base64
import contextlib
import json
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

CHROMIUM = os.environ.get("SCRIPTC_CHROMIUM", "/usr/bin/chromium")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-quic",
         "--hide-scrollbars", "--mute-audio", "--remote-debugging-port=0")


class ChromiumError(RuntimeError):
    """Chromium could not be started or driven; the message says why."""


def available() -> str | None:
    """Why Chromium cannot be driven here (None: it can)."""
    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        return (f"{CHROMIUM} is not there: install Debian's Chromium (`apt-get install "
                "chromium`, as .ci/run does)")
    try:
        import websockets.sync.client  # noqa: F401  (the test extra)
    except ImportError:
        return "the websockets package is missing: pip install -e '.[test]'"
    return None


class Chromium:
    """Headless Chromium with one page, `width` x `height` CSS pixels at `scale`."""

    def __init__(self, width: int = 1280, height: int = 1000, scale: float = 1.0,
                 timeout: float = 30.0) -> None:
        why = available()
        if why is not None:
            raise ChromiumError(why)
        from websockets.sync.client import connect

        self.timeout = timeout
        self.stack = contextlib.ExitStack()
        self.profile = tempfile.mkdtemp(prefix="scriptc-chromium-")
        self.process = subprocess.Popen(
            [CHROMIUM, *FLAGS, f"--user-data-dir={self.profile}",
             f"--window-size={width},{height}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            url = self._browser_url()
            self.socket = self.stack.enter_context(
                connect(url, max_size=None, open_timeout=timeout))
            self.next_id = 0
            self.events: list[dict[str, Any]] = []
            target = self.call("Target.createTarget", {"url": "about:blank"}, session=False)
            attached = self.call("Target.attachToTarget",
                                 {"targetId": target["targetId"], "flatten": True},
                                 session=False)
            self.session = attached["sessionId"]
            for domain in ("Page", "Runtime", "Log", "Network"):
                self.call(f"{domain}.enable")
            self.call("Emulation.setDeviceMetricsOverride",
                      {"width": width, "height": height, "deviceScaleFactor": scale,
                       "mobile": False})
        except BaseException:
            self.close()
            raise

    def _browser_url(self) -> str:
        """The browser's websocket, from the DevToolsActivePort file of its profile."""
        port_file = Path(self.profile) / "DevToolsActivePort"
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise ChromiumError(f"{CHROMIUM} exited with status {self.process.returncode}")
            try:
                port, path = port_file.read_text(encoding="utf-8").split()[:2]
                return f"ws://127.0.0.1:{port}{path}"
            except (OSError, ValueError):
                time.sleep(0.05)
        raise ChromiumError(f"{CHROMIUM} did not open its DevTools port in {self.timeout:g} s")

    def __enter__(self) -> Chromium:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def close(self) -> None:
        socket = getattr(self, "socket", None)
        if socket is not None:
            with contextlib.suppress(Exception):  # closing anyway
                self.call("Browser.close", session=False)
        self.stack.close()
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        shutil.rmtree(self.profile, ignore_errors=True)

    # -- the protocol ------------------------------------------------------------------------

    def call(self, method: str, params: dict[str, Any] | None = None, *,
             session: bool = True) -> dict[str, Any]:
        """Send a command and wait for its answer (events that arrive meanwhile are kept)."""
        self.next_id += 1
        message: dict[str, Any] = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = self.session
        self.socket.send(json.dumps(message))
        deadline = time.monotonic() + self.timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise ChromiumError(f"no answer to {method} in {self.timeout:g} s")
            reply = json.loads(self.socket.recv(timeout=left))
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise ChromiumError(f"{method}: {reply['error'].get('message')}")
                result: dict[str, Any] = reply.get("result", {})
                return result
            if "method" in reply:
                self.events.append(reply)

    def pump(self, seconds: float) -> None:
        """Keep the events that arrive within `seconds`."""
        deadline = time.monotonic() + seconds
        while (left := deadline - time.monotonic()) > 0:
            try:
                reply = json.loads(self.socket.recv(timeout=left))
            except TimeoutError:
                return
            if "method" in reply:
                self.events.append(reply)

    # -- what a test does -------------------------------------------------------------------

    def open(self, url: str) -> None:
        """Navigate to `url` and wait for its load event."""
        self.events = [e for e in self.events if e["method"] != "Page.loadEventFired"]
        self.call("Page.navigate", {"url": url})
        deadline = time.monotonic() + self.timeout
        while not any(e["method"] == "Page.loadEventFired" for e in self.events):
            if time.monotonic() > deadline:
                raise ChromiumError(f"{url} did not load in {self.timeout:g} s")
            self.pump(0.05)

    def evaluate(self, expression: str) -> Any:
        """The value of a JavaScript expression in the page (promises awaited)."""
        result = self.call("Runtime.evaluate", {"expression": expression,
                                                "returnByValue": True, "awaitPromise": True})
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            raise ChromiumError(f"{expression}: "
                                f"{details.get('exception', {}).get('description', details)}")
        return result["result"].get("value")

    def wait_for(self, expression: str, timeout: float | None = None) -> Any:
        """Poll `expression` until it is truthy; its value."""
        deadline = time.monotonic() + (timeout or self.timeout)
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            if time.monotonic() > deadline:
                raise ChromiumError(f"`{expression}` still false after "
                                    f"{timeout or self.timeout:g} s; the page's problems: "
                                    f"{self.problems}")
            self.pump(0.05)

    def mouse_move(self, x: float, y: float, *, buttons: int = 0) -> None:
        """A real mouse move to (x, y) in CSS pixels of the page (`buttons` 1: dragging)."""
        self.call("Input.dispatchMouseEvent",
                  {"type": "mouseMoved", "x": x, "y": y, "buttons": buttons,
                   "button": "left" if buttons else "none"})

    def mouse(self, kind: str, x: float, y: float) -> None:
        """`mousePressed` or `mouseReleased` with the left button at (x, y)."""
        self.call("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y,
                                               "button": "left", "buttons": 1,
                                               "clickCount": 1})

    def screenshot(self, full_page: bool = True) -> bytes:
        """The page as PNG (all of it, or the viewport)."""
        params: dict[str, Any] = {"format": "png"}
        if full_page:
            metrics = self.call("Page.getLayoutMetrics")["cssContentSize"]
            params.update(captureBeyondViewport=True,
                          clip={"x": 0, "y": 0, "width": metrics["width"],
                                "height": metrics["height"], "scale": 1})
        return base64.b64decode(self.call("Page.captureScreenshot", params)["data"])

    @property
    def problems(self) -> list[str]:
        """What went wrong in the page: console errors and warnings, uncaught exceptions,
        browser log errors (a Content-Security-Policy violation), failed loads."""
        out = []
        for e in self.events:
            method, params = e["method"], e.get("params", {})
            if method == "Runtime.exceptionThrown":
                details = params.get("exceptionDetails", {})
                out.append("exception: " + str(details.get("exception", {}).get("description")
                                                or details.get("text")))
            elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error",
                                                                                  "warning",
                                                                                  "assert"):
                said = " ".join(str(a.get("value", a.get("description", "")))
                                for a in params.get("args", []))
                out.append(f"console.{params['type']}: {said}")
            elif method == "Log.entryAdded" and params.get("entry", {}).get("level") in (
                    "error", "warning"):
                entry = params["entry"]
                out.append(f"log {entry['level']}: {entry.get('text')} {entry.get('url', '')}")
            elif method == "Network.loadingFailed":
                out.append(f"load failed: {params.get('errorText')}")
        return out

    @property
    def requests(self) -> list[str]:
        """Every URL the page asked for."""
        return [e["params"]["request"]["url"] for e in self.events
                if e["method"] == "Network.requestWillBeSent"]
