"""ESTAR.FR — the Eclipse half: LCLN (one epipolar line), CFEAT (get the two
slices), PNPL (write POSIT.DT), around MASL and LCSL.

:class:`Eclipse` holds ESTAR's COMMON blocks: /CALIB/ DSEP, DVIRT; /POSIT/ NP,
POS(640) (never cleared between lines, QUIRKS E8); /MATCH/; /BLOBS/ (reset
at the start of every line).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from diskfmt.dgreal import Real, ZERO
from diskfmt.layouts import (BI_COLS, Command, Positions, encode_posit, CODE_SLICE,
                             CODE_TERMINATE, POSIT_BYTES)
from diskfmt.listing import Console, Listing, fi
from nstar.printouts import prqvfl, prbm
from .lcsl import lcsl
from .masl import MatchTables, masl, Options as MaslOptions
from .printouts import RIGHT_EDGE, Debug, pmal, prfpos


@dataclass
class LineResult:
    """What one LCLN produced, for pictures and scans (not part of 1985's output)."""
    iyloc: int
    features1: list[tuple[int, int, int, int]]
    features2: list[tuple[int, int, int, int]]
    matches: dict[int, list[tuple[int, int, int, int]]]
    positions: dict[int, tuple[float, ...] | None]
    posit: bytes
    requests: int = 0
    used: dict[int, tuple[int, int, int, int]] = field(default_factory=dict)
    """For each located edge, the match entry (INDX, QUAL, LOC1, LOC2) LCSL took."""
    # Not 1985: the line's edge bit maps (IBLB1/IBLB2) and, with an improved
    # matcher (package ``matching``), its verdict per left edge.
    maps1: np.ndarray | None = None
    maps2: np.ndarray | None = None
    verdicts: list | None = None


class Eclipse:
    """ESTAR's state and its per-line routine."""

    def __init__(self, link, dsep: Real, dvirt: Real, debug: int = 0,
                 listing: Listing | None = None, console: Console | None = None,
                 options: MaslOptions | None = None, publish=None, matcher=None):
        self.link = link
        # None: the 1985 match lists go to LCSL.  A ``matching`` matcher (never
        # the default) replaces them by its verdicts.
        self.matcher = matcher
        self.dsep, self.dvirt = dsep, dvirt
        self.debug = debug
        self.listing = listing or Listing()
        self.console = console or Console(quiet=True)
        self.options = options or MaslOptions()
        self.np_ = 0
        self.pos: list[Real] = [ZERO] * 640
        self.tables = MatchTables()
        self.publish = publish            # PNPL's writer; None keeps POSIT.DT in memory
        self._posit: bytearray | None = None
        self.requests = 0

    def cfeat(self, iyloc: int):
        """CFEAT — ask NSTAR for the left then the right slice of line IYLOC and
        read them back (the first is renamed to SL.DT so the second can come)."""
        say = self.console.type
        self.link.discard_stale("SLICE.DT", say)
        self.link.cnova(Command(CODE_SLICE, 1, 0, iyloc, BI_COLS, 0))     # the whole row
        self.link.cnova(Command(CODE_SLICE, 2, 0, iyloc, BI_COLS, 0))
        sl1 = self.link.read_slice(1, iyloc, say)
        sl2 = self.link.read_slice(2, iyloc, say)
        return sl1, sl2

    def lcln(self, iyloc: int) -> LineResult:
        """LCLN — features, matches, 3-D locations and POSIT.DT for one line."""
        say = self.console.type
        for name in ("SLICE.FR", "WBMAP.DT", "BLOCK.DT"):   # "SLICE.FR": kept, QUIRKS E2
            self.link.discard_stale(name, say)
        say("Getting slices from IY = ", iyloc)
        sl1, sl2 = self.cfeat(iyloc)
        nfeat1, nfeat2 = sl1.nfeat, sl2.nfeat
        ifeat1 = _columns(sl1)
        ifeat2 = _columns(sl2)
        f1, f2 = sl1.features(), sl2.features()
        if self.debug & Debug.FEATURE_LISTS:
            self.listing.records(prqvfl(nfeat1, f1))
            self.listing.records(prqvfl(nfeat2, f2))
        iblb1 = np.zeros((100, 17), dtype=np.int64)        # flag word 1 = 0: no map yet
        iblb2 = np.zeros((100, 17), dtype=np.int64)
        say("Matching feature lists. N1 = ", nfeat1, " N2 =", nfeat2)
        counting = _CountingLink(self.link, self.debug, self.listing)
        masl(iyloc, nfeat1, ifeat1, nfeat2, ifeat2, iblb1, iblb2, self.tables, counting,
             self.debug, self.listing, self.console if self.console.verbose else None,
             self.options)
        if self.debug & Debug.BLOB_MAPS:
            self._print_maps(nfeat1, iblb1, nfeat2, iblb2)
        if self.debug & Debug.MATCH_LISTS:
            self.listing.records(pmal(nfeat1, self.tables))
        say(" Computing locations.")
        tables, verdicts = self.tables, None
        if self.matcher is not None:
            tables, verdicts = self.matcher.tables_for(self, iyloc, f1, f2, iblb1, iblb2)
        used = lcsl(iyloc, nfeat1, tables, self.pos, self.dsep, self.dvirt)
        self.np_ = nfeat1
        if self.debug & Debug.POSITIONS:
            self.listing.records(prfpos(self.np_, self.pos, self.dsep, self.dvirt))
        say(" Storing positions.")
        edges = [e for k in range(1, nfeat1 + 1) for e in (k, k + RIGHT_EDGE)]
        posit = self.pnpl(edges)
        self.requests += counting.count
        return LineResult(
            iyloc, f1, f2,
            {e: tables.entries(e) for e in edges},
            {e: (tuple(float(v) for v in self.pos[(e - 1) * 6:(e - 1) * 6 + 6])
                 if self.pos[(e - 1) * 6].m > 0 else None) for e in edges},
            posit, counting.count, used, iblb1, iblb2, verdicts)

    def pnpl(self, changed=None) -> bytes:
        """PNPL — POSIT.DT: NP and COMMON /POSIT/ cut at 5 blocks, written as
        EDAT.DT and renamed (atomically replacing the previous POSIT.DT).

        The image of COMMON /POSIT/ is kept encoded; only the entries LCSL may
        have changed (``changed`` edges; all when None) are encoded again."""
        if self._posit is None or changed is None:
            self._posit = bytearray(encode_posit(Positions(self.np_, self.pos)))
        else:
            self._posit[0:2] = self.np_.to_bytes(2, "big", signed=True)
            for e in changed:
                start = 2 + (e - 1) * 24
                self._posit[start:start + 24] = b"".join(
                    r.to_bytes() for r in self.pos[(e - 1) * 6:(e - 1) * 6 + 6])
            del self._posit[POSIT_BYTES:]
        data = bytes(self._posit)
        if self.publish is not None:
            self.publish(data)
        return data

    def terminate(self) -> None:
        """Send code -1: NSTAR writes TERM.DT and stops."""
        self.link.cnova(Command(CODE_TERMINATE, 0, 0, 0, 0, 0))

    def _print_maps(self, nfeat1, iblb1, nfeat2, iblb2) -> None:
        for nfeat, iblb in ((nfeat1, iblb1), (nfeat2, iblb2)):
            for iloc in range(1, nfeat + 1):
                self.listing.record(" MAP #" + fi(iloc, 3))
                for k in (iloc, iloc + RIGHT_EDGE):
                    if iblb[k - 1][0] == 1:
                        self.listing.records(prbm(iblb[k - 1][1:]))
                    else:
                        self.listing.record(" There is no map stored.")
                    if k == iloc:
                        self.listing.record(" ")


class _CountingLink:
    """Counts NBLOB round trips (for benchmarks) and prints received maps on
    debug flag 16 (NBLOB is not listed; QUIRKS E11)."""

    def __init__(self, link, debug, listing):
        self.link, self.debug, self.listing = link, debug, listing
        self.count = 0

    def nblob_many(self, requests, iyloc, iblb1, iblb2):
        self.count += len(requests)
        self.link.nblob_many(requests, iyloc, iblb1, iblb2)
        if self.debug & Debug.BIT_MAPS:
            for image, edge, _, _ in requests:
                self.listing.records(prbm((iblb1 if image == 1 else iblb2)[edge - 1][1:]))


def _real(value) -> Real:
    return value if isinstance(value, Real) else Real.const(str(value))


def in_process_rig(left, right, dsep="0.75", dvirt="180", *, debug: int = 0,
                   listing: Listing | None = None, console: Console | None = None,
                   options: MaslOptions | None = None, nova=None, matcher=None) -> Eclipse:
    """The one constructor of the in-process rig: an NSTAR (:class:`nstar.program.Nova`)
    holding the 120x128 pictures ``left``/``right``, the same bytes handed to it
    through :class:`estar.link.DirectLink`, and an ESTAR on top.  ``dsep``/``dvirt``
    are REALs or decimal text; POSIT.DT stays in memory.  ``eclipse.link.nova``
    is the NSTAR (pass ``nova`` to use one already set up); ``matcher``: an
    improved matcher of package ``matching`` (None: the 1985 match lists)."""
    from nstar.program import Nova
    from .link import DirectLink
    if nova is None:
        nova = Nova()
        nova.load_pair(left, right)
    return Eclipse(DirectLink(nova), _real(dsep), _real(dvirt), debug, listing, console,
                   options, matcher=matcher)


def file_link_estar(link, dsep="0.75", dvirt="180", *, debug: int = 0,
                    listing: Listing | None = None, console: Console | None = None,
                    options: MaslOptions | None = None, matcher=None) -> Eclipse:
    """The one constructor of an ESTAR on a started :class:`estar.link.FileLink`
    (see :func:`estar.link.start_file_link`): PNPL publishes POSIT.DT in JHDATA."""
    return Eclipse(link, _real(dsep), _real(dvirt), debug, listing, console, options,
                   publish=link.publish_posit, matcher=matcher)


def _columns(sl) -> list[list[int]]:
    """IFEAT(50,4) of a slice as four 50-word columns."""
    return [sl.ifbuf[10 + 50 * j:60 + 50 * j] for j in range(4)]
