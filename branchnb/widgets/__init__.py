"""Jupyter widgets: the shared kit and one app per technique.

The kit: :class:`AppShell` (the layout, busy state and status line every
app uses; see :mod:`branchnb.widgets.shell` for how an app is built on
it), :class:`AnnotationCanvas` (with its pure-Python
:class:`AnnotationModel`), :class:`ParamPanel`, :class:`HistogramCompare`,
:class:`ImageView`, :class:`StatusLine`, :class:`ErrorArea` and
:class:`ProgressBar`; :class:`~branchnb.widgets.files.FileBar` gives every
app "open image", "save" and "load annotations", and
:func:`branchnb.widgets.apps.open_app` opens any technique's app by name
(what ``branchnb app`` serves as a page).
"""

from .canvas import AnnotationCanvas
from .feedback import Cancelled, ErrorArea, ProgressBar, StatusLine
from .histograms import HistogramCompare
from .imageview import ImageView
from .model import AnnotationEvent, AnnotationModel, Shape
from .params import ParamPanel
from .shell import AppShell

__all__ = [
    "AnnotationCanvas",
    "AnnotationEvent",
    "AnnotationModel",
    "AppShell",
    "Cancelled",
    "ErrorArea",
    "HistogramCompare",
    "ImageView",
    "ParamPanel",
    "ProgressBar",
    "Shape",
    "StatusLine",
]
