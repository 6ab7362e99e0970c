"""The 1985 rig's line loop as one compiled pass over a frame.

Per line, what ESTAR's LCLN does through the NOVA (estar/program.py), with
the same routines in the same order:

* CFEAT: NSTAR label 600's slices of both pictures through EXQVFL
  (:func:`eyes.exqvfl.exqvfl_fast`, the same lists as
  :func:`nstar.exqvfl.exqvfl_kernel` with its labels as loops; threshold 2);
* NBLOB: NSTAR label 500's edge bit map (:func:`nstar.bitmaps.edge_map_kernel`
  after label 100's :func:`~nstar.bitmaps.command_geometry`) of every edge
  MARF will compare on this line, each once, as MARF's cache does;
* MASL with MARF inlined (:func:`marf_best_shift`), inserting into COMMON
  /MATCH/ (which persists across lines as in 1985) as
  :func:`estar.masl._insert_kernel` does;
* LCSL in DG truncating arithmetic on integers (:mod:`eyes.dgint`), its terms
  memoised in tables: they depend only on the disparity and one offset;
* PNPL: COMMON /POSIT/ kept as its 640 storage words; the POSIT.DT image of a
  line is NP and those words.

No Python object is made per line or per feature.  ``tests/test_eyes.py``
compares every output with the reference path (Eclipse + DirectLink + Nova)."""

from __future__ import annotations

import numpy as np

from diskfmt.jit import jit
from estar.masl import NPIX1, NPIX2, masl_requests
try:                                   # MASL's shift bounds (named search_bounds since)
    from estar.masl import search_bounds as _search_bounds_kernel
except ImportError:                    # pragma: no cover - the older name
    from estar.masl import _search_bounds_kernel
from .exqvfl import exqvfl_fast
from .dgint import dg_add, dg_div, dg_from_int, dg_gt, dg_mul, dg_word

LEFT_X, RIGHT_X = 26, 166          # nstar.program: where label 800 loads the pair
SLICE_THRESHOLD = 2                # NSTAR label 600: EXQVFL(..., ITHR=2)
MAX_DISP = 256                     # LOC1 <= 128 and LOC2 >= 1 - 64 (MARF moves it by <= 64)
OFFSET0 = 64                       # table index of offset 0 (offsets -60..68 occur)
NOFFSETS = 192
# Columns of a point row.
P_LINE, P_EDGE, P_LOC1, P_LOC2, P_INDX, P_QUAL = range(6)


def new_tables() -> dict[str, np.ndarray]:
    """Empty memo tables of LCSL's terms (filled on first use, per calibration)."""
    return {"range_done": np.zeros(MAX_DISP, dtype=np.bool_),
            # dp m,q; ep m,q; their storage words
            "range_mq": np.zeros((MAX_DISP, 6), dtype=np.int64),
            # [disparity, offset]: the storage words of the value and the error
            # (16 bytes an entry, a line's neighbouring edges close together)
            "offset_done": np.zeros((MAX_DISP, NOFFSETS), dtype=np.bool_),
            "offset_words": np.zeros((MAX_DISP, NOFFSETS, 2), dtype=np.int64)}


def build_frame(left, right, out: np.ndarray | None = None) -> np.ndarray:
    """The OCTEK frame store after NSTAR label 800: white (15) everywhere, the
    left picture at x 26 and the right at x 166, rows 0..119, low 4 bits.
    ``out``: a frame store this function made before, refilled in place (only
    the two pictures' places change)."""
    frame = np.full((240, 320), 15, dtype=np.uint8) if out is None else out
    for x0, pic in ((LEFT_X, left), (RIGHT_X, right)):
        pic = np.asarray(pic)
        place = frame[0:120, x0:x0 + 128]
        if pic.dtype.kind in "iub":            # integers: the low 4 bits, no copy
            np.bitwise_and(pic, 15, out=place, casting="unsafe")
        else:                                  # as int(): truncated toward zero
            place[:] = pic.astype(np.int64) & 15
    return frame


U16 = np.uint64(16)


@jit
def popcount64(x):
    x = x - ((x >> np.uint64(1)) & np.uint64(0x5555555555555555))
    x = (x & np.uint64(0x3333333333333333)) + ((x >> np.uint64(2)) & np.uint64(0x3333333333333333))
    x = (x + (x >> np.uint64(4))) & np.uint64(0x0F0F0F0F0F0F0F0F)
    return np.int64((x * np.uint64(0x0101010101010101)) >> np.uint64(56))


WINDOW_PAD = 8                     # zero columns either side: a map never leaves the array
WINDOWS_SHAPE = (2, 4, 17, 128 + 2 * WINDOW_PAD)


def new_windows() -> np.ndarray:
    """Work space for :func:`level_windows`."""
    return np.zeros(WINDOWS_SHAPE, dtype=np.uint64)


@jit
def level_windows(frame, windows):
    """For each picture (0 left, 1 right), grey level g and column x, the rows
    0..119 whose pixel is at most g, as four overlapping 64-row windows:
    bit b of ``windows[i, q, g+1, WINDOW_PAD + x]`` is row 32q+b
    (``windows[i, q, 0]`` is empty).  NSTAR label 500 sets a bit when the
    pixel lies in IGMN..IGMX: ``windows[.., IGMX+1, x] & ~windows[.., IGMN, x]``;
    any 16 rows from row ``top`` >= 0 lie in window ``top >> 5``, so an edge
    map's column is one load and one shift per level, and its 16 columns are
    side by side.  A column's rows are gathered by level in two words (rows
    0..63, 64..127), then each window word is written once; only the
    pictures' columns are written, so the pad columns stay empty as
    :func:`new_windows` made them."""
    one = np.uint64(1)
    m32 = np.uint64(32)
    by_level = np.zeros((17, 2), dtype=np.uint64)   # one column: rows whose pixel is g-1
    for i in range(2):
        x0 = 26 + 140 * i
        for x in range(128):
            by_level[:] = 0
            for r in range(64):
                by_level[frame[r, x0 + x] + 1, 0] |= one << np.uint64(r)
            for r in range(64, 120):
                by_level[frame[r, x0 + x] + 1, 1] |= one << np.uint64(r - 64)
            lo = np.uint64(0)                       # rows 0..63 at most level g-1
            hi = np.uint64(0)                       # rows 64..127
            for g in range(17):
                lo |= by_level[g, 0]
                hi |= by_level[g, 1]
                windows[i, 0, g, WINDOW_PAD + x] = lo
                windows[i, 1, g, WINDOW_PAD + x] = (lo >> m32) | (hi << m32)
                windows[i, 2, g, WINDOW_PAD + x] = hi
                windows[i, 3, g, WINDOW_PAD + x] = hi >> m32


@jit
def nblob_many(frame, windows, iyloc, requests, count, maps, bits, grey):
    """NBLOB(IMAGE, X, IYLOC, IES) for the first ``count`` rows (image, edge,
    X, IES) of ``requests`` (:func:`estar.masl.masl_requests`' rows): NSTAR
    label 100's geometry and label 500's edge bit map
    (:func:`nstar.bitmaps.edge_map_kernel`), from the level windows
    (:func:`level_windows`).  Map ``maps[image-1, edge-1]`` gets the 16
    column words, four to a 64-bit word, column 1 lowest, and
    ``bits[image-1, edge-1]`` its number of set bits (MARF's totals).
    RVBLK's grey range (3 rows from IYC, 2 columns from IXM) is read from
    ``grey`` (work space, (2, 320) uint8), filled once a line for every
    frame-store column: ``grey[0, x]`` the least and ``grey[1, x]`` the
    greatest pixel of rows IYC..IYC+2, columns x and x+1.  (Written out in
    one loop: a helper taking arrays would cost a reference count per
    call.)"""
    columns = maps.view(np.uint16)                 # [image, edge, column]: little-endian limbs
    iyc = min(max(iyloc, 0), 119)                  # command_geometry's clamps
    top = iyc - 7                                  # map rows top..top+15
    q = max(top, 0) >> 5
    down = np.uint64(max(top, 0) - 32 * q)
    up = np.uint64(max(-top, 0))                   # rows above row 0 stay 0
    if count == 0:
        return
    for x in range(319):                           # RVBLK(ICT,IDAT,IXM,2,IYC,3) for every IXM
        a = min(min(frame[iyc, x], frame[iyc + 1, x]), frame[iyc + 2, x])
        b = min(min(frame[iyc, x + 1], frame[iyc + 1, x + 1]), frame[iyc + 2, x + 1])
        grey[0, x] = min(a, b)
        a = max(max(frame[iyc, x], frame[iyc + 1, x]), frame[iyc + 2, x])
        b = max(max(frame[iyc, x + 1], frame[iyc + 1, x + 1]), frame[iyc + 2, x + 1])
        grey[1, x] = max(a, b)
    for k in range(count):
        image = requests[k, 0]
        row = requests[k, 1] - 1
        ies = requests[k, 3]
        ixctr = min(max(requests[k, 2], 0), 127)
        ixc = ixctr + (26 if image == 1 else 166)
        ixm = min(ixc, ixc + ies + ies)
        igmn = np.int64(grey[0, ixm])
        igmx = np.int64(grey[1, ixm])
        img = image - 1
        x0 = ixctr - 7 + WINDOW_PAD                # picture column ixctr-7 (outside: empty)
        for c in range(16):
            columns[img, row, c] = np.uint16(((windows[img, q, igmx + 1, x0 + c]
                                               & ~windows[img, q, igmn, x0 + c]) >> down) << up)
        bits[img, row] = (popcount64(maps[img, row, 0]) + popcount64(maps[img, row, 1])
                          + popcount64(maps[img, row, 2]) + popcount64(maps[img, row, 3]))


@jit
def _pick(a0, a1, a2, a3, j):
    if j == 0:
        return a0
    if j == 1:
        return a1
    if j == 2:
        return a2
    if j == 3:
        return a3
    return np.uint64(0)


@jit
def _down(a0, a1, a2, a3, s):
    """A 256-bit map moved down ``s`` columns (column s becomes column 0)."""
    q = s >> 2
    r = np.uint64(16 * (s & 3))
    if r == 0:
        return (_pick(a0, a1, a2, a3, q), _pick(a0, a1, a2, a3, q + 1),
                _pick(a0, a1, a2, a3, q + 2), _pick(a0, a1, a2, a3, q + 3))
    rr = np.uint64(64) - r
    x0 = _pick(a0, a1, a2, a3, q)
    x1 = _pick(a0, a1, a2, a3, q + 1)
    x2 = _pick(a0, a1, a2, a3, q + 2)
    x3 = _pick(a0, a1, a2, a3, q + 3)
    return ((x0 >> r) | (x1 << rr), (x1 >> r) | (x2 << rr), (x2 >> r) | (x3 << rr), x3 >> r)


@jit
def _mask(k, i):
    """Limb ``i`` of the mask of the first ``k`` columns."""
    n = k - 4 * i
    if n >= 4:
        return np.uint64(0xFFFFFFFFFFFFFFFF)
    if n <= 0:
        return np.uint64(0)
    return (np.uint64(1) << np.uint64(16 * n)) - np.uint64(1)


@jit
def marf_best_shift(a0, a1, a2, a3, b0, b1, b2, b3, iwst):
    """MARF labels 70-200 (as :func:`estar.masl.marf_kernel`) on map 1 (limbs
    ``a``) and map 2 (limbs ``b``): the best shift in -IWST..IWST and its
    quality (ND*256)/NTOT, 256 without bits or when ND >= 128; ties go to the
    shift nearest zero, the earlier when equally near.  For IPOS >= 0 map-1
    column c+IPOS meets map-2 column c for c < 16-IPOS (else map-1 c meets
    map-2 c+|IPOS|): with the maps as 256-bit words, one shift, one mask and
    three bit counts."""
    mnval = 256
    mloc = 0
    for ipos in range(-iwst, iwst + 1):
        ioff = abs(ipos)
        inum = 16 - ioff
        ival = 256
        if inum > 0:
            if ipos < 0:
                x0, x1, x2, x3 = (a0 & _mask(inum, 0), a1 & _mask(inum, 1),
                                  a2 & _mask(inum, 2), a3 & _mask(inum, 3))
                y0, y1, y2, y3 = _down(b0, b1, b2, b3, ioff)
            else:
                x0, x1, x2, x3 = _down(a0, a1, a2, a3, ioff)
                y0, y1, y2, y3 = (b0 & _mask(inum, 0), b1 & _mask(inum, 1),
                                  b2 & _mask(inum, 2), b3 & _mask(inum, 3))
            ntot = (popcount64(x0) + popcount64(x1) + popcount64(x2) + popcount64(x3)
                    + popcount64(y0) + popcount64(y1) + popcount64(y2) + popcount64(y3))
            nd = (popcount64(x0 ^ y0) + popcount64(x1 ^ y1) + popcount64(x2 ^ y2)
                  + popcount64(x3 ^ y3))
            if ntot != 0 and nd < 128:               # ND*256 would overflow 16 bits
                ival = (nd * 256) // ntot
        if mnval < ival:
            continue
        if mnval == ival and abs(mloc) <= abs(ipos):
            continue
        mnval = ival
        mloc = ipos
    return mloc, mnval


@jit
def _quality(nd, ntot):
    """(ND*256)/NTOT for 0 <= ND < 128, 0 < NTOT <= 512, through a double: the
    quotient's distance from the next integer is at least 1/NTOT, far above
    the double's rounding, so its floor is the integer quotient (and a float
    division is several times quicker than a 64-bit integer one)."""
    return np.int64(np.float64(nd * 256) / np.float64(ntot))


@jit
def marf_no_shift(a0, a1, a2, a3, ta, b0, b1, b2, b3, tb):
    """MARF's MNVAL when IWST = 0 (its only shift is 0, so MLOC = 0), given
    each map's bit count: the stepped MARF's first comparison alone, without
    setting up its registers."""
    ntot = ta + tb
    nd = (popcount64(a0 ^ b0) + popcount64(a1 ^ b1) + popcount64(a2 ^ b2)
          + popcount64(a3 ^ b3))
    if ntot != 0 and nd < 128:
        return _quality(nd, ntot)
    return 256


@jit
def marf_best_shift_stepwise(a0, a1, a2, a3, b0, b1, b2, b3, iwst):
    """:func:`marf_best_shift`, the same (MLOC, MNVAL), with the shifts stepped
    one column at a time instead of computed afresh: shift k and -k from
    registers moved 16 bits per step, the bit totals kept by taking off the
    one column that leaves, and the division done only for a new best.

    MARF visits -IWST..IWST and keeps a shift when its quality is lower, or
    equal and strictly nearer zero; so the winner is the least (quality,
    |IPOS|, IPOS), and visiting 0, -1, 1, -2, 2, ... a later shift wins only
    when strictly lower: floor(ND*256/NTOT) < MNVAL exactly when
    ND*256 < MNVAL*NTOT, tested without dividing."""
    ta = popcount64(a0) + popcount64(a1) + popcount64(a2) + popcount64(a3)
    tb = popcount64(b0) + popcount64(b1) + popcount64(b2) + popcount64(b3)
    return marf_stepwise_counted(a0, a1, a2, a3, ta, b0, b1, b2, b3, tb, iwst)


@jit
def marf_stepwise_counted(a0, a1, a2, a3, ta, b0, b1, b2, b3, tb, iwst):
    """:func:`marf_best_shift_stepwise` given each map's bit count (``ta``,
    ``tb``), which the frame scan keeps with the map."""
    m16 = np.uint64(16)
    m48 = np.uint64(48)
    lo16 = np.uint64(0xFFFF)
    mnval = 256
    mloc = 0
    ntot = ta + tb
    nd = (popcount64(a0 ^ b0) + popcount64(a1 ^ b1) + popcount64(a2 ^ b2)
          + popcount64(a3 ^ b3))
    if ntot != 0 and nd < 128:
        mnval = _quality(nd, ntot)
    # registers: a and b moved down k columns (da, db); a and b with their top
    # k columns cleared (ka, kb); a and b moved up k-1 columns (ua, ub), whose
    # top column is the one that leaves at step k
    da0, da1, da2, da3 = a0, a1, a2, a3
    db0, db1, db2, db3 = b0, b1, b2, b3
    ones = np.uint64(0xFFFFFFFFFFFFFFFF)
    mk0, mk1, mk2, mk3 = ones, ones, ones, ones
    ua3 = a3
    ub3 = b3
    ua0, ua1, ua2 = a0, a1, a2
    ub0, ub1, ub2 = b0, b1, b2
    n_da = ta                                  # bits of da
    n_db = tb
    n_ka = ta                                  # bits of ka
    n_kb = tb
    for k in range(1, min(iwst, 15) + 1):
        # columns leaving: the low column of da/db, the top column of ka/kb
        n_da -= popcount64(da0 & lo16)
        n_db -= popcount64(db0 & lo16)
        n_ka -= popcount64(ua3 >> m48)
        n_kb -= popcount64(ub3 >> m48)
        da0 = (da0 >> m16) | (da1 << m48)
        da1 = (da1 >> m16) | (da2 << m48)
        da2 = (da2 >> m16) | (da3 << m48)
        da3 = da3 >> m16
        db0 = (db0 >> m16) | (db1 << m48)
        db1 = (db1 >> m16) | (db2 << m48)
        db2 = (db2 >> m16) | (db3 << m48)
        db3 = db3 >> m16
        ua3 = (ua3 << m16) | (ua2 >> m48)
        ua2 = (ua2 << m16) | (ua1 >> m48)
        ua1 = (ua1 << m16) | (ua0 >> m48)
        ua0 = ua0 << m16
        ub3 = (ub3 << m16) | (ub2 >> m48)
        ub2 = (ub2 << m16) | (ub1 >> m48)
        ub1 = (ub1 << m16) | (ub0 >> m48)
        ub0 = ub0 << m16
        mk0 = (mk0 >> m16) | (mk1 << m48)      # the first 16-k columns
        mk1 = (mk1 >> m16) | (mk2 << m48)
        mk2 = (mk2 >> m16) | (mk3 << m48)
        mk3 = mk3 >> m16
        ka0, ka1, ka2, ka3 = a0 & mk0, a1 & mk1, a2 & mk2, a3 & mk3
        kb0, kb1, kb2, kb3 = b0 & mk0, b1 & mk1, b2 & mk2, b3 & mk3
        # IPOS = -k: map 1 column c meets map 2 column c + k
        ntot = n_ka + n_db
        nd = (popcount64(ka0 ^ db0) + popcount64(ka1 ^ db1) + popcount64(ka2 ^ db2)
              + popcount64(ka3 ^ db3))
        if ntot != 0 and nd < 128 and nd * 256 < mnval * ntot:
            mnval = _quality(nd, ntot)
            mloc = -k
        # IPOS = k: map 1 column c + k meets map 2 column c
        ntot = n_da + n_kb
        nd = (popcount64(da0 ^ kb0) + popcount64(da1 ^ kb1) + popcount64(da2 ^ kb2)
              + popcount64(da3 ^ kb3))
        if ntot != 0 and nd < 128 and nd * 256 < mnval * ntot:
            mnval = _quality(nd, ntot)
            mloc = k
    return mloc, mnval


@jit
def lcsl_range(disp, consts, tables_done, tables):
    """DP=DCONS/DISP; DENOM=DISP*DISP-DISP*EDISP; EPMAX=DCONS*EDISP/DENOM,
    into row ``disp`` of the memo table (once)."""
    if not tables_done[disp]:
        dcm, dcq, _, _, edm, edq, _, _ = consts
        dm, dq = dg_from_int(disp)
        am, aq = dg_mul(dm, dq, dm, dq)
        bm, bq = dg_mul(dm, dq, edm, edq)
        denm, denq = dg_add(am, aq, -bm, bq)
        dpm, dpq = dg_div(dcm, dcq, dm, dq)
        nm, nq = dg_mul(dcm, dcq, edm, edq)
        epm, epq = dg_div(nm, nq, denm, denq)
        tables[disp, 0] = dpm
        tables[disp, 1] = dpq
        tables[disp, 2] = epm
        tables[disp, 3] = epq
        tables[disp, 4] = dg_word(dpm, dpq)
        tables[disp, 5] = dg_word(epm, epq)
        tables_done[disp] = True


@jit
def lcsl_offset(offset, disp, dpm, dpq, epm, epq, consts, done, tables):
    """DX=DL*DP*DVI; EXMAX=(ABS(DL)*EPMAX+DP*ELMAX+EPMAX*ELMAX)*DVI, left to
    right (the same for DY, EYMAX with DD and EDMAX = ELMAX), their storage
    words into the memo table (once)."""
    k = offset + OFFSET0
    if not done[disp, k]:
        _, _, dvm, dvq, _, _, emm, emq = consts
        om, oq = dg_from_int(offset)
        am, aq = dg_mul(om, oq, dpm, dpq)
        vm, vq = dg_mul(am, aq, dvm, dvq)
        um, uq = dg_from_int(abs(offset))
        sm, sq = dg_mul(um, uq, epm, epq)
        tm, tq = dg_mul(dpm, dpq, emm, emq)
        sm, sq = dg_add(sm, sq, tm, tq)
        tm, tq = dg_mul(epm, epq, emm, emq)
        sm, sq = dg_add(sm, sq, tm, tq)
        em, eq = dg_mul(sm, sq, dvm, dvq)
        tables[disp, k, 0] = dg_word(vm, vq)
        tables[disp, k, 1] = dg_word(em, eq)
        done[disp, k] = True


@jit
def cfeat(frame, iyloc, pix, ifeat1, ifeat2, work):
    """CFEAT: NSTAR label 600's slice of line IYLOC of image 1, then image 2,
    through EXQVFL (threshold 2); ``work``: :func:`eyes.exqvfl.new_work`.
    Returns (NFEAT1, NFEAT2)."""
    for c in range(128):
        pix[c] = frame[iyloc, LEFT_X + c]
    nfeat1, _ = exqvfl_fast(pix, 128, SLICE_THRESHOLD, ifeat1, work)
    for c in range(128):
        pix[c] = frame[iyloc, RIGHT_X + c]
    nfeat2, _ = exqvfl_fast(pix, 128, SLICE_THRESHOLD, ifeat2, work)
    return nfeat1, nfeat2


@jit
def masl_line(frame, windows, iyloc, nfeat1, ifeat1, nfeat2, ifeat2, sign_fix, nmatch, imatch,
              maps, bits, requests, partners, bounds, kept, grey):
    """MASL for one line (IBLB1/IBLB2 empty at its start).  MASL tries every
    slice-2 feature JNDX for every slice-1 feature INDX, both sides, and
    compares the pairs whose grey levels differ by at most 1; a side's match
    list only depends on the order of JNDX within that side, so here each
    side visits just its partners, in increasing JNDX, from a bit set per
    grey level.  NBLOB's round trips are counted as MASL makes them (every
    edge with a partner, :func:`estar.masl.masl_requests`), but a map is only
    made when a pair will compare it (the maps depend only on the pictures),
    then each pair goes through MARF (:func:`marf_best_shift`) into COMMON
    /MATCH/.  Work space: ``partners`` (2, 18), ``bounds`` (2, 50, 2) (IRGD
    of slice 1, then slice 2), ``kept`` (2, 50), ``grey`` (2, 320) uint8
    (:func:`nblob_many`'s).  Returns the number of NBLOB round trips."""
    # partners[side, g + 1]: bit JNDX-1 set when slice-2 feature JNDX's grey on
    # that side is within 1 of g
    partners[:] = 0
    for side in range(2):
        for jndx in range(1, nfeat2 + 1):
            g = ifeat2[2 + side, jndx - 1]
            for d in range(3):
                partners[side, g + d] |= 1 << (jndx - 1)
    for j in range(1, nfeat2 + 1):
        b = _search_bounds_kernel(ifeat2, nfeat2, j, NPIX2)
        bounds[1, j - 1, 0] = b[0]
        bounds[1, j - 1, 1] = b[1]
    # A pair MARF can keep has X2 - IWST < X1, so X2 < X1 + IRGD (IWST <= IRGD):
    # with slice 2's edges in increasing X (EXQVFL finds them left to right;
    # checked, else no pair is passed over) those are the JNDX below a limit,
    # found by a pointer walked along slice 2 (``below``).
    ordered = True
    for j in range(1, nfeat2):
        if ifeat2[0, j] <= ifeat2[0, j - 1] or ifeat2[1, j] <= ifeat2[1, j - 1]:
            ordered = False
    nreq = 0
    nfetch = 0
    for side in range(2):
        wanted = 0                             # slice-2 partners: NBLOB's requests
        needed = 0                             # those some pair will compare
        below = 0
        for indx in range(1, nfeat1 + 1):
            if side == 0:
                b = _search_bounds_kernel(ifeat1, nfeat1, indx, NPIX1)   # QUIRKS E4
                bounds[0, indx - 1, 0] = b[0]
                bounds[0, indx - 1, 1] = b[1]
            m = partners[side, ifeat1[2 + side, indx - 1] + 1]
            x1 = ifeat1[side, indx - 1]
            if m:
                nreq += 1
                wanted |= m
                if ordered:
                    limit = x1 + bounds[0, indx - 1, side]
                    while below < nfeat2 and ifeat2[side, below] < limit:
                        below += 1
                    while below > 0 and ifeat2[side, below - 1] >= limit:
                        below -= 1
                    m &= (1 << below) - 1
            kept[side, indx - 1] = m
            if m:
                requests[nfetch, 0] = 1
                requests[nfetch, 1] = indx + 50 * side
                requests[nfetch, 2] = x1
                requests[nfetch, 3] = -1 if side == 0 else 1
                nfetch += 1
                needed |= m
        nreq += popcount64(np.uint64(wanted))
        for jndx in range(1, nfeat2 + 1):
            if needed & (1 << (jndx - 1)):
                requests[nfetch, 0] = 2
                requests[nfetch, 1] = jndx + 50 * side
                requests[nfetch, 2] = ifeat2[side, jndx - 1]
                requests[nfetch, 3] = -1 if side == 0 else 1
                nfetch += 1
    nblob_many(frame, windows, iyloc, requests, nfetch, maps, bits, grey)
    for indx in range(1, nfeat1 + 1):
        for side in range(2):
            e1 = indx + 50 * side
            row = e1 - 1
            x1 = ifeat1[side, indx - 1]
            a0 = maps[0, row, 0]
            a1 = maps[0, row, 1]
            a2 = maps[0, row, 2]
            a3 = maps[0, row, 3]
            ta = bits[0, row]
            irgd = bounds[0, indx - 1, side]
            count = 0
            m = kept[side, indx - 1]
            while m:
                low = m & -m
                m ^= low
                jndx = 1 + popcount64(np.uint64(low - 1))
                e2 = jndx + 50 * side
                x2 = ifeat2[side, jndx - 1]
                iwst = min(irgd, bounds[1, jndx - 1, side])
                if x1 <= x2 - iwst:
                    # MARF moves LOC2 by at most IWST either way: no shift can
                    # put it left of LOC1, so the pair is dropped below anyway
                    continue
                if iwst == 0:                  # most pairs (86% on the motorcycle)
                    mloc = 0
                    mnval = marf_no_shift(a0, a1, a2, a3, ta, maps[1, e2 - 1, 0],
                                          maps[1, e2 - 1, 1], maps[1, e2 - 1, 2],
                                          maps[1, e2 - 1, 3], bits[1, e2 - 1])
                else:
                    mloc, mnval = marf_stepwise_counted(a0, a1, a2, a3, ta, maps[1, e2 - 1, 0],
                                                        maps[1, e2 - 1, 1], maps[1, e2 - 1, 2],
                                                        maps[1, e2 - 1, 3], bits[1, e2 - 1],
                                                        iwst)
                loc2 = x2 - mloc if sign_fix else x2 + mloc          # QUIRKS E7
                if x1 <= loc2:
                    continue                           # LOC1 must lie right of LOC2
                # MASL labels 100-210 (600-710), as estar.masl._insert_kernel, written
                # out here: a call taking the table would cost a reference count.
                if count < 1:
                    count = 1
                    ispt = 1
                elif mnval >= imatch[row, count - 1, 1]:
                    if count >= 10:
                        continue                       # worse than a full list's bottom
                    count += 1
                    ispt = count
                else:
                    inum = count
                    if count < 10:
                        count += 1
                    ispt = 1
                    for i in range(1, inum + 1):
                        ispt = inum - i + 1
                        if ispt != 10:
                            for j in range(4):         # move the entry down
                                imatch[row, ispt, j] = imatch[row, ispt - 1, j]
                        if ispt >= 2 and mnval >= imatch[row, ispt - 2, 1]:
                            break                      # equal quality goes after (QUIRKS E19)
                        ispt = 1
                imatch[row, ispt - 1, 0] = e2
                imatch[row, ispt - 1, 1] = mnval
                imatch[row, ispt - 1, 2] = x1
                imatch[row, ispt - 1, 3] = loc2
            nmatch[row] = count
    return nreq


@jit
def match_list_rows(nfeat1, nmatch, imatch, match_rows, nrow):
    """Append the match lists of edges 1..NFEAT1, then 51..50+NFEAT1, as rows
    (edge, INDX, QUAL, LOC1, LOC2); returns the new row count."""
    for half in range(2):
        for indx in range(1, nfeat1 + 1):
            edge = indx + 50 * half
            for i in range(nmatch[edge - 1]):
                match_rows[nrow, 0] = edge
                for j in range(4):
                    match_rows[nrow, 1 + j] = imatch[edge - 1, i, j]
                nrow += 1
    return nrow


@jit
def lcsl_line(iyloc, nfeat1, nmatch, imatch, consts, range_done, range_mq, offset_done,
              offset_words, pos, point_rows, point_words, npt):
    """LCSL: for each edge the match entries with a disparity above EDISP in
    order, until one puts the range past 1.0, their six POS values from the
    memo tables as storage words in ``pos``; each located edge appended as a
    point (line, edge, then LOC1, LOC2, INDX, QUAL of the entry whose values
    ended in POS; the POS words).
    Returns the new point count, or -1 when a value does not fit a DG REAL."""
    for half in range(2):                      # edge order, as rig.scan lists points
        for indx in range(1, nfeat1 + 1):
            edge = indx + 50 * half
            base = (edge - 1) * 6
            pos[base] = 0xC1100000                  # -1.0: no data point
            dpm = -1
            dpq = 0
            used = -1
            for i in range(nmatch[edge - 1]):
                loc1 = imatch[edge - 1, i, 2]
                disp = loc1 - imatch[edge - 1, i, 3]
                if disp <= 1:                       # IF (EDISP .GE. DISP1)
                    continue
                used = i                            # the entry whose values are in POS
                if not range_done[disp]:
                    lcsl_range(disp, consts, range_done, range_mq)
                dpm = range_mq[disp, 0]
                dpq = range_mq[disp, 1]
                epm = range_mq[disp, 2]
                epq = range_mq[disp, 3]
                kx = loc1 - 60 + OFFSET0
                ky = iyloc - 60 + OFFSET0
                if not offset_done[disp, kx]:
                    lcsl_offset(loc1 - 60, disp, dpm, dpq, epm, epq, consts, offset_done,
                                offset_words)
                if not offset_done[disp, ky]:
                    lcsl_offset(iyloc - 60, disp, dpm, dpq, epm, epq, consts, offset_done,
                                offset_words)
                pos[base] = range_mq[disp, 4]
                pos[base + 1] = offset_words[disp, kx, 0]
                pos[base + 2] = offset_words[disp, ky, 0]
                pos[base + 3] = range_mq[disp, 5]
                pos[base + 4] = offset_words[disp, kx, 1]
                pos[base + 5] = offset_words[disp, ky, 1]
                for j in range(6):
                    if pos[base + j] < 0:
                        return -1
                if dg_gt(dpm, dpq, 0x100000, -20):  # IF (POS(1,INDX) .GT. 1.0)
                    break
            if dpm > 0:
                point_rows[npt, P_LINE] = iyloc
                point_rows[npt, P_EDGE] = edge
                point_rows[npt, P_LOC1] = imatch[edge - 1, used, 2]
                point_rows[npt, P_LOC2] = imatch[edge - 1, used, 3]
                point_rows[npt, P_INDX] = imatch[edge - 1, used, 0]
                point_rows[npt, P_QUAL] = imatch[edge - 1, used, 1]
                for j in range(6):
                    point_words[npt, j] = pos[base + j]
                npt += 1
    return npt


@jit
def frame_lines_kernel(frame, windows, nfeat_out, ifeat_out, maps_out, requests_out):
    """What the improved matcher asks NSTAR for, for every line 0..119 of the
    frame store (:func:`matching.mode.fetch_line`): CFEAT's two slices
    (``nfeat_out[y]``, ``ifeat_out[y]``) and the edge bit map of every NBLOB
    request MASL makes on the line with no map cached
    (:func:`estar.masl.masl_requests`; ``requests_out[y]`` of them), as
    IBLB1/IBLB2 hold it: ``maps_out[y, image-1, edge-1]`` is flag word 1 then
    the 16 column words as the Nova's signed 16-bit words, the other edges
    all 0.  ``windows``: :func:`new_windows`."""
    level_windows(frame, windows)
    ifeat1 = np.zeros((4, 50), dtype=np.int32)
    ifeat2 = np.zeros((4, 50), dtype=np.int32)
    pix = np.zeros(128, dtype=np.int64)
    work = np.zeros((3, 130), dtype=np.int64)      # eyes.exqvfl.new_work()
    maps = np.zeros((2, 100, 4), dtype=np.uint64)
    bits = np.zeros((2, 100), dtype=np.int64)
    requests = np.zeros((200, 4), dtype=np.int64)
    have1 = np.zeros(100, dtype=np.bool_)
    have2 = np.zeros(100, dtype=np.bool_)
    grey = np.zeros((2, 320), dtype=np.uint8)
    columns = maps.view(np.uint16)                 # [image, edge, column]: as nblob_many
    maps_out[:] = 0
    for y in range(120):
        nfeat1, nfeat2 = cfeat(frame, y, pix, ifeat1, ifeat2, work)
        nfeat_out[y, 0] = nfeat1
        nfeat_out[y, 1] = nfeat2
        ifeat_out[y, 0] = ifeat1
        ifeat_out[y, 1] = ifeat2
        have1[:] = False
        have2[:] = False
        n = masl_requests(nfeat1, ifeat1, nfeat2, ifeat2, have1, have2, requests)
        requests_out[y] = n
        nblob_many(frame, windows, y, requests, n, maps, bits, grey)
        for k in range(n):
            img = requests[k, 0] - 1
            row = requests[k, 1] - 1
            maps_out[y, img, row, 0] = 1
            for c in range(16):
                word = np.int64(columns[img, row, c])
                maps_out[y, img, row, 1 + c] = word - 65536 if word >= 32768 else word


@jit
def scan_frame_kernel(frame, windows, lines, sign_fix, consts, range_done, range_mq,
                      offset_done, offset_words, nmatch, imatch, pos, nfeat_out, ifeat_out,
                      requests_out,
                      match_start, match_rows, point_start, point_rows, point_words,
                      posit_out):
    """LCLN for each line of ``lines`` on the frame store ``frame``: CFEAT,
    MASL, LCSL, PNPL.  ``windows``: :func:`new_windows`, work space kept by
    the caller (its pad columns are never written, so it needs no clearing).

    State carried from line to line, as in ESTAR's COMMON: ``nmatch``,
    ``imatch`` (/MATCH/) and ``pos`` (/POSIT/ as 640 storage words).
    Per line k: ``nfeat_out[k]``/``ifeat_out[k]`` the two slices' feature
    tables; ``requests_out[k]`` NBLOB round trips; match-list rows
    ``match_rows[match_start[k]:match_start[k+1]]`` = (edge, INDX, QUAL, LOC1,
    LOC2) for edges 1..NFEAT1 then 51..50+NFEAT1; located edges
    ``point_rows[point_start[k]:point_start[k+1]]`` = (line, edge, LOC1, LOC2,
    INDX, QUAL of the entry LCSL took) with their six POS words; ``posit_out[k]``
    the 640 POS words after the line (when ``posit_out`` has a row per line).
    Returns 0, or -1 when a POS value does not fit a DG REAL."""
    ifeat1 = np.zeros((4, 50), dtype=np.int32)
    ifeat2 = np.zeros((4, 50), dtype=np.int32)
    pix = np.zeros(128, dtype=np.int64)
    work = np.zeros((3, 130), dtype=np.int64)      # eyes.exqvfl.new_work()
    level_windows(frame, windows)
    maps = np.zeros((2, 100, 4), dtype=np.uint64)
    bits = np.zeros((2, 100), dtype=np.int64)
    requests = np.zeros((200, 4), dtype=np.int64)
    partners = np.zeros((2, 18), dtype=np.int64)
    bounds = np.zeros((2, 50, 2), dtype=np.int64)
    kept = np.zeros((2, 50), dtype=np.int64)
    grey = np.zeros((2, 320), dtype=np.uint8)
    nrow = 0
    npt = 0
    record_posit = posit_out.shape[0] == lines.shape[0]
    for k in range(lines.shape[0]):
        iyloc = lines[k]
        nfeat1, nfeat2 = cfeat(frame, iyloc, pix, ifeat1, ifeat2, work)
        nfeat_out[k, 0] = nfeat1
        nfeat_out[k, 1] = nfeat2
        ifeat_out[k, 0] = ifeat1
        ifeat_out[k, 1] = ifeat2
        requests_out[k] = masl_line(frame, windows, iyloc, nfeat1, ifeat1, nfeat2, ifeat2,
                                    sign_fix, nmatch, imatch, maps, bits, requests, partners,
                                    bounds, kept, grey)
        match_start[k] = nrow
        point_start[k] = npt
        nrow = match_list_rows(nfeat1, nmatch, imatch, match_rows, nrow)
        npt = lcsl_line(iyloc, nfeat1, nmatch, imatch, consts, range_done, range_mq,
                        offset_done, offset_words, pos, point_rows, point_words, npt)
        if npt < 0:
            return -1
        if record_posit:                        # PNPL: the image of /POSIT/ after the line
            posit_out[k] = pos
    match_start[lines.shape[0]] = nrow
    point_start[lines.shape[0]] = npt
    return 0
