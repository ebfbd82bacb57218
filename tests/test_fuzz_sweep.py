"""The whole deterministic fuzz sweep (``tests/fuzzkit.py``) as a test: every case, every package.

``tests/test_fuzz.py`` lets hypothesis pick and mutate a few cases per
package; a public name added later with an unchecked argument can slip past
those few draws (it happened: ``example_domain``, ``Dendrite.rescaled``, the
``costs`` of ``seam_cut``). This file runs every case the harness makes, in
its own file so it shares a worker with nothing slow (about 100 s in all).
"""

from __future__ import annotations

import io
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import fuzzkit  # noqa: E402


@pytest.mark.parametrize("package", fuzzkit.packages())
def test_every_fuzz_case_gets_a_clean_answer(package):
    table, failures = fuzzkit.sweep([package], timeout=30.0, out=io.StringIO())
    n, fails, classes = table[package]
    assert n > 0
    assert not failures, f"{fails} of {n} cases failed {classes}:\n" + "\n".join(
        f"{o.case!r}: {o.detail}" for o in failures[:20])
