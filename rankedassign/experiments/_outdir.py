"""The report directory: recognised by content, locked for the run, replaced atomically.

A user's files are never at stake:

* ``--force`` replaces a directory only if it *is* an earlier report: its ``manifest.json``
  has this module's schema (or the exact key set of the manifests written before the schema
  existed), and every entry of the directory is a regular file that report wrote. Anything else
  is refused, ``--force`` or not.
* A run holds an exclusive lock (``.<out>.lock`` beside the report, created with ``O_EXCL |
  O_NOFOLLOW`` and held with ``fcntl.flock``) from its checks to its last move, so a second run
  into the same ``--out`` is refused and told which run holds it. Whatever else is at the
  lock's place (a user's file, a symbolic link, a directory) is refused and never written,
  followed or removed; a lock record left by a killed run is recognised (its schema, no
  process holding it) and replaced. A run removes its lock only if the file there is still
  the one it created.
* The finished report is moved into place by one atomic ``rename``: ``renameat2`` with
  ``RENAME_NOREPLACE`` when ``out`` did not exist, ``RENAME_EXCHANGE`` when it replaces an
  earlier report. The directory that was at ``out`` is checked again at that moment; if it
  changed while the run worked, or appeared, it is left alone and the finished report is kept
  beside it under a visible name that the error names. The earlier report is then removed file
  by file (only the files its manifest lists), never by a recursive delete.
* A run that was killed (SIGKILL, a power cut) leaves its hidden ``.<out>.partial-*``
  directory. The next run into the same ``--out`` holds the lock, which proves that no run
  writes there, and removes each one that carries the owner record of a run (``.run``), saying
  so.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import datetime
import errno
import fcntl
import json
import os
import secrets
import socket
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path

from .registry import ReproduceError

#: ``schema`` of the manifests this version writes.
SCHEMA = "rankedassign-report/1"
MANIFEST = "manifest.json"
#: Owner record inside a partial report (removed before the report is moved into place).
OWNER = ".run"
#: The keys of the manifests written before ``schema`` existed (exactly these).
_LEGACY_KEYS = frozenset({"command", "version", "mode", "seed", "studies", "executor", "started",
                          "seconds", "python", "platform", "cpu_count"})

_RENAME_NOREPLACE, _RENAME_EXCHANGE = 1, 2
_AT_FDCWD = -100


def _load_renameat2():
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):  # pragma: no cover - not glibc
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


_renameat2_fn = _load_renameat2()


def renameat2(src, dst, flags: int) -> bool:
    """``renameat2(src, dst, flags)``; ``False`` where the platform or file system lacks it.

    Raises :class:`OSError` for every other failure (``EEXIST`` when ``RENAME_NOREPLACE``
    finds ``dst``, ``EBUSY`` for a mount point, ...).
    """
    if _renameat2_fn is None:  # pragma: no cover - not glibc
        return False
    r = _renameat2_fn(_AT_FDCWD, os.fsencode(src), _AT_FDCWD, os.fsencode(dst), flags)
    if r == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP):  # pragma: no cover - old kernel/FS
        return False
    raise OSError(err, os.strerror(err), os.fspath(src), None, os.fspath(dst))


# --------------------------------------------------------------------------- recognition
def _entries(d: Path) -> dict:
    """``{name: (mode, size, mtime_ns)}`` of the entries of ``d`` (links not followed)."""
    out = {}
    with os.scandir(d) as it:
        for e in it:
            st = e.stat(follow_symlinks=False)
            out[e.name] = (st.st_mode, st.st_size, st.st_mtime_ns)
    return out


def fingerprint(d: Path):
    """What must be unchanged for ``d`` to be the directory checked before the run."""
    st = os.lstat(d)
    return (st.st_dev, st.st_ino, tuple(sorted(_entries(d).items())))


def _report_names(manifest: dict) -> set | None:
    """The file names the report of ``manifest`` may hold, or None if it is not ours."""
    if manifest.get("schema") == SCHEMA:
        files = manifest.get("files")
        if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
            return None
        return {*files, MANIFEST}
    if set(manifest) == _LEGACY_KEYS and isinstance(manifest.get("studies"), list):
        names = {MANIFEST, "report.md", "config.json"}
        for s in manifest["studies"]:
            if not isinstance(s, str):
                return None
            names |= {f"{s}.json", f"{s}_runs.json", f"{s}.csv"}
        return names
    return None


def not_a_report(d: Path) -> str | None:
    """Why ``d`` (an existing directory) is not an earlier report, or None if it is one.

    An empty directory counts as replaceable (nothing in it can be lost).
    """
    entries = _entries(d)
    if not entries:
        return None
    if MANIFEST not in entries:
        return f"it is not empty and holds no {MANIFEST} of an earlier report"
    if not stat.S_ISREG(entries[MANIFEST][0]):
        return f"its {MANIFEST} is not a regular file"
    try:
        manifest = json.loads((d / MANIFEST).read_text())
    except (OSError, ValueError, UnicodeDecodeError):
        manifest = None
    names = _report_names(manifest) if isinstance(manifest, dict) else None
    if names is None:
        return f"its {MANIFEST} is not the manifest of a rankedassign report"
    legacy = manifest.get("schema") != SCHEMA
    for name, (mode, _, _) in sorted(entries.items()):
        ours = name in names or (legacy and name.endswith(".png"))
        if not ours:
            return f"it holds {name!r}, which is not part of the report its {MANIFEST} lists"
        if not stat.S_ISREG(mode):
            return f"{name!r} in it is not a regular file"
    return None


# --------------------------------------------------------------------------- the lock
#: ``schema`` of the lock records this version writes.
LOCK_SCHEMA = "rankedassign-lock/1"
#: The keys of the lock records written before ``schema`` existed (exactly these).
_LEGACY_LOCK_KEYS = frozenset({"pid", "host", "command", "started"})
# A lock record is a few hundred bytes; a file at the lock's place that is larger is not one
# (and is not read whole).
_LOCK_MAX_BYTES = 1 << 16
# Attempts at creating the lock when a stale one is removed between them (each attempt that
# fails removes one stale lock or refuses, so two are enough unless other runs race).
_LOCK_ATTEMPTS = 8


def lock_path(out: Path) -> Path:
    """The lock file of report directory ``out``: ``.<name>.lock`` beside it."""
    return out.parent / f".{out.name}.lock"


def _lock_record(data: bytes) -> dict | None:
    """The lock record in ``data``, or None unless it is one this program writes (or wrote)."""
    try:
        info = json.loads(data.decode())
    except (UnicodeDecodeError, ValueError):
        return None
    if not isinstance(info, dict):
        return None
    if info.get("schema") == LOCK_SCHEMA and _LEGACY_LOCK_KEYS | {"schema", "token"} <= set(info):
        return info
    if set(info) == _LEGACY_LOCK_KEYS:  # written before the schema existed
        return info
    return None


def _describe_holder(info: dict | None) -> str:
    try:
        return (f"pid {info['pid']} on {info['host']}, started {info['started']}: "
                f"{info['command']}")
    except (KeyError, TypeError):
        return "a run whose details cannot be read"


class RunLock:
    """The lock of one run, created by :func:`run_lock`.

    Attributes
    ----------
    path : Path
        ``.<out>.lock`` beside the report directory.
    notes : list of str
        What was done on the way (a stale lock of a killed run removed), for the user.
    """

    def __init__(self, path: Path, fd: int, notes: list[str]):
        self.path, self.notes = path, notes
        self._fd = fd
        self._stat = os.fstat(fd)

    def release(self) -> None:
        """Remove the lock file, if the file at its place is still the one this run made.

        Idempotent, and safe to call from a signal handler: it only compares inodes, unlinks
        and closes; a file or link that someone put at the lock's place meanwhile is left.
        """
        fd, self._fd = self._fd, None
        if fd is None:
            return
        try:
            st = os.lstat(self.path)
            if stat.S_ISREG(st.st_mode) and os.path.samestat(st, self._stat):
                os.unlink(self.path)
        except OSError:  # pragma: no cover - gone already, or the parent made read-only
            pass
        finally:
            os.close(fd)


def _foreign(out: Path, path: Path, what: str) -> ReproduceError:
    return ReproduceError(
        f"cannot write the report to {str(out)!r}: {str(path)!r}, where its lock goes, {what}, "
        "not a lock of rankedassign reproduce; it was left as it is: move it away or choose "
        "another --out"
    )


def _create_lock(path: Path) -> int | None:
    """The descriptor of a new lock file at ``path`` (locked), or None if something is there."""
    flags = (os.O_RDWR | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0)
             | getattr(os, "O_CLOEXEC", 0))
    try:
        fd = os.open(path, flags, 0o644)
    except FileExistsError:
        return None
    try:
        # O_EXCL made the file: no other run has it open yet, so this cannot block
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:  # a file system without flock (ENOLCK): the file made here goes again
        os.unlink(path)
        os.close(fd)
        raise
    return fd


def _inspect_lock(out: Path, path: Path) -> str | None:
    """Deal with what is at ``path`` when the lock cannot be created there.

    Returns a note if it was a stale lock of a killed run, now removed (or None if the path
    is free again); raises :class:`ReproduceError` for a live run's lock or anything that is
    not a lock of this program, which is never touched.
    """
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None  # removed meanwhile: try again
    if stat.S_ISLNK(st.st_mode):
        raise _foreign(out, path, "is a symbolic link")
    if stat.S_ISDIR(st.st_mode):
        raise _foreign(out, path, "is a directory")
    if not stat.S_ISREG(st.st_mode):
        raise _foreign(out, path, "is not a regular file")
    try:
        # O_NOFOLLOW and O_NONBLOCK: whatever is swapped in after the lstat is neither followed
        # nor waited for (a FIFO); the fstat below sees what was opened
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | os.O_NONBLOCK
                     | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        return None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise _foreign(out, path, "is a symbolic link") from None
        raise ReproduceError(f"cannot write the report to {str(out)!r}: cannot read what is at "
                             f"its lock's place, {str(path)!r} ({exc.strerror or exc})") from None
    try:
        fst = os.fstat(fd)
        if not stat.S_ISREG(fst.st_mode):
            raise _foreign(out, path, "is not a regular file")
        info = _lock_record(os.read(fd, _LOCK_MAX_BYTES)) if fst.st_size <= _LOCK_MAX_BYTES \
            else None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            # a live run holds it (its record may still be being written)
            raise ReproduceError(
                f"another run is writing the report to {str(out)!r} ({_describe_holder(info)}); "
                "wait for it to finish or choose another --out"
            ) from None
        if info is None:
            raise _foreign(out, path, "is a file that is not a lock record")
        # Our record, and no process holds it: the run that made it was killed (a flock goes
        # with its process). Removed only if the path still names the file just read.
        try:
            same = os.path.samestat(os.lstat(path), fst)
        except FileNotFoundError:
            return None
        if not same:
            return None
        try:
            os.unlink(path)
        except OSError as exc:  # another user's lock in a sticky directory
            raise ReproduceError(
                f"cannot write the report to {str(out)!r}: its lock {str(path)!r} was left by a "
                f"run that was killed (pid {info.get('pid', '?')}), and it cannot be removed "
                f"({exc.strerror or exc}); remove it or choose another --out") from None
        return (f"removed {str(path)!r}, the lock of an earlier run into the same --out that was "
                f"killed (pid {info.get('pid', '?')})")
    finally:
        os.close(fd)


@contextmanager
def run_lock(out: Path, command: str):
    """Hold the exclusive lock of ``out`` for the duration of the ``with`` block.

    The lock is a file ``.<out>.lock`` beside ``out``, created exclusively (``O_CREAT |
    O_EXCL | O_NOFOLLOW``: never through a link, never over an existing file) and locked with
    ``flock``; it holds a record of the run (schema, pid, host, start, command and a random
    token). At the end it is removed only if the file at its place is still the one this run
    created (same inode). A lock record of a killed run (no process holds its ``flock``) is
    removed and the lock is taken, with a note; anything else at the lock's place (a user's
    file, a symbolic link, a directory) is refused and left as it is.

    Parameters
    ----------
    out : Path
        The report directory.
    command : str
        The command line recorded in the lock (shown to a run that is refused).

    Yields
    ------
    RunLock
        The lock held (its ``path`` and ``notes``).

    Raises
    ------
    ReproduceError
        If another run holds it, naming that run (pid, host, start, command); if something
        that is not a lock of this program is at its place, naming the path; if it cannot be
        created.
    """
    path = lock_path(out)
    notes: list[str] = []
    for _ in range(_LOCK_ATTEMPTS):
        try:
            fd = _create_lock(path)
        except OSError as exc:
            if exc.errno == errno.ELOOP:  # pragma: no cover - O_EXCL reports EEXIST first
                raise _foreign(out, path, "is a symbolic link") from None
            raise ReproduceError(
                f"cannot write the report to {str(out)!r}: cannot create its lock file "
                f"{str(path)!r} ({exc.strerror or exc})"
            ) from None
        if fd is not None:
            break
        note = _inspect_lock(out, path)
        if note is not None:
            notes.append(note)
    else:  # pragma: no cover - other runs kept taking and dropping the lock
        raise ReproduceError(f"cannot write the report to {str(out)!r}: could not take its lock "
                             f"{str(path)!r}; try again")
    lock = RunLock(path, fd, notes)
    try:
        info = {"schema": LOCK_SCHEMA, "pid": os.getpid(), "host": socket.gethostname(),
                "command": command, "token": secrets.token_hex(16),
                "started": datetime.datetime.now().strftime("%Y-%m-%d %H:%M:%S")}
        os.write(fd, json.dumps(info).encode())
        yield lock
    finally:
        lock.release()


# --------------------------------------------------------------------------- partial reports
def new_partial(out: Path, command: str) -> Path:
    """A new hidden partial report directory beside ``out``, with its owner record."""
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
    # mkdtemp makes the directory private (0700); give the report the usual permissions.
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o777 & ~umask)
    (tmp / OWNER).write_text(json.dumps({"pid": os.getpid(), "host": socket.gethostname(),
                                         "command": command}))
    return tmp


def remove_files(d: Path, names=None) -> bool:
    """Unlink the regular files of ``d`` (only ``names`` if given), then ``rmdir`` it.

    Returns whether ``d`` is gone; a subdirectory or any other entry keeps it.
    """
    try:
        entries = _entries(d)
    except FileNotFoundError:
        return True
    for name, (mode, _, _) in entries.items():
        if stat.S_ISREG(mode) and (names is None or name in names):
            try:
                os.unlink(d / name)
            except FileNotFoundError:
                pass
    try:
        os.rmdir(d)
    except OSError:
        return False
    return True


def remove_stale_partials(out: Path) -> list[str]:
    """Remove the partial reports of killed runs into ``out``; call with its lock held.

    Only directories named ``.<out>.partial-*`` that hold a run's owner record are touched,
    and in them only regular files. Returns a note per directory removed (or left).
    """
    notes = []
    prefix = f".{out.name}.partial-"
    try:
        candidates = sorted(p for p in out.parent.iterdir() if p.name.startswith(prefix))
    except OSError:
        return notes
    for p in candidates:
        if p.is_symlink() or not p.is_dir() or not (p / OWNER).is_file():
            continue
        try:
            pid = json.loads((p / OWNER).read_text()).get("pid", "?")
        except (OSError, ValueError, AttributeError):
            pid = "?"
        if remove_files(p):
            notes.append(f"removed {str(p)!r}, the partial report of an earlier run into the "
                         f"same --out that was killed (pid {pid})")
        else:
            notes.append(f"left {str(p)!r}, the partial report of a killed run (pid {pid}): it "
                         "holds entries that are not files of a report")
    return notes


# --------------------------------------------------------------------------- the final move
def _stamp() -> str:
    return datetime.datetime.now().strftime("%Y%m%d-%H%M%S")


def keep_beside(tmp: Path, out: Path, kind: str) -> Path:
    """Move ``tmp`` to a visible unused name beside ``out`` (``tmp`` itself if that fails)."""
    base = out.parent / f"{out.name}.{kind}-{_stamp()}"
    for i in range(1000):
        kept = base if i == 0 else base.with_name(f"{base.name}-{i}")
        try:
            if not renameat2(tmp, kept, _RENAME_NOREPLACE):  # pragma: no cover - not glibc
                if kept.exists():
                    continue
                os.rename(tmp, kept)
            return kept
        except FileExistsError:
            continue
        except OSError:
            break
    return tmp


def place(tmp: Path, out: Path, before, names_before) -> list[str]:
    """Move the finished report ``tmp`` to ``out`` atomically; returns notes for the user.

    Parameters
    ----------
    tmp : Path
        The finished report (beside ``out``).
    out : Path
        Its destination.
    before : tuple or None
        :func:`fingerprint` of ``out`` when it was checked, or None if it did not exist.
    names_before : set or None
        The names of the entries of the earlier report when it was checked (only those are
        removed after the exchange).

    Raises
    ------
    ReproduceError
        If ``out`` changed during the run, appeared during it, or cannot be replaced; the
        finished report is then kept under a visible name beside ``out``, which the message
        names, and whatever is at ``out`` is left as it is.
    """
    (tmp / OWNER).unlink(missing_ok=True)

    def refuse(why: str):
        kept = keep_beside(tmp, out, "new")
        raise ReproduceError(f"{why}; the finished report is kept in {str(kept)!r}")

    if before is None:
        try:
            if not renameat2(tmp, out, _RENAME_NOREPLACE):  # pragma: no cover - not glibc
                if out.exists() or out.is_symlink():
                    raise FileExistsError(errno.EEXIST, "File exists")
                os.rename(tmp, out)  # never replaces a non-empty directory
        except FileExistsError:
            refuse(f"{str(out)!r} appeared while the run worked and was left as it is")
        except OSError as exc:
            refuse(f"could not move the finished report into {str(out)!r} "
                   f"({exc.strerror or exc})")
        return []
    try:
        now = fingerprint(out)
    except OSError:
        now = None
    if now != before:
        refuse(f"{str(out)!r} changed while the run worked and was left as it is")
    try:
        exchanged = renameat2(tmp, out, _RENAME_EXCHANGE)
    except OSError as exc:
        refuse(f"could not move the finished report into {str(out)!r} ({exc.strerror or exc})")
    if not exchanged:  # pragma: no cover - platforms without renameat2
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
        os.rename(out, old / out.name)
        try:
            os.rename(tmp, out)
        except OSError as exc:
            os.rename(old / out.name, out)
            os.rmdir(old)
            refuse(f"could not move the finished report into {str(out)!r} "
                   f"({exc.strerror or exc})")
        tmp_old = old / out.name
    else:
        tmp_old = tmp  # after the exchange the earlier report is at tmp's path
    # the earlier report: checked once more, then removed file by file
    try:
        same = fingerprint(tmp_old) == before
    except OSError:
        same = False
    notes = []
    if not (same and remove_files(tmp_old, names_before)):
        kept = keep_beside(tmp_old, out, "old")
        notes.append(f"the earlier report changed at the last moment and is kept in "
                     f"{str(kept)!r}")
    if not exchanged:  # pragma: no cover
        os.rmdir(tmp_old.parent)
    return notes
