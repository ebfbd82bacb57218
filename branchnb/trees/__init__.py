"""Image-based tree variations (Argudo, Andujar, Chica, CGF 2020)."""
