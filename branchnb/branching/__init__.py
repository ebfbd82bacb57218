"""Branching structure synthesis ("Image Synthesis for Branching Structures").

Learn bending, branching and spacing from a skeleton drawn on an example
image, synthesize new skeletons, then a new image from fragments of the
example.
"""

from .structure import Branch, Structure

__all__ = ["Branch", "Structure"]
