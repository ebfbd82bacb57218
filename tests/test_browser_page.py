"""Real browser: one app as a web page, served by ``branchnb app strokes`` (Voila).

The command prints one URL; the page shows the app alone (no code cells),
a stroke drawn on it reaches the kernel, the layout holds (the checks of
``test_browser.py``), "open source image" takes the user's file through
the upload dialog, and "save" hands the annotations over as a download.
A file of its own so that it runs beside the notebook tests.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import test_browser as tb  # noqa: E402
from proctools import stop  # noqa: E402
from test_browser import CHROMIUM, ROOT, SHOTS, _canvas_box, _check_layout, _drag  # noqa: E402

chromium = tb.chromium  # the same module-scoped browser fixture

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed "
                                "(apt-get install -y chromium); .ci/run installs it")


def test_app_page_from_branchnb_app(chromium, tmp_path):
    """``branchnb app strokes`` prints one URL; the page shows the app alone, and drawing on it works."""
    pytest.importorskip("voila")
    cfg = tmp_path / "jupyter"
    env = dict(os.environ, JUPYTER_CONFIG_DIR=str(cfg / "config"), JUPYTER_RUNTIME_DIR=str(cfg / "runtime"),
               PYTHONPATH=os.pathsep.join([str(ROOT)] + [p for p in [os.environ.get("PYTHONPATH")] if p]))
    log = open(tmp_path / "voila.log", "w")
    proc = subprocess.Popen([sys.executable, "-m", "branchnb.cli", "app", "strokes"], stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=log, text=True, env=env, cwd=tmp_path)
    page = None
    try:
        line = proc.stdout.readline().strip()
        assert line.startswith("branchnb app: http://127.0.0.1:") and "?token=" in line, line
        url = line.split(" ", 2)[2]
        page = chromium.new_page(viewport={"width": 1400, "height": 1000})
        for _ in range(120):  # the server needs a moment after printing its URL
            try:
                page.goto(url, timeout=120_000)
                break
            except Exception:  # noqa: BLE001 - connection refused until it listens
                assert proc.poll() is None, (tmp_path / "voila.log").read_text()[-2000:]
                time.sleep(0.5)
        page.wait_for_selector(".bnb-app .bnb-canvas canvas", timeout=180_000)
        time.sleep(1.0)
        # the app alone: no code, no prompts
        assert page.locator(".jp-InputArea, .jp-InputPrompt").count() == 0
        assert "open_app" not in page.locator("body").inner_text()
        status = page.locator(".bnb-app .bnb-canvas").first
        n0 = status.inner_text()
        box = _canvas_box(page, 0)
        _drag(page, box, [(0.2, 0.5), (0.5, 0.45), (0.8, 0.5)])
        for _ in range(60):  # the canvas' own status line is written by the kernel
            if "1 shapes" in status.inner_text():
                break
            time.sleep(0.25)
        assert "1 shapes" in status.inner_text(), f"the stroke did not reach the kernel: {n0!r}"
        _check_layout(page, "branchnb app strokes")
        # "open source image": the user's own file replaces the sample
        from branchnb.core.io import imsave

        mine = np.zeros((90, 160, 4), np.float32)
        mine[35:55, 10:150] = (0.2, 0.6, 0.3, 1.0)
        imsave(tmp_path / "mine.png", mine)
        with page.expect_file_chooser() as chooser:  # the upload button opens the file dialog
            page.locator(".bnb-app .widget-upload").first.click()
        chooser.value.set_files(str(tmp_path / "mine.png"))
        for _ in range(60):
            if "160×90 px" in status.inner_text():
                break
            time.sleep(0.25)
        assert "160×90 px" in status.inner_text(), status.inner_text()
        # "save": the files come as downloads in a page (no server folder shown)
        assert page.locator(".bnb-app .widget-text input[placeholder='folder']").count() == 0 or \
            not page.locator(".bnb-app .widget-text input[placeholder='folder']").first.is_visible()
        page.locator(".bnb-app .widget-button:text-is('save')").first.click()
        link = page.locator(".bnb-app .bnb-links a").first
        link.wait_for(timeout=30_000)
        with page.expect_download() as dl:
            link.click()
        got = Path(dl.value.path()).read_bytes()
        assert dl.value.suggested_filename == "strokes_annotations.json"
        assert json.loads(got)["app"] == "strokes"
        out = SHOTS or tmp_path
        out.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(out / "app_page_strokes.png"))
        assert page.locator(".bnb-app .bnb-status-error").count() == 0
    finally:
        if page is not None:
            page.close()
        stop(proc)
        log.close()
