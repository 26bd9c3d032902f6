"""Explicit finite-element ball models (thesis chapters 5 and 6)."""
