"""Jupyter widgets: the shared kit and one app per technique.

The kit: :class:`AnnotationCanvas` (with its pure-Python
:class:`AnnotationModel`), :class:`ParamPanel`, :class:`HistogramCompare`,
:class:`ImageView`, :class:`ErrorArea` and :class:`ProgressBar`.
"""

from .canvas import AnnotationCanvas
from .feedback import ErrorArea, ProgressBar
from .histograms import HistogramCompare
from .imageview import ImageView
from .model import AnnotationEvent, AnnotationModel, Shape
from .params import ParamPanel

__all__ = [
    "AnnotationCanvas",
    "AnnotationEvent",
    "AnnotationModel",
    "ErrorArea",
    "HistogramCompare",
    "ImageView",
    "ParamPanel",
    "ProgressBar",
    "Shape",
]
