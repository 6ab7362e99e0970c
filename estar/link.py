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
from diskfmt.rdos import (JHData, LinkTimeout, NotAProtocolFile, ESTAR_LOCK, NSTAR_BUSY,
                          NSTAR_LOCK)

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
    """The two-process link over files in JHDATA.

    ESTAR's start-up protocol lives here and only here: :meth:`open` checks the
    directory and takes ESTAR.LCK (before any question is asked), :meth:`start`
    sweeps stale files until NSTAR is idle (QUIRKS M12, M14);
    :func:`start_file_link` does both for a program without a dialogue."""

    def __init__(self, jh: JHData, pipeline: bool | None = None):
        self.jh = jh
        self.pipeline = jh.wake != "any" if pipeline is None else pipeline

    @classmethod
    def open(cls, jhdata, *, timeout: float | None = 30.0, wake: str | None = None) -> "FileLink":
        """Check ``jhdata`` and hold ESTAR.LCK (LockedError if another ESTAR does);
        ``wake``: how to wait (:func:`diskfmt.rdos.link_wait`; None: ``$RIG_LINK_WAIT``)."""
        jh = JHData(jhdata, me="ESTAR", peer="NSTAR", timeout=timeout, wake=wake)
        try:
            jh.lock(ESTAR_LOCK)
        except BaseException:
            jh.close()
            raise
        return cls(jh)

    def start(self, say=None) -> None:
        """Set aside what an earlier run left, until NSTAR is not in the middle of
        a command sent before we started: a reply it published later would be
        read as ours (QUIRKS M14)."""
        def sweep() -> None:
            for name in ESTAR_STALE:
                where = self.jh.set_aside(name, "stale")
                if where and say:
                    say(f" Found {name} from an earlier run; moved it to {where}")
        self.jh.wait_idle(NSTAR_BUSY, sweep)

    def nstar_running(self) -> bool:
        """Does an NSTAR hold NSTAR.LCK on this directory now?"""
        return self.jh.held(NSTAR_LOCK)

    def wait_for_nstar(self, timeout: float | None = None) -> None:
        """Wait until an NSTAR runs on this directory (LinkTimeout after ``timeout``)."""
        self.jh.wait_held(NSTAR_LOCK, timeout)

    def publish_posit(self, data: bytes) -> None:
        """PNPL's write: EDAT.DT, renamed over POSIT.DT (DELETE + RENAM, atomically)."""
        self.jh.publish_replace("EDAT.DT", "POSIT.DT", data)

    def cnova(self, cmd: Command) -> None:
        # Wait until NSTAR has taken the previous command, then publish by rename.
        # Giving up, ESTAR takes its command back: NSTAR must not obey it later.
        try:
            self.jh.publish("ECONT.DT", "NCONT.DT", encode_ncont(cmd))
        except LinkTimeout:
            self.withdraw()
            raise

    def nblob_many(self, requests, iyloc: int, iblb1, iblb2) -> None:
        """NBLOB for each request, in order — with request k+1 written as
        ECONT.DT while NSTAR answers request k and renamed to NCONT.DT the
        moment WBMAP.DT k appears, before ESTAR reads that map: NSTAR finds its
        next command waiting when it has published a reply, instead of
        sleeping until ESTAR has read the map and written the next one.

        The same files with the same bytes, in the same order, as one NBLOB
        at a time, and no more in flight: a command is sent only when the
        reply to the one before exists, so a reply is always the one to the
        oldest command without one (WBMAP.DT carries no request tag: an NSTAR
        restarted between taking a command and answering it must not answer a
        later one in its place, QUIRKS M14).  The waits, their timeouts and
        their messages are NBLOB's.  ``RIG_LINK_WAIT=any``: one at a time."""
        if not self.pipeline:
            super().nblob_many(requests, iyloc, iblb1, iblb2)
            return
        rows = [(int(image), int(edge), int(x), int(ies)) for image, edge, x, ies in requests]
        if not rows:
            return

        def command(row) -> Command:
            return Command(CODE_EDGE_MAP, row[0], row[2], iyloc, 0, row[3])

        self.cnova(command(rows[0]))
        ahead = None                   # request k+1: "ECONT.DT" written, then "NCONT.DT" sent
        try:
            for k, (image, edge, _, _) in enumerate(rows):
                last = k + 1 == len(rows)
                if not last:
                    self.jh.write_temp("ECONT.DT", encode_ncont(command(rows[k + 1])))
                    ahead = "ECONT.DT"
                self.jh.wait_for("WBMAP.DT")
                if not last:           # NCONT.DT k is gone: NSTAR deletes it before replying
                    try:
                        self.jh.publish_written("ECONT.DT", "NCONT.DT")
                    except LinkTimeout:
                        self.withdraw()
                        ahead = None
                        raise
                    ahead = "NCONT.DT"
                data = self._take_reply("WBMAP.DT")
                (iblb1 if image == 1 else iblb2)[edge - 1] = decode_wbmap(data)
                ahead = None
        except BaseException:
            # Leave what one NBLOB at a time would leave: request k+1 is taken
            # back (NSTAR must not obey it later); request k, if NSTAR never
            # took it, stays for the next start's sweep (M12), as it did.
            for name in {None: (), "ECONT.DT": ("ECONT.DT",),
                         "NCONT.DT": ("ECONT.DT", "NCONT.DT")}[ahead]:
                try:
                    self.jh.delete(name)
                except OSError:               # not a file of ours (a directory planted)
                    pass
            raise

    def wait_taken(self) -> None:
        """Wait until NSTAR has taken the last command (withdrawn on timeout)."""
        try:
            self.jh.wait_gone("NCONT.DT")
        except LinkTimeout:
            self.withdraw()
            raise

    def withdraw(self) -> bool:
        """Take back a command NSTAR has not taken (while ESTAR.LCK is held every
        NCONT.DT and ECONT.DT is this ESTAR's).  True if there was one."""
        taken_back = False
        for name in ("ECONT.DT", "NCONT.DT"):
            try:
                taken_back = self.jh.delete(name) or taken_back
            except OSError:                   # not a file of ours (a directory planted)
                pass
        return taken_back

    def nwait(self, name: str) -> bytes:
        self.jh.wait_for(name)
        return self._take_reply(name)

    def _take_reply(self, name: str) -> bytes:
        """Take the reply ``name`` that exists now, checked (M16, M19)."""
        src = name
        if name == "SLICE.DT":
            # CFEAT renames SLICE.DT to SL.DT before reading, freeing the name so
            # NSTAR can publish the second slice while ESTAR reads the first.
            self.jh.rename("SLICE.DT", "SL.DT")
            src = "SL.DT"
        try:
            data = self.jh.take(src)
        except NotAProtocolFile as exc:       # a link, FIFO, huge file: moved, not read
            kept = self.jh.set_aside_bad(src, f"{name}.bad")
            raise FormatError(str(self.jh.path(name)), f"{exc.problem}; kept as {kept}") from None
        reader = _READERS.get(name)
        if reader is not None:
            try:
                reader(data, str(self.jh.path(name)))
            except FormatError as exc:        # one clear error; the bytes are kept
                kept = self.jh.keep(f"{name}.bad", data)
                raise FormatError(exc.name, f"{exc.problem}; kept as {kept}") from None
        return data

    def discard_stale(self, name: str, say) -> None:
        where = self.jh.set_aside(name, "stale")
        if where:
            say(f" Found {name} from an earlier run; moved it to {where}")

    def keep_aside(self, name: str, data: bytes, say, why: str) -> None:
        kept = self.jh.keep(f"{name}.skipped", data)
        say(f" Skipped a {name} left from earlier work ({why}); kept as {kept}")

    def close(self) -> None:
        self.jh.close()


def start_file_link(jhdata, *, timeout: float | None = 30.0, say=None,
                    wake: str | None = None) -> FileLink:
    """A started file link: directory checked, ESTAR.LCK held, stale files set
    aside, NSTAR idle — ESTAR's whole start-up protocol (for rig, bench, tests)."""
    link = FileLink.open(jhdata, timeout=timeout, wake=wake)
    try:
        link.start(say)
    except BaseException:
        link.close()
        raise
    return link


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
