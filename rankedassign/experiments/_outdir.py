"""The report directory: recognised by content, locked for the run, replaced atomically.

A user's files are never at stake:

* ``--force`` replaces a directory only if it *is* an earlier report: its ``manifest.json``
  has this module's schema (or the exact key set of the manifests written before the schema
  existed), and every entry of the directory is a regular file that report wrote. Anything else
  is refused, ``--force`` or not.
* A run holds an exclusive lock (``fcntl.flock`` on ``.<out>.lock`` beside the report) from
  its checks to its last move, so a second run into the same ``--out`` is refused and told
  which run holds it.
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
def lock_path(out: Path) -> Path:
    """The lock file of report directory ``out``: ``.<name>.lock`` beside it."""
    return out.parent / f".{out.name}.lock"


def _holder(path: Path) -> str:
    try:
        info = json.loads(path.read_text())
        return (f"pid {info['pid']} on {info['host']}, started {info['started']}: "
                f"{info['command']}")
    except (OSError, ValueError, KeyError, TypeError):
        return "a run whose details cannot be read"


@contextmanager
def run_lock(out: Path, command: str):
    """Hold the exclusive lock of ``out`` for the duration of the ``with`` block.

    Raises
    ------
    ReproduceError
        If another run holds it, naming that run (pid, host, start, command).
    """
    path = lock_path(out)
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o644)
        except OSError as exc:
            raise ReproduceError(
                f"cannot write the report to {str(out)!r}: cannot create its lock file "
                f"{str(path)!r} ({exc.strerror or exc})"
            ) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise ReproduceError(
                f"another run is writing the report to {str(out)!r} ({_holder(path)}); wait "
                "for it to finish or choose another --out"
            ) from None
        # the file may have been unlinked by the run that held it just before: lock the file
        # that is at the path, not an orphaned inode
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(path))
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        info = {"pid": os.getpid(), "host": socket.gethostname(), "command": command,
                "started": datetime.datetime.now().strftime("%Y-%m-%d %H:%M:%S")}
        os.ftruncate(fd, 0)
        os.write(fd, json.dumps(info).encode())
        yield path
    finally:
        try:
            os.unlink(path)
        except OSError:  # pragma: no cover - parent made read-only during the run
            pass
        os.close(fd)


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
