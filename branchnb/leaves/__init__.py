"""Leaf variations by structural layering (Assa & Cohen-Or, C&G 2012)."""
