"""A report page as a reader sees it: Debian's ``chromium`` headless at a given window size, measured by a script.

``measure(page)`` copies the page beside itself with a script appended that reads, once the page has loaded,
``document.documentElement.scrollWidth`` and the positions of the elements a reader looks for (the bottom line, the
first figure, every table, the contents' engine links), and writes them as JSON into the DOM; ``chromium --dump-dom``
prints that DOM.  Nothing is mocked: the layout is Chromium's own.
"""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
from pathlib import Path

__all__ = ["chromium", "measure"]

WIDTH, HEIGHT = 1400, 900

_SCRIPT = """
<script>
window.addEventListener('load', () => {
  const box = e => { if (!e) return null; const r = e.getBoundingClientRect();
    return {top: r.top, bottom: r.bottom, left: r.left, right: r.right, width: r.width, height: r.height}; };
  const img = document.querySelector('figure.first img');
  const out = {
    scrollWidth: document.documentElement.scrollWidth,
    clientWidth: document.documentElement.clientWidth,
    innerWidth: window.innerWidth, innerHeight: window.innerHeight,
    h1: box(document.querySelector('h1')), h1_text: (document.querySelector('h1') || {}).textContent || '',
    bottom_line: box(document.getElementById('bottom-line')),
    figure: box(img), figure_loaded: !!(img && img.complete && img.naturalWidth > 0),
    tables: [...document.querySelectorAll('table')].map(t => ({box: box(t), scrollWidth: t.scrollWidth,
      container: t.parentElement.clientWidth,
      caption: (t.parentElement.previousElementSibling || {}).textContent || ''})),
    engine_links: [...document.querySelectorAll('nav.toc a.engine')].map(a => a.getAttribute('href')),
  };
  const pre = document.createElement('pre'); pre.id = 'crosscheck-measure'; pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
"""

_MEASURED = re.compile(r'<pre id="crosscheck-measure">(.*?)</pre>', re.S)


def chromium() -> str:
    """The Chromium executable (Debian's ``chromium``; CI installs it, ``.ci/run``)."""
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        raise RuntimeError("chromium is not installed: apt-get install -y chromium (.ci/run does this in CI)")
    return exe


def measure(page: Path, *, width: int = WIDTH, height: int = HEIGHT, timeout: float = 120.0) -> dict:
    """What Chromium lays out for ``page`` in a ``width`` x ``height`` window (CSS pixels), as a dict."""
    page = Path(page)
    probe = page.with_name(f".measure_{page.name}")  # beside the page: its relative links and images resolve
    probe.write_text(page.read_text().replace("</body>", _SCRIPT + "</body>"))
    try:
        done = subprocess.run(
            [chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
             f"--window-size={width},{height}", "--virtual-time-budget=10000", "--dump-dom", probe.resolve().as_uri()],
            capture_output=True, text=True, timeout=timeout,
        )  # fmt: skip
    finally:
        probe.unlink()
    found = _MEASURED.search(done.stdout)
    if found is None:
        raise RuntimeError(f"chromium printed no measurement (exit {done.returncode}): {done.stderr[-2000:]}")
    return json.loads(html.unescape(found.group(1)))
