"""The Python writers of the bench runner and the report (rtbench.atomic)
held to what docs/command-line.md promises of the raytracer's outputs
(section "Exit codes and outputs"): a full file system and a
read-only one leave the previous file and no temporary, and the error is the
system's (ENOSPC, EROFS). Needs a tmpfs of its own (root); skips otherwise."""

from __future__ import annotations

import errno
import os
import subprocess

import pytest

from rtbench import atomic


def test_a_full_file_system_keeps_the_previous_manifest(tmpfs):
    fs = tmpfs("fs", "64k")
    target = fs / "manifest.json"
    atomic.write_json(target, {"runs": ["previous"]})
    before = target.read_bytes()
    free = os.statvfs(fs).f_bavail * os.statvfs(fs).f_frsize
    (fs / "filler").write_bytes(b"\0" * free)
    with pytest.raises(OSError) as raised:
        atomic.write_json(target, {"runs": ["x" * 100_000]})
    assert raised.value.errno == errno.ENOSPC and "No space left on device" in str(raised.value)
    assert target.read_bytes() == before
    assert sorted(p.name for p in fs.iterdir()) == ["filler", "manifest.json"]


def test_a_read_only_file_system_keeps_the_previous_report(tmpfs):
    fs = tmpfs("fs", "64k")
    target = fs / "report.md"
    atomic.write_text(target, "previous\n")
    subprocess.run(["mount", "-o", "remount,ro", str(fs)], check=True)
    with pytest.raises(OSError) as raised:
        atomic.write_text(target, "new\n")
    assert raised.value.errno == errno.EROFS
    assert target.read_text() == "previous\n"
