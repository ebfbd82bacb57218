"""Package list for setuptools (the rest of the metadata is in pyproject.toml).

The sample images stay in the visible top-level ``data/`` folder; the build
maps that folder into the package as ``branchnb._data``, so an installed
wheel carries them and :mod:`branchnb.data` reads them with
``importlib.resources``. pyproject.toml's ``packages.find`` cannot add a
package whose folder lies elsewhere, hence this file.

The measuring scripts beside each technique (``_*check*.py``, ``_measure*.py``:
procedural examples and figure tables run from a checkout with
``python -m branchnb.<technique>._name`` and imported by the tests) stay out
of the wheel; no shipped module imports them (``tests/test_wheel.py``).
"""

import fnmatch

from setuptools import find_packages, setup
from setuptools.command.build_py import build_py

MEASURING_SCRIPTS = ("_*check*.py", "_measure*.py")


def is_measuring_script(filename: str) -> bool:
    """Whether a module file is a checkout-only measuring script."""
    name = filename.replace("\\", "/").rsplit("/", 1)[-1]
    return any(fnmatch.fnmatch(name, pattern) for pattern in MEASURING_SCRIPTS)


class BuildWithoutMeasuringScripts(build_py):
    """``build_py`` that leaves the measuring scripts out of the wheel."""

    def find_package_modules(self, package, package_dir):
        return [entry for entry in super().find_package_modules(package, package_dir)
                if not is_measuring_script(entry[2])]


setup(
    cmdclass={"build_py": BuildWithoutMeasuringScripts},
    packages=find_packages(include=["branchnb", "branchnb.*"]) + ["branchnb._data"],
    package_dir={"branchnb._data": "data"},
    package_data={"branchnb._data": ["*.md", "*/*.png", "*/*.jpg", "*/*.json", "*/*.txt"],
                  "branchnb._docs": ["pages/*.md", "pages/*.rst", "pages/*/*.md", "static/*.css"]},
)
