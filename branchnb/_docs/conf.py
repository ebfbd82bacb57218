"""Sphinx configuration of the documentation site (used by :func:`branchnb._docs.build`).

The builder copies the pages of this folder, the notebooks and the generated
API pages into one source folder and runs Sphinx there; nothing here reaches
the network (no intersphinx, notebooks rendered from their stored outputs).
"""

import os

import branchnb

project = "branchnb"
author = "the branchnb developers"
copyright = "the branchnb developers, BSD-3-Clause"
version = release = branchnb.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_nb",
    "branchnb._docs.xref",
]

# Notebooks are shown exactly as committed: their stored outputs, never executed here.
nb_execution_mode = "off"
nb_merge_streams = True
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}

# One object, one place: numpydoc lists parameters; autodoc's :members: lists methods.
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks = set()
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_default_options = {"show-inheritance": False}
add_module_names = False

# Every :class:/:func:/:mod: reference inside branchnb must resolve. Names of other
# libraries (no inventories offline) and the plain-language types of numpydoc's
# "Parameters" lines are the only ones allowed to stay unresolved.
nitpicky = True
nitpick_ignore_regex = [
    (r"py:.*", r"(numpy|np|scipy|matplotlib|mpl|ipywidgets|ipycanvas|traitlets|dask|distributed|collections"
               r"|typing|typing_extensions|pathlib|os|io|json|enum|dataclasses|types|abc|concurrent|cv2|skimage"
               r"|sklearn|tqdm|numba|maxflow|PIL|argparse|threading|asyncio|contextlib|functools|tempfile|t)(\..*)?"),
    # a stringified annotation that Sphinx splits at its comma
    (r"py:.*", r"(tuple|list|dict|set|type)\[.*"),
    (r"py:.*", r"[\w.]+ \| (tuple|list|dict|set|type)\[.*"),
    (r"py:.*", r"(int|float|str|bool|bytes|dict|list|tuple|set|frozenset|object|type|None|NoneType|callable"
               r"|Callable|Any|Path|Sequence|Mapping|Iterable|Iterator|Generator|Literal|Optional|Union|ndarray"
               r"|array_like|array-like|optional|Self|TypeVar|ClassVar|Exception|ValueError|TypeError|RuntimeError"
               r"|KeyError|OSError|Ellipsis|slice|complex|memoryview|bytearray|range|property|T|P|R|Figure|Axes"
               r"|AxesImage|Generator\[.*\]|Future|Client|LocalCluster)"),
]

suppress_warnings = [
    # The notebooks are written for Jupyter: a heading may skip a level there.
    "myst.header",
]

exclude_patterns = ["_build", "**.ipynb_checkpoints", "jupyter_execute"]
templates_path = []
html_theme = "pydata_sphinx_theme"
html_title = f"branchnb {release}"
html_static_path = ["_static"]
html_css_files = ["branchnb.css"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 8,
    "secondary_sidebar_items": ["page-toc"],
}
html_sidebars = {"**": ["sidebar-nav-bs"]}
html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None

# Quiet and deterministic: no "last updated" date, no Git lookups.
os.environ.setdefault("PYDEVD_DISABLE_FILE_VALIDATION", "1")
