"""Image-based tree variations (placeholder, filled below)."""
