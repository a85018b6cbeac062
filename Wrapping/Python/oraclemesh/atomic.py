# SPDX-License-Identifier: GPL-3.0-or-later
"""Atomic file output: write to a hidden temporary name in the destination folder, then rename.

A run that fails or is interrupted while writing leaves the previous file at the destination intact
(a rename within one folder is atomic on POSIX) and no half-written file under the real name."""
import contextlib
import os
import uuid

from .errors import OracleMeshError


def _reason(error):
    return error.strerror or str(error)


def make_folder(path):
    """Creates the folder of `path`; OracleMeshError naming `path` when that is impossible."""
    folder = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as e:
        raise OracleMeshError(f"{path}: could not be written: cannot create the folder {folder} ({_reason(e)})") \
            from None
    return folder


@contextlib.contextmanager
def atomic_output(path):
    """Yields a temporary path next to `path` (same extension, so writers that look at it agree);
    when the block succeeds the temporary file replaces `path`, else it is removed. OSErrors become
    OracleMeshError naming `path`."""
    folder = make_folder(path)
    name = os.path.basename(path)
    stem, ext = os.path.splitext(name)
    temporary = os.path.join(folder, f".{stem}.{os.getpid()}-{uuid.uuid4().hex[:8]}.partial{ext}")
    try:
        yield temporary
        if not os.path.isfile(temporary):
            raise OracleMeshError(f"{path}: could not be written (the writer produced no file)")
        os.replace(temporary, path)
    except OSError as e:
        raise OracleMeshError(f"{path}: could not be written: {_reason(e)}") from None
    finally:
        with contextlib.suppress(OSError):
            os.remove(temporary)


def write_text(path, text):
    """Writes a UTF-8 text file atomically."""
    with atomic_output(path) as temporary:
        with open(temporary, "w", encoding="utf-8") as f:
            f.write(text)
