"""The shared RDOS directory JHDATA: publishing, waiting and taking files.

In 1985 NSTAR (NOVA) and ESTAR (Eclipse) shared one disk partition and spoke only
through files in it.  The semantics kept here (QUIRKS M9-M17):

* every result is written under a temporary name and renamed; RDOS RENAM refused
  an existing target, so :meth:`JHData.publish` waits until the target name is
  free and then publishes with a no-overwrite rename — a reader never sees a
  partial file and an unread file is never replaced;
* waiting for a file uses file-system events with a poll fallback, and every
  wait can time out with a message naming the file and the program that should
  have written (or taken) it.

The directory is a trust boundary (docs/robustness.md, "A hostile peer"):
anyone who can write into it may plant links, FIFOs or huge files under any
name.  So nothing here follows a symbolic link, opens an existing name for
writing, reads a file that is not a regular one, or reads more than a format
allows; ``STALE/`` must be a plain directory.  :func:`write_atomic` is the one
atomic publish of the project for files outside JHDATA too.
"""

from __future__ import annotations

import errno
import fcntl
import math
import os
from pathlib import Path
import secrets
import stat
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

__all__ = ["JHData", "LinkTimeout", "LockedError", "NotAProtocolFile", "default_jhdata",
           "write_atomic", "read_regular", "ESTAR_LOCK", "NSTAR_LOCK", "NSTAR_BUSY",
           "STALE_DIR", "LOCK_MODE"]

# The lock files of the two programs (QUIRKS M14, M17).  They are never deleted:
# a process that opened one just before an unlink would lock the orphaned inode
# while a third locked a new file (two holders at once).
ESTAR_LOCK = "ESTAR.LCK"
NSTAR_LOCK = "NSTAR.LCK"
LOCK_PROBE_GRACE_S = 0.25      # lock(): how long a lock held by a held() probe is waited out
NSTAR_BUSY = "NSTAR.BSY"
STALE_DIR = "STALE"
LOCK_MODE = 0o664          # group-writable: a shared jhdata/ serves a group of users
DIR_MODE = 0o775

# The most bytes a protocol file may hold (its format's size) and how to say it.
PROTOCOL_SIZES = {"NCONT.DT": (12, "12"), "SLICE.DT": (1024, "1024 or 512"),
                  "SL.DT": (1024, "1024 or 512"), "WBMAP.DT": (34, "34"),
                  "BLOCK.DT": (54, "54"), "POSIT.DT": (2560, "2560"),
                  "TERM.DT": (4096, "a line of text")}

_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_CLOEXEC = getattr(os, "O_CLOEXEC", 0)


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


def _rename_noreplace(src, dst, src_dir_fd: int | None = None,
                      dst_dir_fd: int | None = None) -> None:
    """Rename ``src`` to ``dst`` unless ``dst`` exists (FileExistsError).  Neither
    name is followed if it is a symbolic link: the link itself moves."""
    global _RENAMEAT2
    if _RENAMEAT2 is not None:
        sfd = _AT_FDCWD if src_dir_fd is None else src_dir_fd
        dfd = _AT_FDCWD if dst_dir_fd is None else dst_dir_fd
        if _RENAMEAT2(sfd, os.fsencode(src), dfd, os.fsencode(dst), _RENAME_NOREPLACE) == 0:
            return
        err = ctypes_errno()
        if err == errno.EEXIST:
            raise FileExistsError(errno.EEXIST, "exists", str(dst))
        if err not in (errno.ENOSYS, errno.EINVAL):   # no renameat2 on this file system
            raise OSError(err, os.strerror(err), str(src))
        _RENAMEAT2 = None
    # the portable way, two steps; link(2) does not follow a symbolic link
    os.link(src, dst, src_dir_fd=src_dir_fd, dst_dir_fd=dst_dir_fd, follow_symlinks=False)
    os.unlink(src, dir_fd=src_dir_fd)


def ctypes_errno() -> int:
    import ctypes
    return ctypes.get_errno()


class LinkTimeout(TimeoutError):
    """The other program did not write (or take) a file in time."""


class LockedError(RuntimeError):
    """Another copy of the program already works on this JHDATA directory."""


class NotAProtocolFile(OSError):
    """A name in JHDATA that is not a regular file of a size the format allows
    (a symbolic link, FIFO, directory, device, or far too many bytes)."""

    def __init__(self, path, problem: str):
        super().__init__(f"{path}: {problem}")
        self.path = Path(path)
        self.problem = problem

    def __str__(self):
        return f"{self.path}: {self.problem}"


def describe_os_error(exc: OSError) -> str:
    """One line for a file-system error: the path(s), then the cause."""
    if isinstance(exc, (_Said, NotAProtocolFile)) or not exc.strerror:
        return str(exc)
    names = [str(n) for n in (exc.filename, exc.filename2) if n is not None]
    return f"{' -> '.join(names)}: {exc.strerror}" if names else exc.strerror


LINK_WAIT_ENV = "RIG_LINK_WAIT"
LINK_WAITS = ("named", "any")


def link_wait() -> str:
    """How the file link waits: ``named`` (the default) wakes a waiting program
    only on the events that can end its wait, and ESTAR sends a line's next
    edge-map request the moment the reply to the last one appears (before
    reading it; estar.link.FileLink.nblob_many); ``any`` is the earlier way,
    kept to measure against (``RIG_LINK_WAIT=any``): every event in the
    directory wakes every waiter, one request at a time.  The files and
    their bytes are the same either way."""
    value = os.environ.get(LINK_WAIT_ENV) or "named"
    if value not in LINK_WAITS:       # an OSError: every program says it in one line
        raise BadLinkWait(errno.EINVAL, f"{LINK_WAIT_ENV}={value!r}: expected one of "
                                        f"{', '.join(LINK_WAITS)}")
    return value


def default_jhdata() -> Path:
    """``$JHDATA`` when set, else ``./jhdata``."""
    return Path(os.environ.get("JHDATA") or "jhdata")


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISLNK, "a symbolic link"), (stat.S_ISFIFO, "a FIFO"),
                       (stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def read_regular(path, limit: int, expect: str | None = None, *, follow: bool = False,
                 dir_fd: int | None = None) -> bytes:
    """The bytes of ``path`` if it is a regular file of at most ``limit`` bytes;
    else :class:`NotAProtocolFile` naming it (``expect`` says what size was
    wanted).  Never blocks on a FIFO or device, never reads past ``limit``;
    with ``follow=False`` a symbolic link is refused, not followed."""
    flags = os.O_RDONLY | os.O_NONBLOCK | _CLOEXEC | (0 if follow else _NOFOLLOW)
    try:
        fd = os.open(path, flags, dir_fd=dir_fd)
    except OSError as exc:
        if exc.errno == errno.ELOOP and not follow:
            raise NotAProtocolFile(path, "not a regular file (a symbolic link)") from None
        raise
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise NotAProtocolFile(path, f"not a regular file ({_kind(st.st_mode)})")
        if st.st_size > limit:
            raise NotAProtocolFile(path, f"{st.st_size} bytes, expected {expect or limit}")
        chunks, total = [], 0
        while total <= limit:
            chunk = os.read(fd, limit + 1 - total)
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
        if total > limit:                     # grew while being read
            raise NotAProtocolFile(path, f"more than {expect or limit} bytes")
        return b"".join(chunks)
    finally:
        os.close(fd)


def _write_new(path, data: bytes, mode: int = 0o644, dir_fd: int | None = None,
               fsync: bool = False) -> None:
    """Create ``path`` (it must not exist: O_EXCL, and O_NOFOLLOW so a planted
    link is never written through) and write ``data``; removed again on error."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NOFOLLOW | _CLOEXEC, mode,
                 dir_fd=dir_fd)
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
        if fsync:
            os.fsync(fd)
    except BaseException as exc:
        os.close(fd)
        try:
            os.unlink(path, dir_fd=dir_fd)
        except OSError:
            pass
        if isinstance(exc, OSError) and exc.filename is None:   # name the file (ENOSPC…)
            raise OSError(exc.errno, exc.strerror, str(path)) from None
        raise
    os.close(fd)


def write_atomic(path, data: bytes, *, replace: bool = True, mode: int = 0o644,
                 fsync: bool = True, temp_name: str | None = None) -> Path:
    """The one atomic publish: write ``data`` under a new temporary name in the
    target's directory (a random one unless ``temp_name``; never an existing
    name, never through a link), then rename it to ``path`` — replacing an
    existing file when ``replace``, else refusing with FileExistsError (no
    check-then-replace race: the rename itself refuses).  A reader sees the old
    file or the whole new one, never a part; on any error nothing is left."""
    path = Path(path)
    tmp = path.with_name(temp_name or f".{path.name}.{secrets.token_hex(6)}.tmp")
    _write_new(tmp, data, mode, fsync=fsync)
    try:
        if replace:
            os.replace(tmp, path)
        else:
            _rename_noreplace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return path


def _open_lock_file(path: Path) -> int:
    """Open (creating, group-writable) the lock file ``path``; never through a
    link.  A user who may not write it (another user's file in a shared
    jhdata/) opens it read-only: flock(2) needs no write permission."""
    flags = os.O_CREAT | _NOFOLLOW | _CLOEXEC
    try:
        fd = os.open(path, os.O_RDWR | flags, LOCK_MODE)
    except PermissionError:
        fd = os.open(path, os.O_RDONLY | _NOFOLLOW | _CLOEXEC)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise NotAProtocolFile(path, "not a regular file (a symbolic link); "
                                         "remove it — a lock file is never followed") from None
        raise
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise NotAProtocolFile(path, f"not a regular file ({_kind(st.st_mode)})")
    if st.st_nlink != 1:                      # a hard link to some other file: hands off
        os.close(fd)
        raise NotAProtocolFile(path, f"has {st.st_nlink} hard links; a lock file has one — "
                                     f"remove it")
    if st.st_uid == os.geteuid() and stat.S_IMODE(st.st_mode) != LOCK_MODE:
        try:
            os.fchmod(fd, LOCK_MODE)              # the umask must not make it private
        except OSError:
            pass
    return fd


class _InotifyWaiter:
    """File-system events for one directory, read in the waiting thread itself
    through watchdog's inotify bindings: no observer threads, so a round trip
    between the two programs costs no thread hand-offs (measured in
    bench/bench_rig.py: the observer-thread version took about twice as long).

    Each wait arms only the events that can end it (:meth:`arm`): a name
    appears by a rename (IN_MOVED_TO; IN_CREATE too where the no-overwrite
    rename is link + unlink), a name goes by a delete or a rename away.  The
    other program's temporaries (ECONT.DT, NDAT.DT) and its takes then do not
    wake a process that waits for something else; each such wake was a
    context switch, on a busy machine often a wait for a core.  A name made
    in any other way is still seen, by the poll backstop."""

    ANY = ("IN_CREATE", "IN_MOVED_TO", "IN_DELETE", "IN_MOVED_FROM")
    APPEAR = ("IN_MOVED_TO",)
    GONE = ("IN_DELETE", "IN_MOVED_FROM")

    def __init__(self, directory: Path, named: bool = True):
        self.fd = inotify_init()
        if self.fd < 0:
            raise OSError("inotify_init failed")
        self.path = os.fsencode(directory)
        self.named = named
        self.mask = 0
        try:
            os.set_blocking(self.fd, False)   # drained without blocking (see arm)
            self.arm(self.ANY)
        except OSError:
            os.close(self.fd)
            raise
        self.poller = select.poll()
        self.poller.register(self.fd, select.POLLIN)

    _masks: dict = {}

    @classmethod
    def _mask(cls, names) -> int:
        mask = cls._masks.get(names)
        if mask is None:
            mask = 0
            for name in names:
                mask |= getattr(InotifyConstants, name)
            cls._masks[names] = mask
        return mask

    def arm(self, events=ANY) -> None:
        """Watch for ``events`` (names of inotify flags) from now on; call it
        before the first check of a wait.  Events queued under an earlier
        mask (most often this program's own renames and deletes) are dropped:
        whatever they told, the check that follows sees."""
        if not self.named:
            events = self.ANY
        elif events == self.APPEAR and _RENAMEAT2 is None:
            events = ("IN_CREATE", "IN_MOVED_TO")     # the link(2) of the fallback
        mask = self._mask(events)
        if mask == self.mask:
            return
        if inotify_add_watch(self.fd, self.path, mask) < 0:
            if self.mask:                         # keep the old watch: the poll backs it up
                return
            raise OSError(f"cannot watch {os.fsdecode(self.path)}")
        self.mask = mask
        self._drain()

    def _drain(self) -> None:
        try:
            while os.read(self.fd, 65536):
                pass
        except BlockingIOError:
            pass

    def wait(self, seconds: float) -> None:
        """Return when an event arrives or after ``seconds``; drain the events."""
        if self.poller.poll(max(0, math.ceil(seconds * 1000))):
            self._drain()

    def close(self) -> None:
        os.close(self.fd)


class _Wake(FileSystemEventHandler):
    def __init__(self, owner: "JHData"):
        super().__init__()
        self.owner = owner

    def on_any_event(self, event):       # noqa: D401 - watchdog callback
        self.owner._poke()


class _Said:
    """An OSError whose text is one whole sentence (no "[Errno N]")."""

    def __str__(self):
        return self.strerror or super().__str__()


class _DirError(_Said, OSError):
    pass


class BadLinkWait(_Said, OSError):
    """``$RIG_LINK_WAIT`` names no way of waiting."""


class MissingDirectory(_Said, FileNotFoundError):
    pass


class NotADirectory(_Said, NotADirectoryError):
    pass


class UnwritableDirectory(_Said, PermissionError):
    pass


class ReadOnlyDirectory(_Said, OSError):
    pass


def _read_only_file_system(d: Path) -> bool:
    try:
        return bool(os.statvfs(d).f_flag & os.ST_RDONLY)
    except (OSError, AttributeError):
        return False


def check_directory(directory) -> Path:
    """``directory`` as a usable JHDATA, or one clear OSError saying why not."""
    d = Path(directory)
    try:
        st = os.stat(d)
    except FileNotFoundError:
        raise MissingDirectory(errno.ENOENT, f"jhdata directory {d} does not exist "
                                             f"(create it, or give --jhdata DIR)") from None
    if not stat.S_ISDIR(st.st_mode):
        raise NotADirectory(errno.ENOTDIR, f"jhdata {d} is not a directory "
                                           f"(give --jhdata DIR)")
    if not os.access(d, os.W_OK | os.X_OK):
        if _read_only_file_system(d):         # root too is refused there: say the cause
            raise ReadOnlyDirectory(errno.EROFS, f"jhdata directory {d} is on a read-only "
                                                 f"file system (remount it read-write, or "
                                                 f"give --jhdata DIR)")
        raise UnwritableDirectory(errno.EACCES, f"jhdata directory {d} is not writable by "
                                                f"this user (see jhdata/README.md for a "
                                                f"shared setup)")
    return d


class JHData:
    """One program's view of the JHDATA directory.

    ``me`` and ``peer`` name the programs for messages ("no SLICE.DT from NSTAR
    after 30 s — is nstar running on this jhdata directory?")."""

    def __init__(self, directory, *, me: str, peer: str, timeout: float | None = 30.0,
                 use_events: bool = True, poll: float = 0.002, wake: str | None = None):
        self.dir = Path(directory)
        self.wake = wake or link_wait()
        self.me, self.peer = me, peer
        self.timeout = timeout
        self.poll = poll
        self._cond = threading.Condition()
        self._generation = 0
        self._observer = None
        self._inotify = None
        self._locks: dict[str, int] = {}
        self._paths: dict[str, str] = {}      # name -> path text (see _p)
        self._busy_fd = None
        check_directory(self.dir)
        if use_events and inotify_init is not None:
            try:
                self._inotify = _InotifyWaiter(self.dir, named=self.wake != "any")
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
        for fd in self._locks.values():       # closing releases the lock; the file
            os.close(fd)                      # stays (see ESTAR_LOCK)
        self._locks.clear()

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

    def _p(self, name: str) -> str:
        """The path of ``name`` as text, made once: a round trip uses a dozen,
        and building each as a Path cost more than the system calls."""
        p = self._paths.get(name)
        if p is None:
            p = self._paths[name] = os.path.join(self.dir, name)
        return p

    def exists(self, name: str) -> bool:
        """Is there anything under ``name`` (a dangling link counts: it holds the name)."""
        try:
            os.lstat(self._p(name))
            return True
        except OSError:                       # as os.path.lexists: absent, or unreachable
            return False

    # --- locks (QUIRKS M14, M17) -----------------------------------------------
    def lock(self, name: str) -> None:
        """Hold an exclusive lock file for the life of this process (two ESTARs on
        one directory would steal each other's answers).  The file is kept."""
        fd = _open_lock_file(self.dir / name)
        # A peer's held() probe takes a shared lock for an instant; a holder keeps its
        # lock for life.  Refused only if still locked after LOCK_PROBE_GRACE_S (a
        # probe caught at the wrong instant had made a starting NSTAR give up).
        deadline = time.monotonic() + LOCK_PROBE_GRACE_S
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except OSError as exc:
                if exc.errno not in (errno.EAGAIN, errno.EACCES):
                    os.close(fd)
                    raise
                if time.monotonic() >= deadline:
                    os.close(fd)
                    raise LockedError(f"another {self.me} is already running on "
                                      f"{self.dir} (it holds {name}); stop it first") from None
                time.sleep(0.005)
        try:                                  # who holds it, for a person looking
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        except OSError:                       # read-only: another user's lock file
            pass
        self._locks[name] = fd

    def held(self, name: str) -> bool:
        """Does some process hold the lock file ``name`` now?"""
        try:
            fd = os.open(self.dir / name, os.O_RDONLY | os.O_NONBLOCK | _NOFOLLOW | _CLOEXEC)
        except OSError:                       # absent (never ran here) or not a file
            return False
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                return False
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
            return False
        except BlockingIOError:
            return True
        finally:
            os.close(fd)                      # and with it our probe's lock

    # --- the busy lock (QUIRKS M14) ---------------------------------------------
    def open_busy(self, name: str) -> None:
        """Create (or open) the busy-lock file ``name`` that :meth:`busy` locks
        while a command is being carried out; done once, at start."""
        self._busy_fd = _open_lock_file(self.dir / name)

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
                fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | _NOFOLLOW | _CLOEXEC)
            except FileNotFoundError:         # the peer has never run here
                return True
            except OSError as exc:
                if exc.errno == errno.ELOOP:  # not NSTAR's: no NSTAR can hold it
                    return True
                raise
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
    def _wait(self, done, describe, timeout, events=_InotifyWaiter.ANY) -> None:
        limit = self.timeout if timeout is None else timeout
        deadline = None if not limit else time.monotonic() + limit
        if self._inotify is not None:
            self._inotify.arm(events)
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
        self._wait(lambda: self.exists(name), lambda t: self.not_written(name, t), timeout,
                   _InotifyWaiter.APPEAR)

    def not_written(self, name: str, t: float) -> str:
        """What a wait for ``name`` says when it gives up after ``t`` seconds."""
        return (f"no {name} from {self.peer} after {t:g} s — is {self.peer.lower()} running "
                f"on this jhdata directory ({self.dir})?")

    def wait_gone(self, name: str, timeout: float | None = None) -> None:
        """Wait until ``name`` has been taken by the other program."""
        self._wait(lambda: not self.exists(name), lambda t: self._not_taken(name, t), timeout,
                   _InotifyWaiter.GONE)

    def _not_taken(self, name: str, t: float) -> str:
        return (f"{name} not taken by {self.peer} after {t:g} s — is {self.peer.lower()} "
                f"running on this jhdata directory ({self.dir})?")

    def wait_held(self, name: str, timeout: float | None = None) -> None:
        """Wait until some process holds the lock file ``name`` (the peer runs)."""
        self._wait(lambda: self.held(name),
                   lambda t: (f"no {self.peer} on {self.dir} after {t:g} s — start "
                              f"{self.peer.lower()} on this jhdata directory"), timeout)

    # --- moving files ---------------------------------------------------------
    def write_temp(self, temp_name: str, data: bytes) -> None:
        """Write ``data`` as the new file ``temp_name``.  Whatever already holds
        that name (a file left by a killed run, or a link planted there) is set
        aside, never opened."""
        for _ in range(100):
            try:
                _write_new(self._p(temp_name), data)
                return
            except FileExistsError:
                self.set_aside(temp_name, "in the way")
        raise _DirError(errno.EEXIST, f"{self.dir / temp_name} keeps reappearing; "
                                      f"another program writes it")

    def publish(self, temp_name: str, name: str, data: bytes,
                timeout: float | None = None) -> None:
        """Write ``data`` as ``temp_name``, then rename it to ``name`` — but never
        over an unread ``name``: wait until it is gone, then rename atomically
        (refusing an existing target).  Gives up after the timeout with
        :class:`LinkTimeout`, the temporary left in place."""
        self.write_temp(temp_name, data)
        self.publish_written(temp_name, name, timeout)

    def publish_written(self, temp_name: str, name: str, timeout: float | None = None) -> None:
        """The second half of :meth:`publish`: rename ``temp_name``, written
        earlier by :meth:`write_temp`, to ``name`` once ``name`` is free."""
        tmp, dst = self._p(temp_name), self._p(name)
        limit = self.timeout if timeout is None else timeout
        deadline = None if not limit else time.monotonic() + limit
        while True:
            try:                              # the rename itself refuses an unread name
                _rename_noreplace(tmp, dst)
                return
            except FileExistsError:           # unread: wait until it is taken
                pass
            left = None if deadline is None else deadline - time.monotonic()
            if left is not None and left <= 0:
                raise LinkTimeout(self._not_taken(name, limit))
            try:
                self.wait_gone(name, left if left is not None else 0)
            except LinkTimeout:
                raise LinkTimeout(self._not_taken(name, limit)) from None

    def publish_replace(self, temp_name: str, name: str, data: bytes) -> None:
        """Write ``data`` as ``temp_name`` and rename it over ``name`` (PNPL's
        DELETE + RENAM of POSIT.DT, done atomically)."""
        self.write_temp(temp_name, data)
        try:
            os.replace(self._p(temp_name), self._p(name))
        except BaseException:                 # a Ctrl-C too: leave no temporary
            self.delete(temp_name)
            raise

    def read(self, name: str) -> bytes:
        """The bytes of the protocol file ``name``: a regular file of at most the
        size its format allows (:class:`NotAProtocolFile` otherwise)."""
        limit, expect = PROTOCOL_SIZES.get(name, (1 << 20, None))
        return read_regular(self._p(name), limit, expect)

    def take(self, name: str) -> bytes:
        """Read ``name`` and delete it (OPEN, READ, CLOSE, DELETE)."""
        data = self.read(name)
        os.unlink(self._p(name))
        return data

    def delete(self, name: str) -> bool:
        """RDOS DELETE: no error when the file is absent."""
        try:
            os.unlink(self._p(name))
            return True
        except FileNotFoundError:
            return False

    def rename(self, old: str, new: str) -> None:
        os.replace(self._p(old), self._p(new))

    # --- STALE/ ----------------------------------------------------------------
    def _stale_fd(self) -> int:
        """STALE/ opened as a directory, never through a link; created if absent."""
        stale = self.dir / STALE_DIR
        try:
            os.mkdir(stale, DIR_MODE)
        except FileExistsError:
            pass
        try:
            fd = os.open(stale, os.O_RDONLY | os.O_DIRECTORY | _NOFOLLOW | _CLOEXEC)
        except OSError as exc:
            if exc.errno in (errno.ELOOP, errno.ENOTDIR):
                what = "a symbolic link" if os.path.islink(stale) else "not a directory"
                raise _DirError(exc.errno, f"{stale} is {what}, not a plain directory; "
                                           f"nothing is kept through it — remove it") from None
            raise
        st = os.fstat(fd)
        mode = stat.S_IMODE(st.st_mode)
        if st.st_uid == os.geteuid() and mode | DIR_MODE != mode:
            try:                              # the group sets aside into it too
                os.fchmod(fd, mode | DIR_MODE)
            except OSError:
                pass
        return fd

    def _into_stale(self, src: str, label: str) -> Path | None:
        """Move ``src`` (whatever it is: file, link, FIFO; never followed, never
        copied) to ``STALE/<label>.<n>``; None if it vanished meanwhile."""
        sfd = self._stale_fd()
        try:
            n = 0
            while True:                 # never replace: both programs sweep into STALE/
                dest = f"{label}.{n}"
                try:
                    _rename_noreplace(self.dir / src, dest, dst_dir_fd=sfd)
                    return self.dir / STALE_DIR / dest
                except FileExistsError:
                    n += 1
                except FileNotFoundError:     # taken or swept by the other program
                    return None
        finally:
            os.close(sfd)

    def set_aside(self, name: str, why: str = "stale", as_name: str | None = None) -> Path | None:
        """Move a stale ``name`` into ``STALE/`` instead of deleting it, so
        nothing is lost; returns where it went (named after ``as_name`` if given)."""
        if not self.exists(name):
            return None
        return self._into_stale(name, f"{as_name or name}.{time.strftime('%Y%m%d-%H%M%S')}")

    def set_aside_bad(self, name: str, label: str) -> Path | None:
        """Move the file ``name`` that failed its checks to ``STALE/<label>.<n>``."""
        return self._into_stale(name, label)

    def keep(self, label: str, data: bytes) -> Path:
        """Keep ``data`` (bytes already taken from a file) as a new
        ``STALE/<label>.<n>``, created exclusively: never through a link."""
        sfd = self._stale_fd()
        try:
            n = 0
            while True:
                try:
                    _write_new(f"{label}.{n}", data, dir_fd=sfd)
                    return self.dir / STALE_DIR / f"{label}.{n}"
                except FileExistsError:
                    n += 1
        finally:
            os.close(sfd)
