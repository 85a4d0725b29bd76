"""Opening a page in Debian's headless Chromium, as a person's browser would: what its scripts did, the
errors they raised, and a screenshot.

Chromium prints a page's DOM once its scripts ran (``--dump-dom``); a copy of the page is opened with a
probe added before anything else, which records every error (uncaught, rejected, ``console.error``) and,
a moment after loading, runs the test's own script and writes both into the DOM for the test to read.
"""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from tests.patience import patient

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run")
VIEW = "--hide-scrollbars"
#: How long the page may run its timers (virtual time: no real waiting once it is idle), in ms.
BUDGET_MS = 5000

PROBE = """<script>
window.__errors = [];
window.addEventListener("error", function (e) { __errors.push(String(e.message || e)); });
window.addEventListener("unhandledrejection", function (e) { __errors.push("rejected: " + String(e.reason)); });
(function (original) {
  console.error = function () { __errors.push(Array.from(arguments).join(" ")); original.apply(console, arguments); };
})(console.error);
</script>"""

AFTER = """<script>
window.addEventListener("load", function () {
  var settled = function () { return new Promise(function (resolve) { setTimeout(resolve, 50); }); };
  var finish = function (results) {
    document.body.setAttribute("data-test-errors", JSON.stringify(__errors));
    document.body.setAttribute("data-test-results", JSON.stringify(results === undefined ? null : results));
  };
  settled()
    .then(function () { return (async function () { %s })(); })
    .catch(function (e) { __errors.push("test script: " + e); return null; })
    .then(finish);
});
</script>"""


@pytest.fixture(scope="session")
def chromium() -> str:
    """Skip without Chromium, but in CI, which installs it (scripts/install-reference.sh), fail."""
    if CHROMIUM is None:
        reason = "Chromium is not installed (apt-get install chromium; scripts/test.sh installs it as root)"
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must run the browser tests, but {reason}")
        pytest.skip(reason)
    return CHROMIUM


@dataclass(frozen=True)
class Opened:
    """A page as Chromium left it: its DOM, the errors its scripts raised, what the test script returned."""

    dom: str
    errors: list[str]
    results: Any

    @property
    def text(self) -> str:
        """The DOM's text, tags and scripts left out, entities decoded."""
        body = re.sub(r"<script\b.*?</script>", " ", self.dom, flags=re.S | re.I)
        return html.unescape(re.sub(r"<[^>]+>", " ", body))


def open_page(page: Path, script: str = "return null;", width: int | None = None) -> Opened:
    """Open ``page`` in headless Chromium (a window ``width`` pixels wide, if given); ``script`` (an async
    function's body, in which ``await settled()`` lets the page draw what it was asked to) runs once the page
    has loaded, and its result comes back as JSON."""
    assert CHROMIUM is not None
    probed = page.with_name(f"probed-{page.name}")
    text = page.read_text(encoding="utf-8")
    head = text.index("<head>") + len("<head>")
    end = text.rindex("</body>")
    probed.write_text(text[:head] + PROBE + text[head:end] + AFTER % script + text[end:], encoding="utf-8")
    window = () if width is None else (f"--window-size={width},1600",)
    done = _run("--dump-dom", *window, f"--virtual-time-budget={BUDGET_MS}", probed.as_uri())
    body = re.search(r"<body[^>]*>", done.stdout)
    assert body is not None, done.stdout[-2000:] + done.stderr[-2000:]
    attributes = dict(re.findall(r'(data-test-[a-z]+)="([^"]*)"', body.group(0)))
    assert "data-test-errors" in attributes, f"the page never finished loading: {done.stderr[-2000:]}"
    errors = json.loads(html.unescape(attributes["data-test-errors"]))
    results = json.loads(html.unescape(attributes["data-test-results"]))
    return Opened(done.stdout, errors, results)


def screenshot(page: Path, picture: Path, width: int = 1400, height: int = 2200) -> Path:
    """A PNG of ``page`` as a ``width`` x ``height`` window shows it."""
    budget = f"--virtual-time-budget={BUDGET_MS}"
    _run(f"--screenshot={picture}", VIEW, f"--window-size={width},{height}", budget, page.as_uri())
    assert picture.is_file() and picture.stat().st_size > 0, f"no screenshot written to {picture}"
    return picture


def png_size(picture: Path) -> tuple[int, int]:
    """(width, height) from a PNG's header."""
    data = picture.read_bytes()[:24]
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    assert CHROMIUM is not None
    return subprocess.run([CHROMIUM, *FLAGS, *args], capture_output=True, text=True, timeout=patient(120), check=False)
