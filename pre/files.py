"""Reading and publishing PRE's picture files (.VD, .BI) safely.

The byte layouts are :mod:`diskfmt.layouts` (Appendix E; docs/formats.md).  This
module adds what the 1985 OPEN/WRBLK calls did not promise: an output is
written under a temporary name in the same directory and renamed into place
with ``os.replace``, so no reader ever sees half a file and a failed write
leaves nothing behind; an existing output is refused unless the caller says
``force``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from diskfmt.rdos import write_atomic
from diskfmt.layouts import (BI_BYTES, POSIT_BYTES, VD_BYTES, FormatError, decode_bi,
                             decode_vd, encode_bi, encode_vd, read_file)


class PreError(Exception):
    """A clear, one-line problem with a file or a value (the CLI prints it and
    exits non-zero; the menu prints it and goes on)."""


def load_vd(path) -> np.ndarray:
    """A .VD file as a 240x256 array of 4-bit pixels."""
    try:
        return decode_vd(read_file(path), str(path))
    except FormatError as exc:
        raise PreError(_vd_hint(str(exc), path)) from None


def load_bi(path) -> np.ndarray:
    """A .BI file as a 120x128 array of 4-bit pixels; a file of another kind is
    named for what it is, with the command that makes a .BI of it."""
    data = _read(path)
    if len(data) != BI_BYTES:
        raise PreError(f"{path}: not a .BI picture: {what_file_is(data)}; {how_to_make_bi(data)}")
    try:
        return decode_bi(data, str(path))
    except FormatError as exc:
        raise PreError(str(exc)) from None


_MAGIC = ((b"\xff\xd8\xff", "a JPEG picture"), (b"\x89PNG\r\n\x1a\n", "a PNG picture"),
          (b"GIF8", "a GIF picture"), (b"BM", "a BMP picture"), (b"II*\x00", "a TIFF picture"),
          (b"MM\x00*", "a TIFF picture"), (b"P5", "a PGM picture"), (b"P6", "a PPM picture"),
          (b"RIFF", "a RIFF file (WebP picture or AVI video)"), (b"\x93NUMPY", "a NumPy array"))


def what_file_is(data: bytes) -> str:
    """A few words on what a file is, from its size and first bytes."""
    size = f"{len(data):,} bytes"
    if len(data) == VD_BYTES:
        return f"{size}, the size of a 256x240 .VD picture"
    if len(data) == POSIT_BYTES:
        return f"{size}, the size of ESTAR's POSIT.DT"
    for magic, kind in _MAGIC:
        if data.startswith(magic):
            return f"{size}, {kind}"
    if len(data) > 8 and data[4:8] == b"ftyp":
        return f"{size}, an MP4/MOV video or HEIC picture"
    return size if data else "an empty file"


def how_to_make_bi(data: bytes) -> str:
    if len(data) == VD_BYTES:
        return "make the .BI with `pre shrink X.VD -o X.BI`"
    return "make a pair with `pre pair LEFT.jpg RIGHT.jpg -o NAME` (NAME-L.BI, NAME-R.BI)"


def _vd_hint(msg: str, path) -> str:
    if msg.startswith(f"{path}: 30720 bytes"):
        return msg + " (that is the size of a .BI file, not a .VD)"
    return msg


def load_picture_file(path) -> np.ndarray:
    """A .VD or .BI file, told apart by its size (32768 or 30720 bytes)."""
    data = _read(path)
    if len(data) == 32768:
        return decode_vd(data, str(path))
    if len(data) == 30720:
        try:
            return decode_bi(data, str(path))
        except FormatError as exc:
            raise PreError(str(exc)) from None
    raise PreError(f"{path}: {len(data)} bytes, neither a .VD (32768) nor a .BI (30720) picture")


def _read(path) -> bytes:
    try:
        return read_file(path)
    except FormatError as exc:
        raise PreError(str(exc)) from None


def check_output(path, force: bool = False) -> Path:
    """Refuse an output that exists (unless ``force``) or whose directory does not."""
    p = Path(path)
    if p.is_dir():
        raise PreError(f"{p}: is a directory, not a file name")
    if p.exists() and not force:
        raise PreError(f"{p}: already exists; not overwritten (use --force to replace it)")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise PreError(f"{p}: directory {parent} does not exist")
    return p


def publish(path, data: bytes, force: bool = False) -> Path:
    """Write ``data`` to ``path`` through a temporary file in the same
    directory and ``os.replace``; never leaves a partial file."""
    p = check_output(path, force)
    try:                                      # the project's one atomic publish: without
        write_atomic(p, data, replace=force)  # --force the rename itself refuses (no race)
    except FileExistsError:                   # appeared while we wrote
        raise PreError(f"{p}: already exists; not overwritten (use --force to replace it)") from None
    return p


def publish_many(items: list[tuple[object, bytes]], force: bool = False) -> list[Path]:
    """Publish several outputs, checking all names before writing any."""
    for path, _ in items:
        check_output(path, force)
    return [publish(path, data, force) for path, data in items]


def save_vd(path, picture, force: bool = False) -> Path:
    return publish(path, encode_vd(picture), force)


def save_bi(path, picture, force: bool = False) -> Path:
    return publish(path, encode_bi(picture), force)
