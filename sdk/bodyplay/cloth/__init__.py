"""Cloth simulation pinned to the skeleton, for the cloth-mirror game (DESIGN.md layout).

The package is reserved for it and holds no code yet.
"""
