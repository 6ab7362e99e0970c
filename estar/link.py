"""ESTAR's side of the NOVA link: CNOVA, NWAIT and NBLOB (called in the listing,
not listed; RIG-NOTES §2), behind one interface with two implementations:

* :class:`FileLink` — the 1985 way: NCONT.DT out, SLICE.DT / WBMAP.DT back,
  through the shared JHDATA directory, to an ``nstar`` running elsewhere;
* :class:`DirectLink` — the same message bytes handed to an in-process
  :class:`nstar.program.Nova` (for fast whole-picture scans).
"""

from __future__ import annotations

from collections import defaultdict, deque

import numpy as np

from diskfmt.layouts import (Command, encode_ncont, decode_wbmap, decode_slice, Slice,
                             CODE_EDGE_MAP, FormatError)
from diskfmt.rdos import JHData

_READERS = {"SLICE.DT": decode_slice, "WBMAP.DT": decode_wbmap}

ESTAR_STALE = ("NCONT.DT", "ECONT.DT", "SLICE.DT", "SL.DT", "WBMAP.DT", "BLOCK.DT", "EDAT.DT")


class Link:
    """What ESTAR needs from the NOVA."""

    def cnova(self, cmd: Command) -> None:
        """CNOVA — send one command."""
        raise NotImplementedError

    def nwait(self, name: str) -> bytes:
        """NWAIT + OPEN/READ/CLOSE/DELETE — the next ``name`` file's bytes."""
        raise NotImplementedError

    def discard_stale(self, name: str, say) -> None:
        """LCLN/CFEAT's DELETE of a result file left from earlier work."""

    def nblob(self, image: int, x: int, y: int, ies: int, ibm: list[int]) -> None:
        """NBLOB(IMAGE, X, Y, IES, IBM) — ask for the edge bit map of one side of an
        edge (code 4; the "max number" word is 0) and store WBMAP.DT's 17 words in
        IBM (word 1 = 1 marks "map present")."""
        self.cnova(Command(CODE_EDGE_MAP, image, x, y, 0, ies))
        ibm[:] = decode_wbmap(self.nwait("WBMAP.DT"))

    def nblob_many(self, requests, iyloc: int, iblb1, iblb2) -> None:
        """NBLOB for each (image, edge, X, IES) row, in order, storing each map
        in its cache row (IBLB1 for image 1, IBLB2 for image 2)."""
        for image, edge, x, ies in requests:
            self.nblob(int(image), int(x), iyloc, int(ies),
                       (iblb1 if image == 1 else iblb2)[edge - 1])

    def read_slice(self, image: int, iyloc: int, say) -> Slice:
        """Take the next SLICE.DT.  A slice for another line or image (left over
        from an ESTAR that was stopped mid-line) is set aside, said, and skipped:
        IDIR(3) and IDIR(7) of the file name the line and image it is for."""
        while True:
            data = self.nwait("SLICE.DT")
            sl = decode_slice(data)
            idir = sl.idir
            if idir[0] == -1 and idir[2] == iyloc and idir[6] == image:
                return sl
            self.keep_aside("SLICE.DT", data, say,
                            f"it is for line {idir[2]}, image {idir[6]}, not line {iyloc}, "
                            f"image {image}")

    def keep_aside(self, name: str, data: bytes, say, why: str) -> None:
        say(f" Skipped a {name} left from earlier work ({why}).")

    def close(self) -> None:
        pass


class FileLink(Link):
    """The two-process link over files in JHDATA."""

    def __init__(self, jh: JHData):
        self.jh = jh

    def cnova(self, cmd: Command) -> None:
        # Wait until NSTAR has taken the previous command, then publish by rename.
        self.jh.publish("ECONT.DT", "NCONT.DT", encode_ncont(cmd))

    def nwait(self, name: str) -> bytes:
        self.jh.wait_for(name)
        if name == "SLICE.DT":
            # CFEAT renames SLICE.DT to SL.DT before reading, freeing the name so
            # NSTAR can publish the second slice while ESTAR reads the first.
            self.jh.rename("SLICE.DT", "SL.DT")
            data = self.jh.take("SL.DT")
        else:
            data = self.jh.take(name)
        reader = _READERS.get(name)
        if reader is not None:
            try:
                reader(data, str(self.jh.path(name)))
            except FormatError as exc:        # one clear error; the bytes are kept
                kept = self._store(f"{name}.bad", data)
                raise FormatError(exc.name, f"{exc.problem}; kept as {kept}") from None
        return data

    def discard_stale(self, name: str, say) -> None:
        where = self.jh.set_aside(name, "stale")
        if where:
            say(f" Found {name} from an earlier run; moved it to {where}")

    def _store(self, label: str, data: bytes):
        stale = self.jh.dir / "STALE"
        stale.mkdir(exist_ok=True)
        n = 0
        while (stale / f"{label}.{n}").exists():
            n += 1
        (stale / f"{label}.{n}").write_bytes(data)
        return stale / f"{label}.{n}"

    def keep_aside(self, name: str, data: bytes, say, why: str) -> None:
        kept = self._store(f"{name}.skipped", data)
        say(f" Skipped a {name} left from earlier work ({why}); kept as {kept}")


class DirectLink(Link):
    """The same bytes, handed to an in-process NSTAR: each command is executed at
    once and its reply files queue up by name, in order."""

    def __init__(self, nova):
        self.nova = nova
        self.pending: dict[str, deque] = defaultdict(deque)

    def cnova(self, cmd: Command) -> None:
        for reply in self.nova.execute(encode_ncont(cmd)):
            self.pending[reply.name].append(reply.data)

    def nblob_many(self, requests, iyloc: int, iblb1, iblb2) -> None:
        """The same NCONT.DT bytes, handed to NSTAR in one block (compiled)."""
        if len(requests) == 0:
            return
        req = np.asarray(requests, dtype=np.int64)
        words = np.zeros((len(req), 6), dtype=np.int64)
        words[:, 0] = CODE_EDGE_MAP
        words[:, 1] = req[:, 0]
        words[:, 2] = req[:, 2]
        words[:, 3] = iyloc
        words[:, 5] = req[:, 3]
        replies = np.frombuffer(self.nova.execute_edge_maps(words.astype(">i2").tobytes()),
                                dtype=">i2").reshape(-1, 17)
        if len(replies) != len(req) or not (replies[:, 0] == 1).all():
            raise FormatError("WBMAP.DT", "the in-process NSTAR returned no edge map")
        for image, iblb in ((1, iblb1), (2, iblb2)):
            rows = req[:, 0] == image
            iblb[req[rows, 1] - 1] = replies[rows]

    def nwait(self, name: str) -> bytes:
        queue = self.pending.get(name)
        if not queue:
            raise FormatError(name, "the in-process NSTAR produced no such reply")
        return queue.popleft()
