"""Third-party file readers behind one guard: :func:`guarded`.

meshio, on a file it cannot parse, prints ``Error: Couldn't read file ...`` (and each
reader's complaint) and calls ``sys.exit(1)``; its ``SystemExit`` passes every
``except Exception``. gmsh raises plain ``Exception`` whose text may not even decode
(a binary file's bytes in its syntax-error line: ``UnicodeDecodeError``). Every reader
of a user's file (particle files, mesh walls, structure meshes) calls the library
through :func:`guarded`: whatever it raises, ``SystemExit`` included, becomes one
:class:`ReadFailed` with a one-line reason, and whatever it printed on the way is
swallowed. The caller turns that into a :class:`gsi.errors.GsiInputError` naming its key
and the file. ``KeyboardInterrupt`` passes through (Ctrl-C stays Ctrl-C).
"""
from __future__ import annotations

import contextlib
import io

__all__ = ["ReadFailed", "guarded", "reason"]


class ReadFailed(Exception):
    """A library could not read a file; ``str()`` is the one-line reason."""


def reason(exc: BaseException, printed: str = "") -> str:
    """One line saying why a reader failed (no traceback, no control characters);
    ``printed``: what the reader printed before it gave up."""
    if isinstance(exc, UnicodeDecodeError):
        text = (exc.object.decode("utf-8", "replace") if isinstance(exc.object, bytes)
                else "")
        bad = sum(1 for c in text if c == "\ufffd" or not c.isprintable())
        if not text or bad > 0.05 * len(text):      # the file's bytes, not a message
            text = "binary data where text was expected"
    elif isinstance(exc, SystemExit):
        said = [line for line in printed.splitlines() if line.strip()
                and "Couldn't read file" not in line]
        text = said[0] if said else "not a valid file of this format"
    else:
        text = str(exc) or type(exc).__name__
    text = " ".join("".join(c if c.isprintable() and c != "\ufffd" else " " for c in text)
                    .split())
    return text[:200] + (" ..." if len(text) > 200 else "")


def guarded(read, *args, keep: tuple = ()):
    """``read(*args)``, with its prints swallowed; any failure (``SystemExit`` and a C
    extension's errors included) raised as :class:`ReadFailed`, except ``keep`` (the
    caller's own error types, raised as they are) and ``KeyboardInterrupt``."""
    sink = io.StringIO()
    try:
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            return read(*args)
    except (KeyboardInterrupt, *keep):
        raise
    except BaseException as exc:      # SystemExit from meshio; anything from a C library
        raise ReadFailed(reason(exc, sink.getvalue())) from None
