"""Open a page in headless Chromium (Debian's `chromium`) and ask it what it rendered.

Used by the HTML audit's browser test and to take the README's screenshot. It speaks
the DevTools protocol over `--remote-debugging-pipe` (JSON messages separated by NUL
bytes on file descriptors 3 and 4), so it needs no driver, no websocket library and no
network. The flags keep Chromium from reaching out on a closed network, where it would
otherwise stall, and a fresh profile directory keeps runs independent.

    python -m codegen.audit.browser generated/paper/AUDIT.html docs/audit.png [eq-4]
"""

from __future__ import annotations

import base64
import contextlib
import fcntl
import json
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import TracebackType
from typing import Any

CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--hide-scrollbars",
    "--remote-debugging-pipe",
)
TIMEOUT_S = 60.0


class BrowserError(RuntimeError):
    """Chromium is missing, did not start, or did not answer in time."""


def chromium_path() -> str:
    for name in ("chromium", "chromium-browser"):
        found = shutil.which(name)
        if found:
            return found
    raise BrowserError(
        "chromium is not installed: `make sysdeps` installs Debian's chromium package"
    )


def _above_ten(fd: int) -> int:
    moved = fcntl.fcntl(fd, fcntl.F_DUPFD, 10)
    os.close(fd)
    return moved


def _signal_group(group: int, signum: signal.Signals) -> None:
    """Send `signum` to every process of the group (none left is not an error)."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(group, signum)


def _remove_profile(profile: tempfile.TemporaryDirectory[str]) -> None:
    """Remove the profile, waiting out a killed process's last write (a process killed
    by SIGKILL may still be exiting, with a file of the profile open, for a moment)."""
    deadline = time.monotonic() + 5.0
    while True:
        try:
            shutil.rmtree(profile.name)
            break
        except FileNotFoundError:
            break
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.05)
    profile.cleanup()  # the folder is gone: marks the object cleaned up


class Chromium:
    """One headless Chromium with one page, driven over the DevTools pipe."""

    def __init__(self, width: int = 1200, height: int = 900) -> None:
        self.width, self.height = width, height
        self._profile = tempfile.TemporaryDirectory(prefix="audit-chromium-")
        self._log = Path(self._profile.name) / "chromium.log"
        self._next_id = 0
        self._buffer = b""
        self._events: list[dict[str, Any]] = []
        self._session = ""
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()
        # bash (dash takes single-digit fds only) moves the browser's pipe ends to fds 3 and 4, where Chromium expects
        # them; first out of the way to fds >= 10, so that neither is already 3 or 4.
        to_browser_r, from_browser_w = (_above_ten(to_browser_r), _above_ten(from_browser_w))
        launcher = (
            f'exec "$0" "$@" 3<&{to_browser_r} 4>&{from_browser_w}'
            f" {to_browser_r}<&- {from_browser_w}>&-"
        )
        with self._log.open("wb") as log:
            self._process = subprocess.Popen(
                [
                    "/bin/bash",
                    "-c",
                    launcher,
                    chromium_path(),
                    *CHROMIUM_FLAGS,
                    f"--user-data-dir={self._profile.name}/profile",
                    f"--window-size={width},{height}",
                    "about:blank",
                ],
                pass_fds=(to_browser_r, from_browser_w),
                stdin=subprocess.DEVNULL,
                stdout=log,
                stderr=log,
                # its own process group: Chromium's renderer, GPU and crash-handler
                # processes outlive the browser process by a moment, and close() must
                # end them all before it removes the profile they write to
                start_new_session=True,
            )
        os.close(to_browser_r)
        os.close(from_browser_w)
        try:
            target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
            self._session = self.call(
                "Target.attachToTarget", {"targetId": target, "flatten": True}
            )["sessionId"]
            self.call("Page.enable")
            self.call(
                "Emulation.setDeviceMetricsOverride",
                {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
            )
        except BaseException:
            self.close()
            raise

    # --- protocol ------------------------------------------------------------------

    def _send(self, message: dict[str, Any]) -> None:
        data = json.dumps(message).encode() + b"\0"
        while data:
            data = data[os.write(self._to_browser, data) :]

    def _receive(self, deadline: float) -> dict[str, Any]:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            ready, _, _ = select.select([self._from_browser], [], [], max(left, 0))
            if not ready:
                raise BrowserError(f"chromium did not answer within {TIMEOUT_S:g} s{self._tail()}")
            chunk = os.read(self._from_browser, 1 << 20)
            if not chunk:
                raise BrowserError(f"chromium closed the DevTools pipe{self._tail()}")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        result: dict[str, Any] = json.loads(message)
        return result

    def _tail(self) -> str:
        text = self._log.read_text(errors="replace") if self._log.exists() else ""
        return (": " + " | ".join(text.strip().splitlines()[-3:])) if text.strip() else ""

    def call(self, method: str, params: dict[str, Any] | None = None) -> dict[str, Any]:
        self._next_id += 1
        message: dict[str, Any] = {"id": self._next_id, "method": method, "params": params or {}}
        if self._session:
            message["sessionId"] = self._session
        self._send(message)
        deadline = time.monotonic() + TIMEOUT_S
        while True:
            reply = self._receive(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise BrowserError(f"{method}: {reply['error']}")
                result: dict[str, Any] = reply.get("result", {})
                return result
            if "method" in reply:
                self._events.append(reply)

    def _wait_for(self, event: str) -> None:
        deadline = time.monotonic() + TIMEOUT_S
        while True:
            for index, seen in enumerate(self._events):
                if seen["method"] == event:
                    del self._events[: index + 1]
                    return
            reply = self._receive(deadline)
            if "method" in reply:
                self._events.append(reply)

    # --- page ------------------------------------------------------------------------

    def open(self, path: Path, fragment: str = "") -> None:
        """Load a local file afresh, wait for its load event, then go to `fragment`."""
        self._events.clear()
        reply = self.call("Page.navigate", {"url": path.resolve().as_uri()})
        if "errorText" in reply:
            raise BrowserError(f"cannot open {path}: {reply['errorText']}")
        if "loaderId" in reply:  # absent for a navigation within the same document
            self._wait_for("Page.loadEventFired")
        if fragment:
            self.evaluate(f"location.hash = {json.dumps(fragment)}")

    def evaluate(self, expression: str) -> Any:
        """Run JavaScript in the page and return its JSON value."""
        reply = self.call(
            "Runtime.evaluate",
            {"expression": expression, "returnByValue": True, "awaitPromise": True},
        )
        if "exceptionDetails" in reply:
            raise BrowserError(f"script failed: {reply['exceptionDetails']}")
        return reply["result"].get("value")

    def screenshot(self, out: Path, full_height: bool = False) -> Path:
        """A PNG of the viewport (or of the whole page's height)."""
        params: dict[str, Any] = {"format": "png"}
        if full_height:
            height = int(self.evaluate("document.documentElement.scrollHeight"))
            params |= {
                "captureBeyondViewport": True,
                "clip": {"x": 0, "y": 0, "width": self.width, "height": height, "scale": 1},
            }
        data = self.call("Page.captureScreenshot", params)["data"]
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_bytes(base64.b64decode(data))
        return out

    def close(self) -> None:
        """End the browser and every process it started, then remove the profile."""
        group = self._process.pid  # the group's id: the session was started for it
        if self._process.poll() is None:
            _signal_group(group, signal.SIGTERM)  # the browser shuts its children down
            try:
                self._process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self._process.kill()
                self._process.wait()
        _signal_group(group, signal.SIGKILL)  # any child still writing to the profile
        for fd in (self._to_browser, self._from_browser):
            with contextlib.suppress(OSError):
                os.close(fd)
        _remove_profile(self._profile)

    def __enter__(self) -> Chromium:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()


def readme_screenshot(page: Path, out: Path, fragment: str = "") -> Path:
    """A picture for the README: the top of the audit (findings first, the first
    finding's evidence open), or the page scrolled to `fragment`."""
    with Chromium(width=1180, height=1000) as browser:
        browser.open(page, fragment)
        if not fragment:
            browser.evaluate("document.querySelector('li.finding details').open = true")
        return browser.screenshot(out)


def main(argv: list[str]) -> int:
    if len(argv) not in (2, 3):
        print("usage: python -m codegen.audit.browser PAGE.html OUT.png [ANCHOR]", file=sys.stderr)
        return 2
    try:
        out = readme_screenshot(Path(argv[0]), Path(argv[1]), *argv[2:])
    except BrowserError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    print(f"screenshot: {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
