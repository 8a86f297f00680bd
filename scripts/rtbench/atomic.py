"""Writers that never leave a half-written file: each writes a temporary file
in the destination's directory and renames it over the destination (atomic on
POSIX), so a reader, or a run stopped with Ctrl-C, sees the old file or the
new one, never a torn one."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """Yields a temporary path beside `path`; renames it to `path` if the block
    succeeds and removes it if the block raises (KeyboardInterrupt included)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_text(path: Path, text: str) -> Path:
    """Writes UTF-8 text with '\\n' line ends, atomically."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
    return Path(path)


def write_json(path: Path, value) -> Path:
    """Writes indented JSON (keys in insertion order), atomically; values JSON
    has no type for (TOML dates in a profile, paths) are written as text."""
    return write_text(path, json.dumps(value, indent=2, ensure_ascii=False, default=str) + "\n")
