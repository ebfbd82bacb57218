"""The command line: clear errors instead of tracebacks, and `branchnb lab` stops with its signals."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request

import pytest

from branchnb import cli


def _gallery(capsys, outdir):
    code = cli.main(["gallery", outdir])
    return code, capsys.readouterr().err


def test_gallery_refuses_an_empty_folder_name(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, err = _gallery(capsys, "")
    assert code == 1 and "OUTDIR is empty" in err
    assert list(tmp_path.iterdir()) == []                  # nothing written into the current folder


def test_gallery_onto_an_existing_file(capsys, tmp_path):
    target = tmp_path / "index.html"
    target.write_text("keep me")
    code, err = _gallery(capsys, str(target))
    assert code == 1 and "is an existing file" in err
    assert target.read_text() == "keep me"


def test_gallery_into_a_folder_that_cannot_be_written(capsys, tmp_path):
    (tmp_path / "file").write_text("")
    code, err = _gallery(capsys, str(tmp_path / "file" / "sub"))   # a folder under a file
    assert code == 1 and "cannot write to OUTDIR" in err
    if os.geteuid() != 0:                                  # root writes anywhere
        locked = tmp_path / "locked"
        locked.mkdir(mode=0o500)
        code, err = _gallery(capsys, str(locked))
        assert code == 1 and "cannot write" in err


def test_gallery_errors_print_no_traceback(tmp_path):
    (tmp_path / "f").write_text("")
    run = subprocess.run([sys.executable, "-m", "branchnb.cli", "gallery", str(tmp_path / "f")],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 1
    assert "Traceback" not in run.stderr and "branchnb gallery: error:" in run.stderr


def test_lab_command_opens_the_tour_and_adds_allow_root_for_root():
    cmd = cli.lab_command()
    assert cmd[:3] == [sys.executable, "-m", "jupyterlab"] and cmd[3].endswith("00_tour.ipynb")
    assert ("--allow-root" in cmd) == (os.geteuid() == 0)
    assert cli.lab_command("x.ipynb", ["--no-browser"])[3:4] == ["x.ipynb"]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _serving(port: int) -> bool:
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/api", timeout=2) as r:
            return r.status == 200
    except OSError:
        return False


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_to_branchnb_lab_stops_the_server(tmp_path, sig):
    pytest.importorskip("jupyterlab")
    port = _free_port()
    nb = tmp_path / "empty.ipynb"
    nb.write_text('{"cells": [], "metadata": {}, "nbformat": 4, "nbformat_minor": 5}')
    proc = subprocess.Popen(
        [sys.executable, "-m", "branchnb.cli", "lab", str(nb), "--no-browser", f"--port={port}",
         "--ServerApp.token=", f"--ServerApp.root_dir={tmp_path}"],
        stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=tmp_path)
    try:
        deadline = time.time() + 90
        while time.time() < deadline and not _serving(port):
            assert proc.poll() is None, "branchnb lab exited before serving"
            time.sleep(0.3)
        assert _serving(port), "JupyterLab never answered"
        proc.send_signal(sig)
        proc.wait(timeout=30)
        time.sleep(0.5)
        assert not _serving(port)                          # no server left behind
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
