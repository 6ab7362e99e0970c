"""PRE command 2's arithmetic: condense a 256x240 picture to 128x120.

PRE.FR averages each 2x2 block as ``(a+b+c+d+2)/4`` in INTEGER arithmetic (all
terms are non-negative, so FORTRAN truncation and floor agree).  The line order
(centre outward) and the frame-store side effects live with the PRE menu; the
result is exactly this block average (checked in tests/test_pre_condense.py).
"""

import numpy as np


def condense(picture: np.ndarray) -> np.ndarray:
    """Return the 120x128 condensed picture of a 240x256 4-bit picture."""
    pic = np.asarray(picture, dtype=np.int32)
    if pic.shape != (240, 256):
        raise ValueError(f"PRE condenses a 240x256 picture, got {pic.shape}")
    total = pic[0::2, 0::2] + pic[0::2, 1::2] + pic[1::2, 0::2] + pic[1::2, 1::2] + 2
    return (total // 4).astype(np.uint8)
