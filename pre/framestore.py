"""PRE.FR's work on the OCTEK frame store, label by label (Appendix F).

Each function is one menu command's board and disk traffic, written with the
listing's own calls (RVBLK, WVBLK, PXFILL, GVECT) on an :class:`octek_sim.board.Octek`
and the listing's block loops, so that the frame store ends up exactly as the
1985 program left it.  Buffers follow the library convention: FORTRAN
``IBUF(k)`` is ``buf[k-1]``, element 0 the header word (QUIRKS M7).

Geometry (docs/pre.md): the 256x240 picture sits at x 32..287, rows 0..239;
the condensed 128x120 picture at x 96..223, rows 60..179, with a black box
one pixel outside it.
"""

from __future__ import annotations

import numpy as np

from octek_sim.board import Octek

VD_X, VD_W = 32, 256          # IXP=32, IXL=256 (commands 10, 11); IX=32 (command 2)
BI_X, BI_Y = 96, 60           # INX=96 (command 2), IX=96 IY=60 (commands 4, 5)
BI_W, BI_H = 128, 120
BLOCK_WORDS = 256             # one RDOS block


def _word(v) -> int:
    return int(v) & 0xFFFF


# --- command 2 -----------------------------------------------------------------

def condense_frame(ict: Octek) -> None:
    """Command 2, "Create condensed image for NSTAR" (label 20).

    Centre outward: pass INY (0..59) reads the two source lines 120+2*INY,
    121+2*INY into IBUF1 and 118-2*INY, 119-2*INY into IBUF2, blanks both
    bands white over the full width, averages each 2x2 block as
    ``(a+b+c+d+2)/4`` in place (IBUF1(IIN), IIN=ILOC+2, OCR repairs of
    QUIRKS P1) and writes the results to rows 120+INY and 119-INY at x 96.
    Then a black box is drawn around the 128x120 picture."""
    inx, inxl, inyl = 96, 128, 120
    inyl1 = (inyl // 2) - 1
    ix, ixl = 32, 256
    for iny in range(0, inyl1 + 1):                      # DO 25 INY=0,INYL1
        iy = iny + iny
        iyb = 120 + iy
        iyt = 118 - iy
        ibuf1 = ict.rvblk(ix, ixl, iyb, 2)               # CALL RVBLK(ICT,IBUF1,IX,IXL,IYB,2)
        ibuf2 = ict.rvblk(ix, ixl, iyt, 2)
        ict.pxfill(15, 0, 320, iyb, 2)                   # blank them
        ict.pxfill(15, 0, 320, iyt, 2)
        for iloc in range(0, 128):                       # DO 21 ILOC=0,127
            iin = iloc + 2
            il1 = iloc + iloc + 2
            il11 = il1 + 1
            il2 = il1 + 256
            il21 = il2 + 1
            # IBUF1(k) is ibuf1[k-1].  All terms are >= 0: FORTRAN's
            # truncating /4 equals floor division here.
            ival = ibuf1[il1 - 1] + ibuf1[il11 - 1] + ibuf1[il2 - 1] + ibuf1[il21 - 1] + 2
            ibuf1[iin - 1] = ival // 4
            ival = ibuf2[il1 - 1] + ibuf2[il11 - 1] + ibuf2[il2 - 1] + ibuf2[il21 - 1] + 2
            ibuf2[iin - 1] = ival // 4
        inyb = 120 + iny
        inyt = 119 - iny
        ict.wvblk(ibuf1, inx, inxl, inyb, 1)
        ict.wvblk(ibuf2, inx, inxl, inyt, 1)
    # Put a black box around it.
    ix1 = inx - 1
    ix2 = inx + inxl
    iny = 60
    iy1 = iny - 1
    iy2 = iny + inyl
    ict.gvect(ix1, iy1, ix1, iy2, 0)
    ict.gvect(ix1, iy1, ix2, iy1, 0)
    ict.gvect(ix1, iy2, ix2, iy2, 0)
    ict.gvect(ix2, iy1, ix2, iy2, 0)


# --- commands 4 and 5: the 128x120 picture, one word per pixel ----------------

def store_bi_frame(ict: Octek) -> bytes:
    """Command 4 (label 41): 15 chunks of 8 rows read at (96, 60+8*IYP) and
    written as 4 blocks each at block 4*IYP: the .BI file's bytes."""
    ix, ixl, iy = 96, 128, 60
    iybn, iyi = 14, 8
    disk = bytearray(0)
    for iyp in range(0, iybn + 1):                       # DO 45 IYP=0,IYBN
        iyb = iyp * 4
        iypos = 8 * iyp + iy
        ibuf = ict.rvblk(ix, ixl, iypos, iyi)
        words = ibuf[1:1 + 4 * BLOCK_WORDS]              # CALL WRBLK(1,IYB,IBUF(2),4,IER)
        chunk = np.array([_word(w) for w in words], dtype=">u2").tobytes()
        start = iyb * 512
        disk[start:start + len(chunk)] = chunk
    return bytes(disk)


def load_bi_frame(ict: Octek, data: bytes) -> None:
    """Command 5 (label 51): read 4 blocks at a time into IBUF(2) and write
    them as 8 rows at (96, 60+8*IYP).  ``data`` is a checked .BI file."""
    ix, ixl, iy = 96, 128, 60
    iybn, iyi = 14, 8
    for iyp in range(0, iybn + 1):                       # DO 55 IYP=0,IYBN
        iyb = iyp * 4
        block = np.frombuffer(data[iyb * 512:(iyb + 4) * 512], dtype=">i2")
        ibuf = np.zeros(1 + 4 * BLOCK_WORDS + 1, dtype=np.int32)   # IBUF(1026)
        ibuf[0] = ixl * iyi
        ibuf[1:1 + block.size] = block                   # CALL RDBLK(1,IYB,IBUF(2),4,IER)
        iypos = 8 * iyp + iy
        ict.wvblk(ibuf, ix, ixl, iypos, iyi)


# --- commands 10 and 11: the 256x240 picture, packed four to a word ------------

def load_vd_frame(ict: Octek, data: bytes) -> None:
    """Command 10 (label 101): clear the screen white, then unpack blocks
    0..59 (4 rows each, first pixel in the high nibble) into the picture at
    x 32; blocks 60..63 are ignored."""
    ict.pxfill(15, 0, 320, 0, 240)
    ixp, ixl, iyp, iyl = 32, 256, 0, 4
    for i in range(0, 60):                               # DO 104 I=0,59
        vfile = np.frombuffer(data[i * 512:(i + 1) * 512], dtype=">u2").astype(np.int64)
        ibuf = np.zeros(1 + 4 * BLOCK_WORDS + 1, dtype=np.int64)
        ibuf[0] = ixl * iyl
        for j in range(1, BLOCK_WORDS + 1):              # DO 103 J=1,256
            k = 4 * (j - 1) + 2
            v = int(vfile[j - 1])
            ibuf[k - 1] = (v >> 12) & 15                 # ISHFT(VFILE(J),-12) .AND. 15
            ibuf[k] = (v >> 8) & 15
            ibuf[k + 1] = (v >> 4) & 15
            ibuf[k + 2] = v & 15
        ict.wvblk(ibuf, ixp, ixl, iyp, iyl)
        iyp = iyp + iyl


def store_vd_frame(ict: Octek) -> bytes:
    """Command 11 (label 111): 64 blocks of 4 rows from x 32, packed four
    pixels to a word (first pixel in the high nibble); blocks 60..63 zero."""
    ixp, ixl, iyp, iyl = 32, 256, 0, 4
    out = bytearray()
    for i in range(0, 64):                               # DO 115 I=0,63
        ibuf = ict.rvblk(ixp, ixl, iyp, iyl)
        iyp = iyp + iyl
        vfile = [0] * BLOCK_WORDS
        for j in range(1, BLOCK_WORDS + 1):              # DO 113 J=1,256
            if i <= 59:
                k = 4 * (j - 1) + 2
                itemp1 = (int(ibuf[k - 1]) & 15) << 12
                itemp2 = (int(ibuf[k]) & 15) << 8
                itemp3 = (int(ibuf[k + 1]) & 15) << 4
                itemp4 = int(ibuf[k + 2]) & 15
                vfile[j - 1] = itemp1 | itemp2 | itemp3 | itemp4
        out += np.array(vfile, dtype=">u2").tobytes()    # CALL WRBLK(2,I,VFILE,1,IER)
    return bytes(out)


# --- command 3 -----------------------------------------------------------------

def cartoon_frame(ict: Octek, t: int, passes: str = "hv"):
    """Command 3: cartoon the condensed picture at (96, 60) in place.
    Returns the :class:`pre.cartoon.CartoonResult`."""
    from .cartoon import cartoon
    buf = ict.rvblk(BI_X, BI_W, BI_Y, BI_H)
    pic = np.asarray(buf[1:], dtype=np.uint8).reshape(BI_H, BI_W)
    result = cartoon(pic, t, passes)
    out = np.zeros(1 + BI_W * BI_H, dtype=np.int32)
    out[0] = BI_W * BI_H
    out[1:] = result.picture.reshape(-1)
    ict.wvblk(out, BI_X, BI_W, BI_Y, BI_H)
    return result


def put_vd_picture(ict: Octek, picture: np.ndarray) -> None:
    """A 240x256 picture into the frame store the way command 10 leaves it
    (used for a camera frame when a stand-in camera is given)."""
    ict.pxfill(15, 0, 320, 0, 240)
    buf = np.zeros(1 + VD_W * 240, dtype=np.int32)
    buf[0] = VD_W * 240
    buf[1:] = np.asarray(picture, dtype=np.int32).reshape(-1)
    ict.wvblk(buf, VD_X, VD_W, 0, 240)
