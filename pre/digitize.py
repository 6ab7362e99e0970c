"""Today's pictures into the rig: the digitizer model behind ``pre import``.

In 1985 a Dage camera fed the OCTEK 2000, which digitized a 256x240 picture of
16 grey levels (PRE command 1, then command 11 stored it as a .VD file).  Today
a picture comes from a file, a video or a webcam; this module turns it into
the same thing, in four documented steps (docs/pre.md, "Digitizer model"):

1. **grey**: a colour picture becomes its luminance
   ``Y = 0.299 R + 0.587 G + 0.114 B`` (ITU-R BT.601, the luma a monochrome
   TV camera of the time delivered); alpha is dropped; 16-bit pictures are
   scaled by 255/65535, floating-point ones by 255 (0..1 full scale).
2. **fit** to 256x240 (``crop`` default, ``stretch``, ``pad``): ``crop`` cuts
   the centre of the picture to the 256:240 shape and scales it with area
   averaging, keeping pixels square and adding no borders; ``stretch`` scales
   the whole picture (non-square pixels if the shape differs); ``pad`` scales
   the whole picture to fit and fills the rest with black (0, blanking level).
3. **brightness / contrast** (off by default): the software control
   Chapter VI recommends -- ``Y' = (Y - 127.5) * contrast + 127.5 +
   brightness`` (gain about the middle of the range, then a d.c. bias), or
   ``auto`` levels that map the 1st..99th percentile onto 0..255.
4. **16 grey levels**: a uniform 4-bit converter over 0..255,
   ``level = floor(Y / 16)`` clipped to 0..15.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .files import PreError

WIDTH, HEIGHT = 256, 240
FITS = ("crop", "stretch", "pad")
DEFAULT_FIT = "crop"
PICTURE_SUFFIXES = {".png", ".jpg", ".jpeg", ".pgm", ".ppm", ".pbm", ".pnm", ".tif",
                    ".tiff", ".bmp", ".webp", ".jp2"}


def _cv2():
    import cv2          # imported late: the 1985 menu does not need it
    return cv2


@dataclass(frozen=True)
class Levels:
    """Software brightness/contrast control (Chapter VI recommendation).
    ``auto`` chooses gain and bias from the picture's 1st..99th percentile."""
    brightness: float = 0.0
    contrast: float = 1.0
    auto: bool = False

    @property
    def active(self) -> bool:
        return self.auto or self.brightness != 0.0 or self.contrast != 1.0


# --- sources -------------------------------------------------------------------

def parse_camera(source: str) -> int | None:
    """``cam:N`` / ``webcam:N`` names webcam N; anything else is a file."""
    for prefix in ("cam:", "webcam:"):
        if source.lower().startswith(prefix):
            rest = source[len(prefix):] or "0"
            try:
                return int(rest)
            except ValueError:
                raise PreError(f"{source}: camera number {rest!r} is not a number") from None
    return None


def read_source(source: str, frame: int = 0) -> np.ndarray:
    """The picture named by ``source`` as OpenCV reads it (any depth, grey or
    BGR(A)): a picture file, frame ``frame`` of a video file, or a webcam
    frame (``cam:N``)."""
    cv2 = _cv2()
    cam = parse_camera(source)
    if cam is not None:
        return _grab(cv2.VideoCapture(cam), f"webcam {cam}", 0)
    p = Path(source)
    if not p.exists():
        raise PreError(f"{source}: no such file")
    if p.is_dir():
        raise PreError(f"{source}: is a directory, not a picture")
    if not os.access(p, os.R_OK):
        raise PreError(f"{source}: cannot be read (permission denied)")
    if p.stat().st_size == 0:
        raise PreError(f"{source}: empty file, not a picture")
    img = None
    if frame == 0:
        img = cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
    if img is not None and img.size:
        return img
    if p.suffix.lower() in PICTURE_SUFFIXES and frame == 0:
        raise PreError(f"{source}: not a picture OpenCV can read (damaged or not really "
                       f"{p.suffix.lower()[1:].upper()})")
    cap = cv2.VideoCapture(str(p))
    if not cap.isOpened():
        raise PreError(f"{source}: not a picture or video OpenCV can read")
    return _grab(cap, source, frame)


def _grab(cap, name: str, frame: int) -> np.ndarray:
    cv2 = _cv2()
    try:
        if not cap.isOpened():
            raise PreError(f"{name}: cannot be opened")
        if frame < 0:
            raise PreError(f"{name}: frame {frame} is negative")
        if frame:
            cap.set(cv2.CAP_PROP_POS_FRAMES, frame)
        ok, img = cap.read()
        if not ok or img is None:
            raise PreError(f"{name}: no frame {frame} (the video is shorter or unreadable)")
        return img
    finally:
        cap.release()


# --- the model -----------------------------------------------------------------

def to_grey(img: np.ndarray) -> np.ndarray:
    """Step 1: luminance on the 0..255 scale, float64."""
    a = np.asarray(img)
    if a.dtype == np.uint8:
        scale = 1.0
    elif a.dtype == np.uint16:
        scale = 255.0 / 65535.0
    elif np.issubdtype(a.dtype, np.floating):
        scale = 255.0
    elif np.issubdtype(a.dtype, np.integer):
        scale = 255.0 / float(np.iinfo(a.dtype).max)
    elif a.dtype == np.bool_:
        scale = 255.0
    else:
        raise PreError(f"pixels of type {a.dtype} are not a grey or colour picture")
    a = a.astype(np.float64) * scale
    if a.ndim == 2:
        return a
    if a.ndim == 3 and a.shape[2] == 1:
        return a[:, :, 0]
    if a.ndim == 3 and a.shape[2] in (3, 4):          # OpenCV order: B, G, R (, A)
        return 0.114 * a[:, :, 0] + 0.587 * a[:, :, 1] + 0.299 * a[:, :, 2]
    raise PreError(f"a picture of shape {a.shape} is neither grey nor colour")


def fit(grey: np.ndarray, how: str = DEFAULT_FIT) -> np.ndarray:
    """Step 2: the 240x256 picture (float64) by ``crop``, ``stretch`` or ``pad``."""
    cv2 = _cv2()
    if how not in FITS:
        raise PreError(f"--fit {how!r}: expected one of {', '.join(FITS)}")
    g = np.asarray(grey, dtype=np.float64)
    h, w = g.shape
    if h < 1 or w < 1:
        raise PreError("the picture has no pixels")
    if how == "crop":
        if w * HEIGHT > h * WIDTH:                       # too wide: cut the sides
            cw = max(1, round(h * WIDTH / HEIGHT))
            x0 = (w - cw) // 2
            g = g[:, x0:x0 + cw]
        elif w * HEIGHT < h * WIDTH:                     # too tall: cut top and bottom
            ch = max(1, round(w * HEIGHT / WIDTH))
            y0 = (h - ch) // 2
            g = g[y0:y0 + ch, :]
        return _resize(g, WIDTH, HEIGHT)
    if how == "stretch":
        return _resize(g, WIDTH, HEIGHT)
    # pad
    scale = min(WIDTH / w, HEIGHT / h)
    nw, nh = max(1, min(WIDTH, round(w * scale))), max(1, min(HEIGHT, round(h * scale)))
    out = np.zeros((HEIGHT, WIDTH), dtype=np.float64)
    x0, y0 = (WIDTH - nw) // 2, (HEIGHT - nh) // 2
    out[y0:y0 + nh, x0:x0 + nw] = _resize(g, nw, nh)
    return out


def _resize(g: np.ndarray, w: int, h: int) -> np.ndarray:
    cv2 = _cv2()
    if g.shape == (h, w):
        return g.copy()
    # Area averaging: what a camera's sensor cell and the digitizer's sample
    # do to finer detail (exact block means for whole-number reductions).
    interp = cv2.INTER_AREA if (g.shape[0] >= h and g.shape[1] >= w) else cv2.INTER_LINEAR
    return cv2.resize(g.astype(np.float32), (w, h), interpolation=interp).astype(np.float64)


def apply_levels(grey: np.ndarray, levels: Levels) -> np.ndarray:
    """Step 3 (optional): brightness and contrast, software-controlled."""
    g = np.asarray(grey, dtype=np.float64)
    if not levels.active:
        return g
    contrast, brightness = levels.contrast, levels.brightness
    if levels.auto:
        lo, hi = np.percentile(g, [1.0, 99.0])
        if hi - lo < 1e-9:
            contrast, brightness = 1.0, 127.5 - (lo + hi) / 2
        else:
            # gain puts the percentile range onto 0..255; the bias puts its
            # midpoint at the middle of the range
            contrast = 255.0 / (hi - lo)
            brightness = -((lo + hi) / 2 - 127.5) * contrast
    return np.clip((g - 127.5) * contrast + 127.5 + brightness, 0.0, 255.0)


def quantize(grey: np.ndarray) -> np.ndarray:
    """Step 4: 16 grey levels, ``floor(Y/16)`` clipped to 0..15."""
    g = np.clip(np.asarray(grey, dtype=np.float64), 0.0, 255.0)
    return np.minimum(np.floor(g / 16.0), 15).astype(np.uint8)


def digitize(img: np.ndarray, how: str = DEFAULT_FIT, levels: Levels = Levels()) -> np.ndarray:
    """The whole model: any picture -> 240x256 4-bit picture (a .VD's content)."""
    return quantize(apply_levels(fit(to_grey(img), how), levels))


def import_picture(source: str, how: str = DEFAULT_FIT, levels: Levels = Levels(),
                   frame: int = 0) -> np.ndarray:
    """``pre import``: read a picture/video frame/webcam frame and digitize it."""
    return digitize(read_source(source, frame), how, levels)
