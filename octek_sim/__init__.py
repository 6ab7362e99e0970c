"""The simulated OCTEK 2000 image analyser card (frame store and library calls)."""

from .board import Octek, OctekError, WIDTH, HEIGHT

__all__ = ["Octek", "OctekError", "WIDTH", "HEIGHT"]
