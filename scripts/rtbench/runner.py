"""Runs the planned runs of a manifest, each configuration as its own
raytracer process in a process group of its own, and records how each
ended; Ctrl-C or SIGTERM stops the running one and leaves the manifest
saying what is missing (rtbench.manifests keeps the run directory).
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from contextlib import contextmanager
from pathlib import Path

from rtbench import manifests, names
from rtbench.manifests import Manifest, RunRecord
from rtbench.run_status import ManifestStatus, RunStatus

STDERR_TAIL_CHARS = 2000


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) or SIGTERM: stop after killing the running
    configuration. A KeyboardInterrupt, so every `except KeyboardInterrupt`
    cleans up the same way for both signals."""

    def __init__(self, signum: int = signal.SIGINT):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def probe_renderer(
    binary: Path, renderer: str, scene_path: str, cwd: Path, timeout: float = 120, args: tuple[str, ...] = ()
) -> str | None:
    """None if the binary can run `renderer` at all (a 4x4 frame), else why not
    (e.g. 'not built' in this build, no Vulkan device, or a device without the
    extensions the renderer needs). `args`: options of the runs to probe with
    it, where a device may run the renderer but not them
    (configurations.probe_args: gpu_rt's --gpu-rt-reorder hit)."""
    argv = [
        str(binary),
        names.RENDERER_FLAGS[renderer],
        scene_path,
        *args,
        "--width",
        "4",
        "--height",
        "4",
        "--warmup",
        "0",
        "--frames",
        "1",
        "--quiet",
    ]
    try:
        code, out, err = run_process(argv, cwd, timeout)
    except subprocess.TimeoutExpired:
        return f"a 4x4 test frame did not finish in {timeout:.0f} s"
    if code == 0:
        return None
    return f"exit {code}: {_tail(err or out)}"


def _tail(text: str) -> str:
    return text.strip()[-STDERR_TAIL_CHARS:]


def run_process(argv: list[str], cwd: Path, timeout: float) -> tuple[int, str, str]:
    """Runs a process in a process group of its own and returns (exit code,
    stdout, stderr). Whatever ends the wait (the timeout, Ctrl-C, SIGTERM)
    kills the whole group with SIGKILL and reaps it before propagating, so
    nothing it started keeps running. Its own group also keeps a terminal's
    Ctrl-C from reaching it before the runner has decided what to do.

    A signal that comes while Popen is still starting the child (it has
    exec'd, but Popen has not returned it) is held until the child is ours
    to kill: raised there, it would leave the child running unowned."""
    with _interrupts.held() as hold:
        proc = subprocess.Popen(
            argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
        )
        try:
            hold.release()
            out, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired as e:
            _kill_group(proc)
            _, err = proc.communicate()
            e.stderr = err
            raise
        except BaseException:
            _kill_group(proc)
            proc.communicate()
            raise
    return proc.returncode, out, err


def _kill_group(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:  # the group is gone already
        pass


def run_one(record: RunRecord, run_dir: Path, cwd: Path, timeout: float) -> RunRecord:
    """Runs one configuration's process and records how it ended. A
    KeyboardInterrupt propagates after the process group is killed."""
    started = time.monotonic()
    try:
        code, _, err = run_process(record.argv, cwd, timeout)
        record.exit_code, record.stderr_tail = code, _tail(err)
        complete = (run_dir / record.csv).is_file() and (run_dir / record.meta).is_file()
        record.status = RunStatus.OK if code == 0 and complete else RunStatus.FAILED
        if code == 0 and not complete:
            record.stderr_tail = (record.stderr_tail + "\nexit 0 but the CSV or metadata is missing").strip()
    except subprocess.TimeoutExpired as e:
        record.status = RunStatus.FAILED
        record.stderr_tail = f"timed out after {timeout:.0f} s\n" + _tail(_text(e.stderr))
    finally:
        record.seconds = round(time.monotonic() - started, 3)
        manifests.remove_temporaries(run_dir, record)
    return record


def _text(data) -> str:
    if data is None:
        return ""
    return data.decode(errors="replace") if isinstance(data, bytes) else data


class Observer:
    """Progress callbacks; the base class stays silent."""

    def started(self, record: RunRecord, done: int, total: int) -> None: ...
    def finished(self, record: RunRecord, done: int, total: int) -> None: ...


def execute(manifest: Manifest, run_dir: Path, cwd: Path, timeout: float, observer: Observer) -> bool:
    """Runs every pending record in order, rewriting the manifest after each;
    the observer counts the runs this call executes (unavailable ones are not
    among them). Returns False if interrupted (Ctrl-C or SIGTERM): the record
    in flight is marked interrupted (its process group killed), the ones
    after it stay pending, the manifest is written with what is missing."""
    todo = [r for r in manifest.runs if r.status == RunStatus.PENDING]
    current = None
    try:
        for done, record in enumerate(todo):
            current = record
            observer.started(record, done, len(todo))
            run_one(record, run_dir, cwd, timeout)
            observer.finished(record, done + 1, len(todo))
            current = None
            manifests.write_manifest(run_dir, manifest)
    except KeyboardInterrupt as e:
        if current is not None:
            current.status, current.exit_code, current.stderr_tail = RunStatus.INTERRUPTED, None, ""
            manifests.discard_outputs(run_dir, current)
        manifests.mark_interrupted(run_dir, manifest, e)
        return False
    manifest.status = ManifestStatus.COMPLETE
    manifest.finished_at = manifests.utc_now()
    manifests.write_manifest(run_dir, manifest)
    return True


class _InterruptState:
    """What interruptible()'s handler shares with run_process: whether the
    first signal was raised already, and whether a signal must wait (held)
    until the running child can be killed."""

    def __init__(self):
        self.raised = False
        self.holding = False
        self.pending: int | None = None

    def on_signal(self, signum: int) -> None:
        if self.raised:
            return
        if self.holding:
            self.pending = signum
            return
        self.raised = True
        raise Interrupted(signum)

    @contextmanager
    def held(self):
        """Signals that come inside the block wait for release(), which
        raises the first of them; leaving the block releases too (a signal
        held while Popen failed is raised, not lost)."""
        self.holding, self.pending = True, None
        try:
            yield self
        finally:
            self.release()

    def release(self) -> None:
        self.holding = False
        if self.pending is not None:
            signum, self.pending = self.pending, None
            self.on_signal(signum)


_interrupts = _InterruptState()


@contextmanager
def interruptible():
    """SIGINT (Ctrl-C) and SIGTERM raise Interrupted inside the block, the
    first one only: a second signal while the runner kills the running
    configuration and writes the manifest is ignored, so that cleanup
    finishes."""
    _interrupts.raised = False

    def handler(signum, frame):
        _interrupts.on_signal(signum)

    previous = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
