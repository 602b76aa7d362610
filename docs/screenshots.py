"""Opens the documentation site's home page and its validation report page
in headless Chromium (`make validate`, after the site is built with the
report), fails on any console error (an exception, `console.error`, a
resource that does not load), and adds the pages' screenshots to the
report (`report.md` and `report.html` in --report).

The browser is driven through the DevTools protocol over a pipe
(`--remote-debugging-pipe`: JSON messages ending in a NUL byte on file
descriptors 3 and 4), so nothing listens on a port and nothing beyond the
standard library is needed.

    python docs/screenshots.py --site docs/_build/html --report results
"""

from __future__ import annotations

import argparse
import base64
import fcntl
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PAGES = {"site_home": "index.html", "site_report": "_generated/report.html"}
WIDTH, HEIGHT = 1280, 1000
# Errors logged this long after the load event still count (late scripts).
SETTLE_SECONDS = 1.0
TIMEOUT_SECONDS = 60.0


class Browser:
    """Headless Chromium with one page, over the DevTools pipe."""

    def __init__(self) -> None:
        to_browser_read, self._write = os.pipe()
        self._read, from_browser_write = os.pipe()
        # Above 10, so that placing them at 3 and 4 in the child overwrites nothing.
        keep = [fcntl.fcntl(fd, fcntl.F_DUPFD, 10) for fd in (to_browser_read, from_browser_write)]

        def at_3_and_4() -> None:
            os.dup2(keep[0], 3)
            os.dup2(keep[1], 4)

        self._profile = tempfile.TemporaryDirectory(prefix="quatrot-chromium-")
        self.process = subprocess.Popen(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--hide-scrollbars",
             "--remote-debugging-pipe", f"--user-data-dir={self._profile.name}", "about:blank"],
            preexec_fn=at_3_and_4, pass_fds=(3, 4), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )
        for fd in (to_browser_read, from_browser_write, *keep):
            os.close(fd)
        self._buffer = b""
        self._next_id = 0
        self.events: list[dict] = []
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            self.call(f"{domain}.enable", session=True)
        self.call("Emulation.setDeviceMetricsOverride", session=True, width=WIDTH, height=HEIGHT, deviceScaleFactor=1, mobile=False)

    def _message(self, deadline: float) -> dict:
        while b"\0" not in self._buffer:
            if time.monotonic() > deadline:
                raise TimeoutError("chromium did not answer")
            chunk = os.read(self._read, 1 << 20)
            if not chunk:
                raise RuntimeError("chromium closed the pipe")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method: str, session: bool = False, **params) -> dict:
        """Sends a command and returns its result; events met on the way are kept."""
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = self.session
        os.write(self._write, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + TIMEOUT_SECONDS
        while True:
            reply = self._message(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def wait_for(self, method: str) -> None:
        deadline = time.monotonic() + TIMEOUT_SECONDS
        while not any(e.get("method") == method for e in self.events):
            self.events.append(self._message(deadline))

    def open(self, url: str) -> tuple[bytes, list[str]]:
        """The page's screenshot (PNG) and its console errors."""
        self.events = []
        self.call("Page.navigate", session=True, url=url)
        self.wait_for("Page.loadEventFired")
        time.sleep(SETTLE_SECONDS)
        png = base64.b64decode(self.call("Page.captureScreenshot", session=True, format="png")["data"])
        return png, console_errors(self.events)

    def close(self) -> None:
        try:
            self.call("Browser.close")
        except (RuntimeError, TimeoutError, OSError):
            pass
        self.process.wait(timeout=30)
        self._profile.cleanup()


def console_errors(events: list[dict]) -> list[str]:
    """What the console showed as an error: uncaught exceptions,
    `console.error` and `console.assert`, and error log entries (a resource
    that failed to load, a blocked request)."""
    errors = []
    for event in events:
        method, params = event.get("method"), event.get("params", {})
        if method == "Runtime.exceptionThrown":
            details = params["exceptionDetails"]
            errors.append(details.get("exception", {}).get("description") or details.get("text", "exception"))
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            errors.append(" ".join(str(a.get("value", a.get("description", ""))) for a in params.get("args", [])))
        elif method == "Log.entryAdded" and params["entry"].get("level") == "error":
            entry = params["entry"]
            errors.append(f"{entry.get('text', '')} {entry.get('url', '')}".strip())
    return errors


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--site", type=Path, required=True, help="the built site (docs/_build/html)")
    parser.add_argument("--report", type=Path, required=True, help="the report's folder (report.md is extended)")
    args = parser.parse_args(argv)
    shots = args.report / "screenshots"
    shots.mkdir(parents=True, exist_ok=True)
    version = subprocess.run(["chromium", "--version"], capture_output=True, text=True).stdout.strip()
    browser = Browser()
    found: dict[str, list[str]] = {}
    try:
        for name, page in PAGES.items():
            png, errors = browser.open((args.site / page).resolve().as_uri())
            (shots / f"{name}.png").write_bytes(png)
            found[page] = errors
            print(f"{page}: {len(errors)} console errors" + "".join(f"\n  {e}" for e in errors))
    finally:
        browser.close()
    lines = ["", "## The documentation site in a browser", "",
             f"{version} (headless) opened the site built with this report; console errors per page:", "",
             "| page | console errors |", "|---|---|"]
    lines += [f"| `{page}` | {len(errors)} |" for page, errors in found.items()]
    for name, page in PAGES.items():
        lines += ["", f"![{page}](screenshots/{name}.png)"]
    report = args.report / "report.md"
    text = report.read_text().rstrip() + "\n" + "\n".join(lines) + "\n"
    report.write_text(text)
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from validation.report_html import to_html

    (args.report / "report.html").write_text(to_html(text, args.report, "quatrot validation report"))
    failed = sum(len(e) for e in found.values())
    print(f"screenshots in {shots}; {failed} console errors")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
