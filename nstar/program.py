"""NSTAR.FR — the NOVA half of the stereo system, as a state machine.

:class:`Nova` owns the OCTEK frame store and NSTAR's COMMON storage, and turns
one NCONT.DT message into its reply files (:meth:`Nova.execute`).  The file
loop in :mod:`nstar.main` and ESTAR's in-process link both call it with the
same bytes, so they cannot drift apart.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from diskfmt import layouts
from diskfmt.dgreal import Real, ZERO
from diskfmt.layouts import (BlockMap, decode_ncont, encode_wbmap, encode_block, CODE_TERMINATE, CODE_STAR,
                             CODE_SLICE, CODE_NEW_PAIR, CODE_EDGE_MAP)
from diskfmt.listing import Console, Listing, fi
from octek_sim import Octek
from diskfmt.bitmap_files import EXTENSION_CODES
from . import extensions
from .bitmaps import block_map, command_geometry, edge_map, edge_map_batch, scale_factors
from .exqvfl import exqvfl
from .printouts import prbm
from .radial import direction_cosines, ilcm, radsp

IHMIN, IHMAX = 0, 127
IVMIN, IVMAX = 0, 119
LEFT_X, RIGHT_X = 26, 166          # where label 800 loads the pair in the frame store


@dataclass
class Reply:
    """One file NSTAR publishes: written as ``temp`` then renamed to ``name``."""
    name: str
    data: bytes
    temp: str = "NDAT.DT"


@dataclass
class Options:
    """Deliberate departures from 1985, each off by default."""
    no_wrap_percent: bool = False    # command 1: compute ICNT*100 without 16-bit wrap
    bitmap_extensions: bool = False  # codes 11-13, Appendix B beyond 1985 (nstar/extensions.py)


class Nova:
    """NSTAR's state: the board, COMMON /FBUFF/ IFBUF and the /BLOB/ record."""

    def __init__(self, debug: int = 0, listing: Listing | None = None,
                 console: Console | None = None, options: Options | None = None):
        self.octek = Octek()
        self.debug = debug
        self.listing = listing or Listing()
        self.console = console or Console(quiet=True)
        self.options = options or Options()
        self.ifbuf = np.zeros(256, dtype=np.int32)      # IDIR, NFEAT, IFIRST, ILAST, IFEAT
        self.ifeat = self.ifbuf[10:210].reshape(4, 50)  # EQUIVALENCE (IFBUF(11), IFEAT(1,1))
        self.sfx: Real = ZERO                          # /BLOB/ keeps old SFX, SFY when IYL <= 1
        self.sfy: Real = ZERO
        self.ca1, self.ca2 = direction_cosines()
        self.terminated = False
        self.octek.sintro()
        self.octek.greyscale(1)
        self.octek.greyscale(2)

    # --- label 800: the picture pair -----------------------------------------
    def load_pair(self, left: np.ndarray, right: np.ndarray) -> None:
        """Label 800-856 — clear the frame store to white, load the left picture
        at x 26 and the right at x 166, rows 0..119."""
        self.octek.pxfill(15, 0, 320, 0, 240)
        for x, pic in ((LEFT_X, left), (RIGHT_X, right)):
            pic = np.asarray(pic)
            for i in range(15):                   # 15 chunks of 8 rows, as RDBLK/WVBLK
                buf = np.concatenate(([1024], pic[8 * i:8 * i + 8].reshape(-1)))
                self.octek.wvblk(buf, x, 128, 8 * i, 8)

    def picture(self, image: int) -> np.ndarray:
        """The 120x128 picture as held in the frame store (label 860 saves this)."""
        x = LEFT_X if image == 1 else RIGHT_X
        return self.octek.frame[0:120, x:x + 128].copy()

    # --- label 100: one command ----------------------------------------------
    def execute(self, ncont: bytes) -> list[Reply]:
        """Carry out one NCONT.DT; return the files to publish (none for an
        ignored code or for command 3, whose dialogue is the caller's)."""
        cmd = decode_ncont(ncont)
        code, imf, ixctr, iyctr, irad, idn = cmd.words()
        self.ifbuf[6] = imf                                  # IDIR(7)=IMF
        ixoff, ixmin, ixmax, iymin, iymax, ixctr, iyctr, ixc, iyc = (
            int(v) for v in command_geometry(imf, ixctr, iyctr))
        iyoff = 0
        if self.options.bitmap_extensions and code in EXTENSION_CODES:
            return extensions.execute(self, code, imf, cmd.words()[2], cmd.words()[3], irad, idn)
        if code < -1 or code > 4 or code == 0:
            # IF ((ICODE .LT. -1) .OR. (ICODE .GT. 4)) GOTO 100; code 0 falls
            # through the computed GOTO to GOTO 100.
            self.console.type(" Ignored command code", code)
            return []
        if code == CODE_TERMINATE:
            self.console.type("COMMAND= Terminate processing.")
            self.terminated = True
            self.octek.oremove()
            return [Reply("TERM.DT", layouts.TERM_TEXT.encode("ascii"), temp="TRM.DT")]
        if code == CODE_STAR:
            return [self._star(imf, ixctr, iyctr, ixc, iyc, irad, idn, ixoff, iyoff,
                               (ixmin, ixmax, iymin, iymax))]
        if code == CODE_SLICE:
            return [self._slice(imf, iyctr, iyoff, ixmin, ixmax)]
        if code == CODE_NEW_PAIR:
            return []
        return [self._edge(ixc, iyc, idn, (ixmin, ixmax, iymin, iymax))]

    def execute_edge_maps(self, ncont_block: bytes) -> bytes:
        """Many code-4 NCONT.DT messages, back to back (12 bytes each), carried
        out in one compiled pass; returns their WBMAP.DT replies back to back
        (34 bytes each).  Same bytes, same NSTAR state and printouts as calling
        :meth:`execute` on each — the in-process link uses it for speed."""
        words = np.frombuffer(ncont_block, dtype=">i2").reshape(-1, 6).astype(np.int64)
        if len(words) == 0 or not (words[:, 0] == CODE_EDGE_MAP).all():
            return b"".join(r.data for k in range(len(words))
                            for r in self.execute(ncont_block[12 * k:12 * k + 12]))
        out = np.zeros((len(words), 17), dtype=np.int64)
        corners = np.zeros((len(words), 2), dtype=np.int64)
        edge_map_batch(self.octek.frame, words, out, corners)
        for k in range(len(words)) if (self.debug & 16 or not self.console.quiet) else ():
            geometry = command_geometry(*words[k, 1:4])
            self.console.type(" Bit map region edge. IYC=", int(geometry[8]),
                              " IXC=", int(geometry[7]))
            if self.debug & 16:
                self.listing.records(prbm(out[k, 1:]))
        self.ifbuf[6] = words[-1, 1]                         # IDIR(7) of the last one
        ixlft, iytop = (int(v) for v in corners[-1])
        self.octek.boxcur(18, 18)
        self.octek.hctab(ixlft, 255)
        return out.astype(">i2").tobytes()

    # --- label 600 -----------------------------------------------------------
    def _slice(self, imf, iyctr, iyoff, ixmin, ixmax) -> Reply:
        """Label 600 — one epipolar slice of 128 pixels through EXQVFL (threshold 2)."""
        iy = iyctr - iyoff
        self.console.type("COMMAND = Get image slice. Image #=", imf, " Line #=", iy)
        ixl = ixmax - ixmin + 1
        ix = LEFT_X + (140 if imf == 2 else 0)     # IMF other than 1, 2: IXOFF right, IX left (N3)
        idat = self.octek.rvblk(ix, ixl, iy, 1)
        self.ifbuf[0:6] = (-1, 0, iy, ixl - 1, iy, ixl)
        self.ifbuf[8] = idat[1]                    # IFIRST=IDAT(2)
        self.ifbuf[9] = idat[ixl]                  # ILAST=IDAT(IXL1)
        nfeat, _ = exqvfl(idat[1:1 + ixl], 2, self.ifeat, ilast=ixl, warn=self.console.type)
        self.ifbuf[7] = nfeat
        # encode_slice(Slice(IFBUF)), straight from the array: block 0 zero, block 1 IFBUF
        return Reply("SLICE.DT", bytes(512) + self.ifbuf.astype(">i2").tobytes())

    # --- label 500 -----------------------------------------------------------
    def _edge(self, ixc, iyc, idn, bounds) -> Reply:
        """Label 500 — the 16x16 edge bit map around (IXC, IYC), one side of an edge."""
        self.console.type(" Bit map region edge. IYC=", iyc, " IXC=", ixc)
        ibmap, ixlft, iytop = edge_map(self.octek, ixc, iyc, idn, bounds)
        self.octek.boxcur(18, 18)
        self.octek.hctab(ixlft - 1, iytop - 1)
        if self.debug & 16:
            self.listing.records(prbm(ibmap))
        self.octek.hctab(ixlft, 255)
        return Reply("WBMAP.DT", encode_wbmap(ibmap))

    # --- labels 200-400 ------------------------------------------------------
    def _star(self, imf, ixctr, iyctr, ixc, iyc, irad, idn, ixoff, iyoff, bounds) -> Reply:
        """Labels 200-400 — the Star filter around the centre, then the region's
        scaled 16x16 block map; written as BLOCK.DT."""
        ixmin, ixmax, iymin, iymax = bounds
        self.console.type("COMMAND= Process star. IXC=", ixctr, " IYC=", iyctr, " Max RAD=", irad)
        self.octek.xhair()
        self.octek.hctab(ixc, iyc)
        icntr = [IHMAX, IHMIN, IVMAX, IVMIN, 15, 0]
        radln_bounds = (ixoff, ixmax, iyoff, iymax)  # /IMAGE/ positional: IXOFF is RADLN's IXMIN
        quadrants = ((0, +1, +1, self.ca1, self.ca2), (4, -1, +1, self.ca2, self.ca1),
                     (8, -1, -1, self.ca1, self.ca2), (12, +1, -1, self.ca2, self.ca1))
        for qoff, isx, isy, cax, cay in quadrants:
            self.ifbuf[0:3] = (qoff, ixctr, iyctr)
            self.ifbuf[5] = irad
            radsp(self.octek, isx, isy, cax, cay, icntr, self.ifbuf, radln_bounds,
                  self.debug, self.listing, self.console)
        self.console.type(" STAR Processed.")
        self.octek.hctab(ixc, 255)
        ixs, ixe = icntr[0] + ixoff, icntr[1] + ixoff
        iys, iye = icntr[2] + iyoff, icntr[3] + iyoff
        self.console.type(" Characterize block. IX=", ixs, ixe, " IY=", iys, iye)
        if self.debug & 4:
            self.listing.record(" ---ICNTR =" + "".join(fi(v, 5) for v in icntr))
        ixs, ixe = max(ixs, ixmin), min(ixe, ixmax)
        iys, iye = max(iys, iymin), min(iye, iymax)
        ixl = ixe - ixs + 1
        iyl = iye - iys + 1
        if iyl > 1:
            self.octek.bocur(ixl, iyl)
            self.octek.hctab(ixs, iys)
            self.sfx, self.sfy = scale_factors(ixl, iyl)
            if self.debug & 4:
                self.listing.record("" + "".join(
                    " LCM( 16," + fi(a, 3) + ") = " + fi(b, 5) + "   "
                    for a, b in ((ixl, ilcm(ixl, 16)), (iyl, ilcm(iyl, 16)))))
            ibmap = block_map(self.octek, ixs, iys, ixl, iyl, icntr[4], icntr[5],
                              wrap=not self.options.no_wrap_percent,
                              chatter=self.console.type if self.console.verbose else None)
            if self.debug & 8:
                self.listing.records(prbm(ibmap))
        else:
            ibmap = [0] * 16
        return Reply("BLOCK.DT", encode_block(BlockMap(idn, self.sfx, self.sfy, icntr, ibmap)))
