"""Committed run directories: a run packed as one compressed tar archive
(data/reference-runs/NAME.tar.xz, see data/reference-runs/README.md) reads like the directory
it holds.

The report and compare take a run directory or such an archive. An archive
must hold exactly one top-level directory (the run directory, under its own
name, which the report prints and uses in its file references) and nothing
but directories and regular files below it, none outside it; it is unpacked
into a temporary directory that lives as long as the `unpacked` block, so the
report of an archive is the report of its directory, byte for byte.
"""

from __future__ import annotations

import tarfile
import tempfile
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path, PurePosixPath

from rtbench.load import RunDataError

# What tarfile opens by its compression: xz for committed runs (the smallest),
# gzip also accepted.
ARCHIVE_SUFFIXES = (".tar.xz", ".txz", ".tar.gz", ".tgz")

# tarfile's extraction filter (Python 3.12, and 3.8-3.11 security updates that
# backport it; Python 3.14 makes "data" the default and 3.12-3.13 warn when no
# filter is given). Where this Python has it, "data" refuses, at extraction,
# what would land outside the destination, as _run_root's checks before it
# do; where it has not (Debian 12's 3.11.2), those checks alone guard the
# extraction, and passing the argument would be a TypeError.
_EXTRACT_FILTER = {"filter": "data"} if hasattr(tarfile, "data_filter") else {}


def is_archive(path: Path) -> bool:
    return Path(path).name.endswith(ARCHIVE_SUFFIXES)


def _run_root(archive: Path, members: list[tarfile.TarInfo]) -> str:
    """The one top-level directory every member lies in; a RunDataError for
    anything that could write outside it or is not a plain file."""
    roots = set()
    for m in members:
        parts = PurePosixPath(m.name).parts
        if not parts or m.name.startswith("/") or ".." in parts:
            raise RunDataError(f"{archive}: member {m.name!r} lies outside the archive's directory")
        if not (m.isfile() or m.isdir()):
            raise RunDataError(f"{archive}: member {m.name!r} is not a regular file or directory")
        roots.add(parts[0])
    if len(roots) != 1:
        raise RunDataError(f"{archive}: must hold exactly one run directory, holds {len(roots)} top-level entries")
    root = roots.pop()
    if any(PurePosixPath(m.name).parts == (root,) and not m.isdir() for m in members):
        raise RunDataError(f"{archive}: its top-level entry {root!r} is not a directory")
    return root


def unpack(archive: Path, into: Path) -> Path:
    """Unpacks a run archive into `into`; the run directory's path."""
    try:
        with tarfile.open(archive, "r:*") as tar:
            members = tar.getmembers()
            root = _run_root(archive, members)
            for m in members:
                tar.extract(m, into, set_attrs=False, **_EXTRACT_FILTER)
    except FileNotFoundError:
        raise RunDataError(f"{archive}: no such file") from None
    except (tarfile.TarError, EOFError, OSError) as e:
        raise RunDataError(f"{archive}: not a readable tar archive: {e}") from None
    return into / root


@contextmanager
def unpacked(paths: list[Path]) -> Iterator[list[Path]]:
    """The given run directories, each archive among them replaced by the
    directory it holds (unpacked for the duration of the block)."""
    with ExitStack() as stack:
        dirs = []
        for path in map(Path, paths):
            if is_archive(path):
                tmp = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="rtbench-run-")))
                dirs.append(unpack(path, tmp))
            else:
                dirs.append(path)
        yield dirs
