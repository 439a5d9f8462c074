"""Helpers for the book's chapters: figures, tables and the paper's printed numbers.

Not re-exported from :mod:`flapping`: the chapters import them explicitly. Plotting needs the
``plot`` extra (matplotlib).
"""
