"""Package list for setuptools (the rest of the metadata is in pyproject.toml).

The sample images stay in the visible top-level ``data/`` folder; the build
maps that folder into the package as ``branchnb._data``, so an installed
wheel carries them and :mod:`branchnb.data` reads them with
``importlib.resources``. pyproject.toml's ``packages.find`` cannot add a
package whose folder lies elsewhere, hence this file.
"""

from setuptools import find_packages, setup

setup(
    packages=find_packages(include=["branchnb", "branchnb.*"]) + ["branchnb._data"],
    package_dir={"branchnb._data": "data"},
    package_data={"branchnb._data": ["*.md", "*/*.png", "*/*.jpg", "*/*.json", "*/*.txt"],
                  "branchnb._docs": ["pages/*.md", "pages/*.rst", "pages/*/*.md", "static/*.css"]},
)
