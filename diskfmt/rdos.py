"""The shared RDOS directory JHDATA: publishing, waiting and taking files.

In 1985 NSTAR (NOVA) and ESTAR (Eclipse) shared one disk partition and spoke only
through files in it.  RIG-NOTES §2 fixes the semantics kept here:

* every result is written under a temporary name and renamed; RDOS RENAM refused
  an existing target, so :meth:`JHData.publish` waits until the target name is
  free and then publishes with a no-overwrite hard link — a reader never sees a
  partial file and an unread file is never replaced;
* waiting for a file uses ``watchdog`` file-system events with a poll fallback,
  and every wait can time out with a message naming the file and the program
  that should have written (or taken) it.
"""

from __future__ import annotations

import errno
import fcntl
import os
from pathlib import Path
import threading
import time

import select

try:                                     # watchdog is a core dependency; the poll
    from watchdog.events import FileSystemEventHandler   # fallback keeps a broken
    from watchdog.observers import Observer              # install usable.
except ImportError:                      # pragma: no cover
    Observer = None
    FileSystemEventHandler = object
try:                                     # watchdog's own inotify(7) bindings (Linux)
    from watchdog.observers.inotify_c import (inotify_init, inotify_add_watch,
                                              InotifyConstants)
except (ImportError, OSError):           # pragma: no cover - not Linux
    inotify_init = None

__all__ = ["JHData", "LinkTimeout", "LockedError", "default_jhdata"]


def _load_renameat2():
    """renameat2(…, RENAME_NOREPLACE): an atomic rename that refuses an existing
    target, as RDOS RENAM did — one file-system operation where link + unlink
    take two (it matters on a disk with slow deletes)."""
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


_RENAMEAT2 = _load_renameat2()
_AT_FDCWD = -100
_RENAME_NOREPLACE = 1


def _rename_noreplace(src: Path, dst: Path) -> None:
    """Rename ``src`` to ``dst`` unless ``dst`` exists (FileExistsError)."""
    global _RENAMEAT2
    if _RENAMEAT2 is not None:
        if _RENAMEAT2(_AT_FDCWD, os.fsencode(src), _AT_FDCWD, os.fsencode(dst),
                      _RENAME_NOREPLACE) == 0:
            return
        err = ctypes_errno()
        if err == errno.EEXIST:
            raise FileExistsError(errno.EEXIST, "exists", str(dst))
        if err not in (errno.ENOSYS, errno.EINVAL):   # no renameat2 on this file system
            raise OSError(err, os.strerror(err), str(src))
        _RENAMEAT2 = None
    os.link(src, dst)                                  # the portable way: two steps
    os.unlink(src)


def ctypes_errno() -> int:
    import ctypes
    return ctypes.get_errno()


class LinkTimeout(TimeoutError):
    """The other program did not write (or take) a file in time."""


class LockedError(RuntimeError):
    """Another copy of the program already works on this JHDATA directory."""


def default_jhdata() -> Path:
    """``$JHDATA`` when set, else ``./jhdata``."""
    return Path(os.environ.get("JHDATA") or "jhdata")


class _InotifyWaiter:
    """File-system events for one directory, read in the waiting thread itself
    through watchdog's inotify bindings: no observer threads, so a round trip
    between the two programs costs no thread hand-offs (measured in
    bench/bench_rig.py: the observer-thread version took about twice as long)."""

    MASK_NAMES = ("IN_CREATE", "IN_MOVED_TO", "IN_DELETE", "IN_MOVED_FROM")

    def __init__(self, directory: Path):
        self.fd = inotify_init()
        if self.fd < 0:
            raise OSError("inotify_init failed")
        mask = 0
        for name in self.MASK_NAMES:
            mask |= getattr(InotifyConstants, name)
        if inotify_add_watch(self.fd, os.fsencode(directory), mask) < 0:
            os.close(self.fd)
            raise OSError(f"cannot watch {directory}")
        self.poller = select.poll()
        self.poller.register(self.fd, select.POLLIN)

    def wait(self, seconds: float) -> None:
        """Return when an event arrives or after ``seconds``; drain the events."""
        if self.poller.poll(max(0, int(seconds * 1000))):
            os.read(self.fd, 65536)

    def close(self) -> None:
        os.close(self.fd)


class _Wake(FileSystemEventHandler):
    def __init__(self, owner: "JHData"):
        super().__init__()
        self.owner = owner

    def on_any_event(self, event):       # noqa: D401 - watchdog callback
        self.owner._poke()


class JHData:
    """One program's view of the JHDATA directory.

    ``me`` and ``peer`` name the programs for messages ("no SLICE.DT from NSTAR
    after 30 s — is nstar running on this jhdata directory?")."""

    def __init__(self, directory, *, me: str, peer: str, timeout: float | None = 30.0,
                 use_events: bool = True, poll: float = 0.002):
        self.dir = Path(directory)
        self.me, self.peer = me, peer
        self.timeout = timeout
        self.poll = poll
        self._cond = threading.Condition()
        self._generation = 0
        self._observer = None
        self._inotify = None
        self._lock_fd = None
        self._busy_fd = None
        if not self.dir.is_dir():
            raise FileNotFoundError(f"jhdata directory {self.dir} does not exist "
                                    f"(create it, or give --jhdata DIR)")
        if use_events and inotify_init is not None:
            try:
                self._inotify = _InotifyWaiter(self.dir)
                self.poll = max(poll, 0.05)
            except OSError:
                self._inotify = None
        if use_events and self._inotify is None and Observer is not None:
            try:
                obs = Observer()
                obs.schedule(_Wake(self), str(self.dir), recursive=False)
                obs.daemon = True
                obs.start()
                self._observer = obs
                self.poll = max(poll, 0.05)  # events do the work; polling only backs up
            except OSError:                   # inotify limits etc.: poll instead
                self._observer = None

    # --- housekeeping -------------------------------------------------------
    def close(self) -> None:
        if self._inotify is not None:
            self._inotify.close()
            self._inotify = None
        if self._observer is not None:
            self._observer.stop()
            self._observer = None
        if self._busy_fd is not None:
            os.close(self._busy_fd)           # the file stays: a peer may hold it open
            self._busy_fd = None
        if self._lock_fd is not None:
            try:
                os.unlink(self._lock_path)    # still ours: we hold the lock
            except FileNotFoundError:
                pass
            os.close(self._lock_fd)
            self._lock_fd = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _poke(self) -> None:
        with self._cond:
            self._generation += 1
            self._cond.notify_all()

    def path(self, name: str) -> Path:
        return self.dir / name

    def exists(self, name: str) -> bool:
        return os.path.exists(self.dir / name)

    def lock(self, name: str) -> None:
        """Hold an exclusive lock file for the life of this process (two ESTARs on
        one directory would steal each other's answers)."""
        fd = os.open(self.dir / name, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(fd)
            if exc.errno in (errno.EAGAIN, errno.EACCES):
                raise LockedError(f"another {self.me} is already running on "
                                  f"{self.dir} (it holds {name}); stop it first") from None
            raise
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        self._lock_fd = fd
        self._lock_path = self.dir / name

    # --- the busy lock (QUIRKS M14) ---------------------------------------------
    def open_busy(self, name: str) -> None:
        """Create (or open) the busy-lock file ``name`` that :meth:`busy` locks
        while a command is being carried out; done once, at start."""
        self._busy_fd = os.open(self.dir / name, os.O_RDWR | os.O_CREAT, 0o644)

    class _Busy:
        def __init__(self, fd):
            self.fd = fd

        def __enter__(self):
            fcntl.flock(self.fd, fcntl.LOCK_EX)    # a peer holds it only for a sweep
            return self

        def __exit__(self, *exc):
            fcntl.flock(self.fd, fcntl.LOCK_UN)

    def busy(self) -> "JHData._Busy":
        """Hold the busy lock (see :meth:`open_busy`) for a ``with`` block: from
        taking a command to publishing its last reply."""
        return self._Busy(self._busy_fd)

    def wait_idle(self, name: str, sweep, timeout: float | None = None) -> None:
        """Call ``sweep()`` until the peer holds no busy lock ``name``, then once
        more while holding it ourselves: afterwards no reply to a command sent
        before we started can still appear (a reply the peer was computing, or
        was waiting to publish, when the first sweep ran is swept too)."""
        path = self.dir / name

        def idle() -> bool:
            sweep()
            try:
                fd = os.open(path, os.O_RDONLY)
            except FileNotFoundError:         # the peer has never run here
                return True
            try:
                try:
                    fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
                except BlockingIOError:
                    return False
                sweep()
                return True
            finally:
                os.close(fd)                  # and with it the lock

        self._wait(idle,
                   lambda t: (f"{self.peer} still busy with a command from an earlier run "
                              f"after {t:g} s (it holds {name}) — is {self.peer.lower()} "
                              f"stopped or waiting at its console ({self.dir})?"), timeout)

    # --- waiting ------------------------------------------------------------
    def _wait(self, done, describe, timeout) -> None:
        limit = self.timeout if timeout is None else timeout
        deadline = None if not limit else time.monotonic() + limit
        if self._inotify is not None:
            while not done():
                left = self.poll
                if deadline is not None:
                    left = min(left, deadline - time.monotonic())
                    if left <= 0:
                        raise LinkTimeout(describe(limit))
                self._inotify.wait(left)
            return
        while True:
            with self._cond:
                gen = self._generation
            if done():
                return
            if deadline is not None and time.monotonic() >= deadline:
                raise LinkTimeout(describe(limit))
            with self._cond:
                if self._generation == gen:
                    wait = self.poll
                    if deadline is not None:
                        wait = min(wait, max(0.0, deadline - time.monotonic()))
                    self._cond.wait(wait)

    def wait_for(self, name: str, timeout: float | None = None) -> None:
        """NWAIT: wait until ``name`` exists."""
        self._wait(lambda: self.exists(name),
                   lambda t: (f"no {name} from {self.peer} after {t:g} s — is "
                              f"{self.peer.lower()} running on this jhdata directory "
                              f"({self.dir})?"), timeout)

    def wait_gone(self, name: str, timeout: float | None = None) -> None:
        """Wait until ``name`` has been taken by the other program."""
        self._wait(lambda: not self.exists(name),
                   lambda t: (f"{name} not taken by {self.peer} after {t:g} s — is "
                              f"{self.peer.lower()} running on this jhdata directory "
                              f"({self.dir})?"), timeout)

    # --- moving files ---------------------------------------------------------
    def publish(self, temp_name: str, name: str, data: bytes,
                timeout: float | None = None) -> None:
        """Write ``data`` as ``temp_name``, then rename it to ``name`` — but never
        over an unread ``name``: wait until it is gone, then link atomically."""
        tmp = self.dir / temp_name
        with open(tmp, "wb") as fh:
            fh.write(data)
        target = self.dir / name
        while True:
            self.wait_gone(name, timeout)
            try:
                _rename_noreplace(tmp, target)  # fails if the name reappeared: wait again
                break
            except FileExistsError:
                continue

    def take(self, name: str) -> bytes:
        """Read ``name`` and delete it (OPEN, READ, CLOSE, DELETE)."""
        path = self.dir / name
        data = path.read_bytes()
        path.unlink()
        return data

    def read(self, name: str) -> bytes:
        return (self.dir / name).read_bytes()

    def delete(self, name: str) -> bool:
        """RDOS DELETE: no error when the file is absent."""
        try:
            (self.dir / name).unlink()
            return True
        except FileNotFoundError:
            return False

    def rename(self, old: str, new: str) -> None:
        os.replace(self.dir / old, self.dir / new)

    def set_aside(self, name: str, why: str, as_name: str | None = None) -> Path | None:
        """Move a stale ``name`` into ``STALE/`` instead of deleting it, so
        nothing is lost; returns where it went (named after ``as_name`` if given)."""
        src = self.dir / name
        name = as_name or name
        if not src.exists():
            return None
        stale = self.dir / "STALE"
        stale.mkdir(exist_ok=True)
        stamp = time.strftime("%Y%m%d-%H%M%S")
        n = 0
        while True:                   # link, never replace: both programs sweep into STALE/
            dest = stale / f"{name}.{stamp}.{n}"
            try:
                os.link(src, dest)
                break
            except FileExistsError:
                n += 1
            except FileNotFoundError:     # taken or swept by the other program meanwhile
                return None
        try:
            os.unlink(src)
        except FileNotFoundError:         # deleted meanwhile (NSTAR's DELETE of NCONT.DT)
            pass
        return dest
