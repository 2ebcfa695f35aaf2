"""A real browser for the documentation tests: Debian's headless Chromium, driven through the
DevTools protocol over a pipe (`--remote-debugging-pipe`: JSON messages separated by NUL on file
descriptors 3 and 4), so nothing beyond the Python standard library and the chromium package
is needed.

`Browser().measure(path, width)` loads a page at a viewport width and returns what the tests
judge: the document's and every element's extent against the viewport, each image's natural
size, every link and every id. `screenshot(path, width, out)` writes the whole page as PNG.

Run as a script to measure pages by hand:
    python tests/python/browser.py PAGE.html [PAGE.html ...]
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

# Flags that work in a container as root: no sandbox, no GPU, nothing fetched from the network.
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--disable-default-apps", "--disable-extensions", "--mute-audio", "--hide-scrollbars",
]

# What the tests measure in the page, once every image has loaded or failed.
MEASURE = r"""
(async () => {
  await Promise.all([...document.images].map(i => i.complete ? null
      : new Promise(r => { i.onload = r; i.onerror = r; })));
  const vw = VIEWPORT;
  const wide = [];
  for (const el of document.querySelectorAll('body *')) {
    const r = el.getBoundingClientRect();
    if (r.width === 0 && r.height === 0) continue;
    if (r.right > vw + 0.5 || r.left < -0.5) {
      wide.push({tag: el.tagName.toLowerCase(), id: el.id, cls: String(el.className),
                 text: (el.textContent || '').trim().slice(0, 50),
                 left: Math.round(r.left), right: Math.round(r.right)});
    }
  }
  const top = el => el ? Math.round(el.getBoundingClientRect().top + window.scrollY) : null;
  let cells = document.querySelectorAll('td[data-label="Description"]');
  if (!cells.length) cells = document.querySelectorAll('tbody tr td:last-child');
  const desc = [...cells].map(td => td.getBoundingClientRect().width).filter(w => w > 0);
  return {
    viewport: vw,
    innerWidth: window.innerWidth,
    scrollWidth: document.documentElement.scrollWidth,
    height: document.documentElement.scrollHeight,
    wide: wide,
    images: [...document.images].map(i => ({src: i.getAttribute('src'), naturalWidth: i.naturalWidth,
                                            shownWidth: Math.round(i.getBoundingClientRect().width)})),
    links: [...document.querySelectorAll('[href]')].map(a => a.getAttribute('href')),
    ids: [...document.querySelectorAll('[id]')].map(e => e.id),
    firstFigureTop: top(document.querySelector('figure')),
    narrowestDescription: desc.length ? Math.round(Math.min(...desc)) : null,
  };
})()
"""


def chromium() -> str | None:
    """The Chromium to use: $CHROMIUM, else chromium on the PATH."""
    return os.environ.get("CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")


class Browser:
    """One headless Chromium for many pages (a fresh profile, removed at close)."""

    def __init__(self, executable: str | None = None):
        exe = executable or chromium()
        if not exe:
            raise RuntimeError("no Chromium: install Debian's chromium (apt-get install chromium) "
                               "or name one in $CHROMIUM")
        self.profile = tempfile.mkdtemp(prefix="bindery-chromium-")
        to_child_r, self._to_child = os.pipe()
        self._from_child, from_child_w = os.pipe()

        def fds():  # the child reads commands on 3 and writes answers on 4
            os.dup2(to_child_r, 3)
            os.dup2(from_child_w, 4)

        self.proc = subprocess.Popen(
            [exe, *FLAGS, f"--user-data-dir={self.profile}", "--remote-debugging-pipe",
             "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=None if os.environ.get("BROWSER_DEBUG") else subprocess.DEVNULL,
            preexec_fn=fds, pass_fds=(3, 4))
        os.close(to_child_r)
        os.close(from_child_w)
        self._next = 0
        self._buffer = b""
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.call("Target.attachToTarget",
                                 {"targetId": target, "flatten": True})["sessionId"]
        self.call("Page.enable", session=True)

    def _send(self, message: dict):
        os.write(self._to_child, json.dumps(message).encode() + b"\0")

    def _receive(self) -> dict:
        while b"\0" not in self._buffer:
            chunk = os.read(self._from_child, 1 << 16)
            if not chunk:
                raise RuntimeError("Chromium closed the DevTools pipe")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method: str, params: dict | None = None, session: bool = False) -> dict:
        """Sends a command and returns its result (events meanwhile are dropped)."""
        self._next += 1
        message = {"id": self._next, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = self.session
        self._send(message)
        while True:
            reply = self._receive()
            if reply.get("id") == self._next:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})

    def wait_for(self, event: str):
        while True:
            message = self._receive()
            if message.get("method") == event and message.get("sessionId") == self.session:
                return message.get("params", {})

    def load(self, path: Path, width: int, height: int = 900):
        """Shows the page at this viewport width (a phone below 600 px: mobile emulation)."""
        self.call("Emulation.setDeviceMetricsOverride",
                  {"width": width, "height": height, "deviceScaleFactor": 1,
                   "mobile": width < 600}, session=True)
        self._next += 1
        self._send({"id": self._next, "method": "Page.navigate",
                    "params": {"url": Path(path).resolve().as_uri()}, "sessionId": self.session})
        self.wait_for("Page.loadEventFired")

    def measure(self, path: Path, width: int) -> dict:
        self.load(path, width)
        script = MEASURE.replace("VIEWPORT", str(int(width)))
        result = self.call("Runtime.evaluate", {"expression": script, "awaitPromise": True,
                                                "returnByValue": True}, session=True)
        if "exceptionDetails" in result:
            raise RuntimeError(f"measuring {path}: {result['exceptionDetails']}")
        return result["result"]["value"]

    def screenshot(self, path: Path, width: int, out: Path, top: int = 0, height: int | None = None):
        """The page at this width as a PNG: all of it, or `height` px from `top`."""
        import base64
        self.load(path, width)
        params = {"format": "png", "captureBeyondViewport": True}
        if height is not None:
            params["clip"] = {"x": 0, "y": top, "width": width, "height": height, "scale": 1}
        shot = self.call("Page.captureScreenshot", params, session=True)
        Path(out).write_bytes(base64.b64decode(shot["data"]))

    def close(self):
        try:
            self._send({"id": 0, "method": "Browser.close", "params": {}})
            self.proc.wait(timeout=10)
        except (OSError, subprocess.TimeoutExpired):
            self.proc.kill()
            self.proc.wait()
        os.close(self._to_child)
        os.close(self._from_child)
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def problems(page: Path, m: dict) -> list[str]:
    """What is wrong with a page as measured: horizontal overflow, an element wider than the
    viewport, an image that did not load, a link to a file that is not there or outside the
    page's folder, or to an anchor the page does not have."""
    out = []
    width = m["viewport"]
    if m["scrollWidth"] > width:
        out.append(f"the page is {m['scrollWidth']} px wide in a {width} px viewport")
    for w in m["wide"][:5]:
        out.append(f"<{w['tag']} id={w['id']!r} class={w['cls']!r}> spans {w['left']}..{w['right']} px "
                   f"in a {width} px viewport ({w['text']!r})")
    if len(m["wide"]) > 5:
        out.append(f"... {len(m['wide']) - 5} more elements beyond the viewport")
    for img in m["images"]:
        if img["naturalWidth"] == 0:
            out.append(f"image {img['src']!r} did not load")
    ids = set(m["ids"])
    for href in m["links"]:
        if href.startswith("#"):
            if href[1:] not in ids:
                out.append(f"link {href!r}: no such anchor in the page")
        elif "://" in href or href.startswith(("/", "..")) or "spec" in href.split("/"):
            out.append(f"link {href!r}: outside the FMU's documentation")
        elif not (page.parent / href.split("#")[0]).is_file():
            out.append(f"link {href!r}: no such file next to the page")
    return out


if __name__ == "__main__":
    with Browser() as b:
        for arg in sys.argv[1:]:
            for width in (1280, 390):
                m = b.measure(Path(arg), width)
                found = problems(Path(arg), m)
                print(f"{arg} at {width} px: document {m['scrollWidth']} px wide, "
                      f"{m['height']} px high, first figure at {m['firstFigureTop']} px, "
                      f"narrowest description {m['narrowestDescription']} px, "
                      f"{len(m['images'])} images, {len(m['links'])} links: "
                      + ("; ".join(found) if found else "fine"))
