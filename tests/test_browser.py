"""Real browser: JupyterLab + Debian's Chromium (Playwright) on the tour notebook.

Opens the tour, runs all cells, drags the mouse across the annotation
canvas and checks that the kernel received the stroke in image pixels and
that the canvas changed on screen. How to run it by hand is in the
README. Playwright cannot download its own browser here, so Debian's
``/usr/bin/chromium`` is used; the test is skipped only if it is missing.
Set ``BRANCHNB_SCREENSHOTS=DIR`` to keep a screenshot of the canvas.
"""

from __future__ import annotations

import json
import os
import secrets
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if Path("/usr/bin/chromium").exists() else None)

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed "
                                "(apt-get install -y chromium); .ci/run installs it")

LAUNCH_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
               "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _get(url: str):
    with urllib.request.urlopen(url, timeout=5) as r:
        return json.loads(r.read())


@pytest.fixture
def lab(tmp_path):
    """A JupyterLab server with an isolated config on a copy of the notebooks."""
    nbdir = tmp_path / "notebooks"
    shutil.copytree(ROOT / "notebooks", nbdir)
    cfg = tmp_path / "jupyter"
    settings = cfg / "lab-settings"
    (settings / "@jupyterlab" / "apputils-extension").mkdir(parents=True)
    (settings / "@jupyterlab" / "apputils-extension" / "notification.jupyterlab-settings").write_text(
        json.dumps({"fetchNews": "false", "checkForUpdates": False}))
    (settings / "@jupyterlab" / "docmanager-extension").mkdir(parents=True)
    (settings / "@jupyterlab" / "docmanager-extension" / "plugin.jupyterlab-settings").write_text(
        json.dumps({"autosave": False}))
    env = dict(os.environ, JUPYTER_CONFIG_DIR=str(cfg / "config"), JUPYTERLAB_SETTINGS_DIR=str(settings),
               JUPYTERLAB_WORKSPACES_DIR=str(cfg / "workspaces"), JUPYTER_RUNTIME_DIR=str(cfg / "runtime"))
    port, token = _free_port(), secrets.token_hex(16)
    cmd = [sys.executable, "-m", "jupyterlab", "--no-browser", "--ip=127.0.0.1", f"--port={port}",
           f"--IdentityProvider.token={token}", f"--ServerApp.root_dir={nbdir}", "--allow-root"]
    log = open(tmp_path / "lab.log", "w")
    proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT)
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(120):
            if proc.poll() is not None:
                pytest.fail("JupyterLab exited: " + (tmp_path / "lab.log").read_text()[-2000:])
            try:
                _get(f"{base}/api/status?token={token}")
                break
            except OSError:
                time.sleep(0.5)
        else:
            pytest.fail("JupyterLab did not start")
        yield {"base": base, "token": token, "runtime": cfg / "runtime", "log": tmp_path / "lab.log"}
    finally:
        try:
            req = urllib.request.Request(f"{base}/api/shutdown?token={token}", method="POST")
            urllib.request.urlopen(req, timeout=5)
            proc.wait(timeout=20)
        except Exception:
            proc.kill()
        log.close()


def _kernel_eval(runtime: Path, kernel_id: str, code: str) -> str:
    """Run ``code`` in the notebook's kernel (second client, same kernel) and return its stdout."""
    from jupyter_client import BlockingKernelClient

    client = BlockingKernelClient(connection_file=str(runtime / f"kernel-{kernel_id}.json"))
    client.load_connection_file()
    client.start_channels()
    try:
        msg_id = client.execute(code)
        out = []
        while True:
            msg = client.get_iopub_msg(timeout=30)
            if msg["parent_header"].get("msg_id") != msg_id:
                continue
            if msg["msg_type"] == "stream":
                out.append(msg["content"]["text"])
            elif msg["msg_type"] == "error":
                raise AssertionError("\n".join(msg["content"]["traceback"]))
            elif msg["msg_type"] == "status" and msg["content"]["execution_state"] == "idle":
                return "".join(out)
    finally:
        client.stop_channels()


def test_tour_canvas_drag_reaches_kernel(lab, tmp_path):
    from playwright.sync_api import sync_playwright

    base, token = lab["base"], lab["token"]
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True, args=LAUNCH_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1400, "height": 1000})
            page.goto(f"{base}/lab/tree/00_tour.ipynb?token={token}")
            # Wait for the kernel to exist, be idle and be connected before running anything.
            kernel = None
            for _ in range(120):
                ks = _get(f"{base}/api/kernels?token={token}")
                ready = [k for k in ks if k["execution_state"] == "idle" and k["connections"] >= 1]
                if ready:
                    kernel = ready[0]
                    break
                time.sleep(0.5)
            assert kernel, "no idle kernel connected to the notebook"
            page.wait_for_selector(".jp-Notebook", timeout=60_000)
            page.click("#jp-MainMenu .lm-MenuBar-item:has-text('Run')")
            page.click(".lm-Menu li[data-command='runmenu:run-all']")

            canvas_sel = ".jp-OutputArea-output .jupyter-widgets canvas"
            page.wait_for_selector(canvas_sel, timeout=120_000)
            # Wait for run-all to finish: the last code cell's output appears.
            for _ in range(240):
                probe = "print('style' in globals())"  # defined by one of the last cells
                if _kernel_eval(lab["runtime"], kernel["id"], probe).strip() == "True":
                    break
                time.sleep(0.5)
            canvas = page.locator(canvas_sel).first
            canvas.scroll_into_view_if_needed()
            time.sleep(1.0)
            box = canvas.bounding_box()
            assert box and box["width"] > 100
            before = np.frombuffer(page.screenshot(clip=box), np.uint8)

            n_before = int(_kernel_eval(lab["runtime"], kernel["id"],
                                        "print(len(canvas.model.of_kind('stroke')))"))
            start = (box["x"] + 0.30 * box["width"], box["y"] + 0.25 * box["height"])
            end = (box["x"] + 0.70 * box["width"], box["y"] + 0.65 * box["height"])
            page.mouse.move(*start)
            page.mouse.down()
            page.mouse.move(*end, steps=15)
            page.mouse.up()

            code = ("import json; s = canvas.model.of_kind('stroke'); "
                    "print(json.dumps({'n': len(s), 'pts': s[-1].points.tolist() if s else [], "
                    "'shape': list(canvas.image_shape)}))")
            got = None
            for _ in range(40):
                got = json.loads(_kernel_eval(lab["runtime"], kernel["id"], code))
                if got["n"] > n_before:
                    break
                time.sleep(0.5)
            assert got["n"] == n_before + 1, f"the kernel did not receive the stroke: {got}"
            pts = np.array(got["pts"])
            h, w = got["shape"]
            assert len(pts) >= 5
            # Image pixels: the drag went from 30 %/25 % to 70 %/65 % of the displayed canvas.
            assert np.allclose(pts[0], (0.30 * w, 0.25 * h), atol=0.03 * w)
            assert np.allclose(pts[-1], (0.70 * w, 0.65 * h), atol=0.03 * w)

            changed = 0
            for _ in range(20):
                after = np.frombuffer(page.screenshot(clip=box), np.uint8)
                changed = before.size != after.size or np.count_nonzero(before != after)
                if changed:
                    break
                time.sleep(0.25)
            shots = Path(os.environ.get("BRANCHNB_SCREENSHOTS", tmp_path))
            shots.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(shots / "tour_canvas.png"), clip={
                "x": 0, "y": max(box["y"] - 120, 0), "width": 1400, "height": box["height"] + 220})
            assert changed, "the canvas did not change on screen after the drag"
        finally:
            browser.close()
