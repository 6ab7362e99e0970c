"""The robot's eyes: the 1985 rig (NSTAR's slices and edge maps, ESTAR's
MASL/MARF and LCSL, POSIT.DT) as one compiled scan of a whole frame.

The faithful reference is ESTAR's Eclipse talking to NSTAR's Nova (in process
or over the JHDATA file link); the eyes compute the same features, match
lists, positions and POSIT.DT image, bit for bit, in about a millisecond a
picture (README, "Speed").  ``Eyes(ds, dv, options).scan(left, right)``."""

from .frame import DEFAULT_LINES, Eyes, FrameScan, scan_pair, words_to_float

__all__ = ["DEFAULT_LINES", "Eyes", "FrameScan", "scan_pair", "words_to_float"]
