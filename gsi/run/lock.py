"""The lock of an output directory: one run (or resume) owns ``--out`` at a time.

A run holds ``<out>/gsi.lock`` for its lifetime: a JSON line with its PID, host, start
time and command, on a file it also holds an ``flock`` on. The file appears complete
and locked at once (written and locked under a temporary name, then hard-linked into
place: a link fails if the name exists, on local and network file systems alike).

Another run that finds the file

* is refused while the holder lives (its ``flock`` is held, or -- where the file system
  has no ``flock`` -- its PID is alive on this host): one line naming PID, host and
  start;
* takes the lock over, with a warning, when the holder is gone: nobody holds the
  ``flock`` (the kernel drops it when a process dies, ``kill -9`` included), or -- without
  ``flock`` -- the PID no longer exists on this host (a lock of another host is then never
  taken over: delete the file if that run is gone).

The lock is removed when the run ends, normally or by an error, and a killed run's is
found stale as above. Under MPI only rank 0 locks (:func:`gsi.run.outdir.output_dir`
broadcasts the outcome).
"""
from __future__ import annotations

import datetime
import errno
import json
import os
import pathlib
import socket
import sys
import time
import warnings

try:
    import fcntl
except ImportError:          # not POSIX: the PID test alone
    fcntl = None

NAME = "gsi.lock"


class LockRefused(Exception):
    """``--out`` is owned by a live run; ``str()`` names it."""


class OutputLock:
    """The lock of ``out`` held by this process (see the module docstring)."""

    def __init__(self, path: pathlib.Path, fd: int):
        self.path, self.fd = path, fd

    def release(self) -> None:
        """Remove the lock file (if it is still ours) and drop the ``flock``."""
        if self.fd is None:
            return
        try:
            if os.stat(self.path).st_ino == os.fstat(self.fd).st_ino:
                os.unlink(self.path)
        except OSError:
            pass
        try:
            os.close(self.fd)
        except OSError:
            pass
        self.fd = None

    def __del__(self):
        try:
            self.release()
        except Exception:      # at interpreter shutdown
            pass


def _holder_text(info: dict) -> str:
    return (f"pid {info.get('pid', '?')} on host {info.get('host', '?')}, started "
            f"{info.get('started', '?')}")


def _try_flock(fd: int) -> bool | None:
    """True: locked now; False: someone holds it; None: no flock on this file system."""
    if fcntl is None:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return True
    except OSError as exc:
        if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
            return False
        return None


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:      # someone else's process
        return True
    return True


def _read_info(fd: int) -> dict:
    try:
        raw = os.pread(fd, 4096, 0).decode("utf-8", "replace")
        info = json.loads(raw)
        return info if isinstance(info, dict) else {}
    except (OSError, ValueError):
        return {}


def acquire(out: pathlib.Path, *, host: str | None = None) -> OutputLock:
    """Take the lock of ``out`` (an existing directory); raises :class:`LockRefused`
    (one line) when a live run holds it, warns when it replaces a stale one."""
    host = host or socket.gethostname()
    path = out / NAME
    info = dict(pid=os.getpid(), host=host,
                started=datetime.datetime.now(datetime.timezone.utc)
                .strftime("%Y-%m-%d %H:%M:%S UTC"),
                command=" ".join(sys.argv))
    tmp = out / f".{NAME}.{host}.{os.getpid()}"
    fd = os.open(tmp, os.O_RDWR | os.O_CREAT | os.O_TRUNC, 0o644)
    try:
        os.write(fd, (json.dumps(info) + "\n").encode())
        own_flock = _try_flock(fd)
        for _ in range(20):
            try:
                os.link(tmp, path)
                return OutputLock(path, fd)
            except FileExistsError:
                pass
            except OSError as exc:       # no hard links here: an exclusive create
                if exc.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP,
                                     errno.EXDEV):
                    raise
                lock = _create_exclusive(path, info)
                if lock is not None:
                    return lock
            _take_over_if_stale(path, host, own_flock)
        raise LockRefused(f"--out = {str(out)!r}: cannot take its lock {path} (it keeps "
                          "changing); is another run starting there?")
    except BaseException:
        os.close(fd)
        raise
    finally:
        try:
            tmp.unlink()
        except OSError:
            pass


def _create_exclusive(path: pathlib.Path, info: dict) -> OutputLock | None:
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644)
    except FileExistsError:
        return None
    _try_flock(fd)
    os.write(fd, (json.dumps(info) + "\n").encode())
    return OutputLock(path, fd)


def _take_over_if_stale(path: pathlib.Path, host: str, own_flock) -> None:
    """``path`` exists: return if it vanished or was stale (removed: try again); raise
    :class:`LockRefused` if its holder lives."""
    try:
        fd = os.open(path, os.O_RDWR)
    except FileNotFoundError:
        return
    try:
        info = _read_info(fd)
        if not info:                      # being written by an exclusive create: wait
            time.sleep(0.1)
            info = _read_info(fd)
        locked = _try_flock(fd)
        same_host = info.get("host") == host
        pid = info.get("pid")
        if locked is False:
            raise LockRefused(_refusal(path, info))
        if locked is None or own_flock is None:     # no flock: the PID on this host
            if not same_host or not isinstance(pid, int) or (
                    pid != os.getpid() and _pid_alive(pid)):
                raise LockRefused(_refusal(path, info, unsure=not same_host))
        try:                              # still the file we judged?
            if os.stat(path).st_ino != os.fstat(fd).st_ino:
                return
        except FileNotFoundError:
            return
        why = ("no process holds it" if locked else f"pid {pid} no longer exists")
        warnings.warn(f"--out = {str(path.parent)!r}: a stale lock ({_holder_text(info)}; "
                      f"{why}) replaced",
                      stacklevel=2)
        os.unlink(path)
    finally:
        os.close(fd)


def _refusal(path: pathlib.Path, info: dict, unsure: bool = False) -> str:
    tail = ("; if that run is gone, delete the lock file and start again" if unsure
            else "; wait for it to end, stop it, or give another --out")
    return (f"--out = {str(path.parent)!r}: in use by another gsi run "
            f"({_holder_text(info)}; lock {path}){tail}")
