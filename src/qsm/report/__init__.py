"""Figures and the Markdown summary of a run."""
