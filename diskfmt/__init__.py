"""The shared disk of the 1985 rig: Data General REALs, the JHDATA file layouts,
and RDOS file semantics (publish by rename, wait, take)."""

from .dgreal import Real, fortran_f
from .layouts import FormatError

__all__ = ["Real", "fortran_f", "FormatError", "version"]


def version() -> str:
    """The installed holten-rig version, for every program's ``--version``."""
    try:
        from importlib.metadata import version as installed
        return installed("holten-rig")
    except Exception:                      # running from a checkout that is not installed
        return "unknown (not installed)"
