"""The command line: clear errors instead of tracebacks, and `branchnb lab` stops with its signals."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

from branchnb import cli

sys.path.insert(0, str(Path(__file__).resolve().parent))
from proctools import stop  # noqa: E402


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


# -- help, lab URL, app page ----------------------------------------------------------------
@pytest.mark.parametrize("argv", [["--help"], ["lab", "--help"], ["app", "--help"], ["gallery", "--help"],
                                  ["batch", "--help"], ["bench", "--help"]])
def test_help_is_plain_text(argv, capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    out = capsys.readouterr().out
    assert exit_.value.code == 0 and out.startswith("usage: branchnb")
    assert "``" not in out and ":func:" not in out and ":class:" not in out  # no reStructuredText


def test_lab_url_opens_the_tour_on_loopback_with_a_token(tmp_path):
    cmd, env, url = cli.lab_setup(extra=["--no-browser"], env={})
    token = env["JUPYTER_TOKEN"]
    assert len(token) >= 32 and token not in " ".join(cmd)            # not visible in ps
    assert url.startswith("http://127.0.0.1:") and url.endswith(f"/lab/tree/00_tour.ipynb?token={token}")
    port = url.split(":")[2].split("/")[0]
    assert f"--ServerApp.port={port}" in cmd and "--ServerApp.ip=127.0.0.1" in cmd
    assert f"--ServerApp.root_dir={cli.TOUR.parent}" in cmd
    # the user's own choices win and the URL follows them
    nb = tmp_path / "sub" / "my notebook.ipynb"
    nb.parent.mkdir()
    nb.write_text("{}")
    cmd, env, url = cli.lab_setup(nb, ["--port=9999", "--IdentityProvider.token=abc",
                                       f"--ServerApp.root_dir={tmp_path}", "--no-browser"], env={})
    assert url == "http://127.0.0.1:9999/lab/tree/sub/my%20notebook.ipynb?token=abc"
    assert "JUPYTER_TOKEN" not in env
    with pytest.raises(cli.CommandError, match="not a file"):
        cli.lab_setup(tmp_path / "missing.ipynb", env={})


def test_lab_prints_one_line_with_the_url(tmp_path):
    """The first line out of ``branchnb lab`` is the URL, and that URL serves the notebook."""
    pytest.importorskip("jupyterlab")
    nb = tmp_path / "empty.ipynb"
    nb.write_text('{"cells": [], "metadata": {}, "nbformat": 4, "nbformat_minor": 5}')
    proc = subprocess.Popen([sys.executable, "-m", "branchnb.cli", "lab", str(nb), "--no-browser"],
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                            text=True, cwd=tmp_path)
    try:
        line = proc.stdout.readline().strip()
        assert line.startswith("branchnb lab: http://127.0.0.1:") and line.endswith("?token=" + line[-48:])
        url = line.split(" ", 2)[2]
        deadline, status = time.time() + 90, None
        while time.time() < deadline and status is None:
            try:
                with urllib.request.urlopen(url, timeout=5) as r:
                    status = r.status
            except OSError:
                assert proc.poll() is None, "branchnb lab exited"
                time.sleep(0.5)
        assert status == 200
        api = url.split("/lab/")[0] + "/api/contents/empty.ipynb?token=" + url.split("token=")[1]
        with urllib.request.urlopen(api, timeout=5) as r:   # the URL's notebook is the one served
            assert r.status == 200
    finally:
        stop(proc)


def test_app_setup_checks_name_and_images_and_writes_the_page(tmp_path):
    from branchnb.widgets.apps import APPS

    assert tuple(cli.APP_HELP) == APPS
    with pytest.raises(cli.CommandError, match="NAME must be one of"):
        cli.app_setup("nope", folder=tmp_path)
    with pytest.raises(cli.CommandError, match="is not a file"):
        cli.app_setup("dendrite", [tmp_path / "missing.png"], folder=tmp_path)
    (tmp_path / "bad.png").write_bytes(b"not a png")
    with pytest.raises(cli.CommandError, match="could not read"):
        cli.app_setup("dendrite", [tmp_path / "bad.png"], folder=tmp_path)
    import numpy as np

    from branchnb.core.io import imsave

    img = imsave(tmp_path / "mine.png", np.full((20, 30, 3), 0.5, np.float32))
    cmd, env, url = cli.app_setup("dendrite", [img], folder=tmp_path)
    token = url.split("token=")[1]
    assert url.startswith("http://127.0.0.1:") and len(token) >= 32
    assert cmd[1:3] == ["-m", "voila"] and "--Voila.ip=127.0.0.1" in cmd and f"--token={token}" in cmd
    import nbformat

    nb = nbformat.read(str(tmp_path / "dendrite.ipynb"), as_version=4)
    assert len(nb.cells) == 1 and str(img.resolve()) in nb.cells[0].source


def test_gallery_reports_progress_from_the_first_second(tmp_path, monkeypatch, capsys):
    import branchnb.gallery as gallery

    def fake_build(outdir, progress=None):
        progress("sample data")
        import numpy as np

        from branchnb.core.io import imsave

        imsave(outdir / "one.png", np.zeros((4, 4, 3)))
        progress("branching")
        time.sleep(1.5)  # a slow picture: the command says it is still working
        imsave(outdir / "two.png", np.zeros((4, 4, 3)))
        return [1, 2]

    monkeypatch.setattr(gallery, "build", fake_build)
    monkeypatch.setattr(cli, "HEARTBEAT", 0.6)
    assert cli.main(["gallery", str(tmp_path / "g")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("branchnb gallery: rendering")
    assert any(line.endswith("one.png") for line in out) and any(line.endswith("two.png") for line in out)
    assert [line.split()[-2] for line in out if line.endswith(" ...") and "still" not in line] == ["data", "branching"]
    assert out[-1].startswith("wrote 2 pictures")
    assert any("branching: still working" in line for line in out)


def test_bench_reports_each_suite_as_it_starts(monkeypatch, capsys):
    import branchnb.bench as bench

    def fake_run(quick=False, suites=bench.SUITES, progress=None):
        progress("core")
        progress("branching")
        return [bench.BenchRow("x", 1.0, "y", 2.0)]

    monkeypatch.setattr(bench, "run", fake_run)
    assert cli.main(["bench", "--quick"]) == 0
    got = capsys.readouterr()
    assert got.err.splitlines()[0].startswith("branchnb bench:")
    assert [line.split()[-2] for line in got.err.splitlines()[1:]] == ["core", "branching"]
    assert "0.500" in got.out                     # the table, with the ratio
