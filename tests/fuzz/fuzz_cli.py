#!/usr/bin/python3
"""Seeded mutation fuzzing of the raytracer binary: scene files and command lines.

Runs the real binary (in CI the ASan + UBSan debug build) on mutated inputs
and holds every run to the contract of bad input (docs/command-line.md,
section "Exit codes and outputs"; docs/render-model.md section 1,
Rejection):

- it exits 0 or 2, by itself (no signal) and in time (no hang);
- no sanitizer report;
- on exit 2 the last line of stderr is the message ("raytracer: ..."), and a
  bad scene file's message is that one line; nothing is left at the output
  paths;
- on exit 0 every output it wrote is complete, and no temporary is left.

Categories (each case draws one): byte flips, truncation, huge and tiny
numbers, deep nesting, huge arrays, duplicate keys, wrong types, BOM and
invalid UTF-8, special files (empty, a directory, /dev/zero, /dev/null, a
FIFO, a missing path) and command-line arguments.

    tests/fuzz/fuzz_cli.py --binary build/debug/raytracer --cases 2000 --seed 1 --jobs 2

Failing inputs are kept under --keep (tests/fuzz/regressions/ holds the ones
found so far, run by tests/fuzz/test_fuzz.py). The summary is one JSON
object per category on stdout (--report writes it to a file too).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import random
import re
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO_ROOT = HERE.parents[1]
CORPUS = HERE / "corpus"

# Small and quick: one frame of 8x6 pixels, no Vulkan device.
RUN_FLAGS = ["--width", "8", "--height", "6", "--warmup", "0", "--frames", "1", "--present", "none", "--quiet"]
CPU_RENDERERS = ["--sequential", "--simd", "--simd-only", "--tbb-only", "--embree"]
SANITIZER_MARKS = ("Sanitizer", "runtime error:", "LeakSanitizer")

SPECIAL_NUMBERS = [
    "1e39",
    "-1e39",
    "1e400",
    "-1e400",
    "1e-400",
    "1e-320",
    "5e-324",
    "0",
    "-0",
    "-0.0",
    "1e6",
    "-1e6",
    "1000000.0000001",
    "1e-6",
    "9.99e-7",
    "1e308",
    "1.7976931348623157e308",
    "123456789012345678901234567890",
    "-9223372036854775809",
    "18446744073709551616",
    "4294967296",
    "65",
    "64",
    "1",
    "0.5",
    "180",
    "179.99999999999",
    "1e-300",
    "2e-308",
]
BAD_NUMBER_TEXT = ["NaN", "Infinity", "-", "1e", "1e+", ".5", "5.", "0x10", "01", "+1", "1_000", "1,5", "--1"]


@dataclass
class Case:
    category: str
    data: bytes | None = None  # the scene file's bytes (None: a special path)
    special: str | None = None  # empty, directory, dev-zero, dev-null, fifo, missing
    args: list[str] = field(default_factory=list)  # extra command-line arguments (the cli category)
    scene_message: bool = True  # a rejected scene: stderr must be exactly one line


# --- scene mutations ------------------------------------------------------


def seeds() -> list[bytes]:
    files = [*sorted(CORPUS.glob("*.json")), REPO_ROOT / "scenes/default.json"]
    return [f.read_bytes() for f in files]


def byte_flips(rng: random.Random, seed: bytes) -> bytes:
    data = bytearray(seed)
    for _ in range(rng.choice([1, 1, 2, 4, 16])):
        i = rng.randrange(len(data))
        data[i] = rng.randrange(256) if rng.random() < 0.5 else data[i] ^ (1 << rng.randrange(8))
    return bytes(data)


def truncation(rng: random.Random, seed: bytes) -> bytes:
    return seed[: rng.randrange(len(seed))]


NUMBER = re.compile(rb"-?\d+(?:\.\d+)?(?:[eE][+-]?\d+)?")


def numbers(rng: random.Random, seed: bytes) -> bytes:
    spans = [m.span() for m in NUMBER.finditer(seed)]
    data = seed
    for start, end in sorted(rng.sample(spans, min(len(spans), rng.choice([1, 1, 3]))), reverse=True):
        pool = SPECIAL_NUMBERS if rng.random() < 0.85 else BAD_NUMBER_TEXT
        data = data[:start] + rng.choice(pool).encode() + data[end:]
    return data


def _nodes(value, path=()):
    """Every (path, value) of a parsed JSON document."""
    yield path, value
    children = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    for key, child in children:
        yield from _nodes(child, (*path, key))


def _replace(doc, path, new):
    if not path:
        return new
    target = doc
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = new
    return doc


def _parsed(rng: random.Random):
    return json.loads(rng.choice([s for s in seeds() if _is_json(s)]))


def _is_json(data: bytes) -> bool:
    try:
        json.loads(data)
        return True
    except ValueError:
        return False


def wrong_types(rng: random.Random, _seed: bytes) -> bytes:
    doc = _parsed(rng)
    path, _ = rng.choice(list(_nodes(doc)))
    new = rng.choice(
        [
            None,
            True,
            False,
            0,
            -1,
            1.5,
            "",
            "1",
            "text",
            [],
            [1, 2, 3],
            [[1, 2, 3]],
            {},
            {"a": 1},
            ["1", "2", "3"],
            [1, 2],
            [1, 2, 3, 4],
            [None, None, None],
        ]
    )
    return json.dumps(_replace(doc, path, new)).encode()


def deep_nesting(rng: random.Random, _seed: bytes) -> bytes:
    depth = rng.choice([100, 1000, 10_000, 100_000, 1_000_000])
    opener, closer = rng.choice([("[", "]"), ('{"a":', "}")])
    inner = "1" if rng.random() < 0.5 else ""
    nested = opener * depth + inner + (closer * depth if rng.random() < 0.8 else "")
    if rng.random() < 0.5:
        return nested.encode()
    doc = _parsed(rng)
    path, _ = rng.choice(list(_nodes(doc)))
    marker = "__NESTED__"
    return json.dumps(_replace(doc, path, marker)).replace(f'"{marker}"', nested).encode()


def huge_arrays(rng: random.Random, _seed: bytes) -> bytes:
    doc = _parsed(rng)
    choice = rng.randrange(4)
    if choice == 0:  # many small spheres: legal, and must still render
        count = rng.choice([10_000, 100_000])
        doc["spheres"] = [
            {
                "position": [rng.uniform(-50, 50), rng.uniform(-5, 5), rng.uniform(10, 60)],
                "radius": 0.01,
                "color": [0.5, 0.5, 0.5],
            }
            for _ in range(count)
        ]
    elif choice == 1:  # a vec3 with a million elements
        path, _ = rng.choice([(p, v) for p, v in _nodes(doc) if isinstance(v, list)])
        doc = _replace(doc, path, [0.5] * 1_000_000)
    elif choice == 2:  # a megabyte-long key or string
        doc["x" * rng.choice([1000, 1_000_000])] = "y" * rng.choice([0, 1_000_000])
    else:  # many unknown keys
        doc.update({f"k{i}": i for i in range(rng.choice([1000, 200_000]))})
    return json.dumps(doc).encode()


def duplicate_keys(rng: random.Random, seed: bytes) -> bytes:
    """A key written twice in one object (JSON allows it; which one wins is
    the parser's business, but the run must still obey the contract)."""
    keys = [m for m in re.finditer(rb'"([A-Za-z]+)"\s*:\s*', seed)]
    if not keys:
        return seed
    m = rng.choice(keys)
    value = rng.choice([b"1", b"-1", b"1e39", b'"x"', b"[0, 0, 0]", b"{}", b"null"])
    return seed[: m.start()] + m.group(0) + value + b", " + seed[m.start() :]


def encodings(rng: random.Random, seed: bytes) -> bytes:
    choice = rng.randrange(7)
    if choice == 0:
        return b"\xef\xbb\xbf" + seed  # UTF-8 BOM
    if choice == 1:
        return b"\xff\xfe" + seed.decode("latin-1").encode("utf-16-le")  # UTF-16 with its BOM
    if choice == 2:
        return seed.replace(b'"color"', b'"col\xc3\x28r"', 1)  # invalid UTF-8 inside a key
    if choice == 3:
        return seed.replace(b'"', b'"\xed\xa0\x80', 1)  # an encoded surrogate
    if choice == 4:
        return seed.replace(b'"radius"', b'"rad\\ud800ius"', 1)  # a lone surrogate escape
    if choice == 5:
        i = rng.randrange(len(seed))
        return seed[:i] + b"\0" + seed[i:]
    return seed.replace(b'"position"', b'"p\xc0\xafsition"', 1)  # an overlong encoding


SCENE_MUTATORS = {
    "byte-flips": byte_flips,
    "truncation": truncation,
    "numbers": numbers,
    "deep-nesting": deep_nesting,
    "huge-arrays": huge_arrays,
    "duplicate-keys": duplicate_keys,
    "wrong-types": wrong_types,
    "encoding": encodings,
}
SPECIALS = ["empty", "directory", "dev-zero", "dev-null", "fifo", "fifo-garbage", "missing"]


# --- command lines ----------------------------------------------------------


def cli_value(rng: random.Random, kind: str) -> str:
    pools = {
        "count": ["0", "-1", "1", "2", "7", "16", "99999999999999999999", "1e3", "", " 3", "3x", "0x10", "+4"],
        "size": ["0", "-1", "1", "3", "8", "16384", "16385", "99999999999999999999", "", "8.5", "abc"],
        "frames": ["0", "1", "2", "1000001", "-5", "", "x"],
        "name": [
            "",
            "x",
            "none",
            "all",
            "bvh",
            "two-pass",
            "single-pass",
            "original",
            "optimized",
            "rows",
            "tiles",
            "native",
            "4",
            "8",
            "16",
            "3",
            "bounce",
            "bounce,sphere",
            "bounce,,sphere",
            "packet",
            "single",
            "hybrid",
            "binary",
            "wide",
            "pixel",
            "persistent",
            "megakernel",
            "wavefront",
            ",",
            "upload",
            "window",
            "\u00e9",
            "a" * 5000,
        ],
        "save": [
            "0:{out}/f.png",
            "1:{out}/f.png",
            "-1:{out}/f.png",
            ":{out}/f.png",
            "0:",
            "0",
            "x:y.png",
            "99999999999999999999:{out}/f.png",
            "0:{out}/missing/f.png",
            "0:{out}",
            "0:{out}/f.png:extra",
        ],
        "path": ["{out}/run.csv", "{out}/missing/run.csv", "{out}", "", "/dev/null", "{out}/sub/../run.csv"],
    }
    return rng.choice(pools[kind])


CLI_OPTIONS = {
    "--width": "size",
    "--height": "size",
    "--frames": "frames",
    "--warmup": "frames",
    "--threads": "count",
    "--grain": "count",
    "--lanes": "name",
    "--partition": "name",
    "--algorithm": "name",
    "--early-exit": "name",
    "--stage": "name",
    "--accel": "name",
    "--traversal": "name",
    "--hybrid-threshold": "count",
    "--gpu-bvh": "name",
    "--gpu-schedule": "name",
    "--gpu-path": "name",
    "--present": "name",
    "--save-frame": "save",
    "--csv": "path",
    "--meta": "path",
    "--device": "name",
}
CLI_FLAGS = [
    *CPU_RENDERERS,
    "--quiet",
    "--version",
    "--help",
    "--vk-validation",
    "--tracy-wait",
    "--counters",
    "--nonsense",
    "-x",
    "--",
    "-",
    "--width=8",
    "--frames=1",
]


def command_line(rng: random.Random) -> list[str]:
    args: list[str] = []
    for _ in range(rng.choice([1, 2, 3, 5, 8])):
        if rng.random() < 0.65:
            option = rng.choice(list(CLI_OPTIONS))
            args += [option, cli_value(rng, CLI_OPTIONS[option])] if rng.random() < 0.95 else [option]
        else:
            args.append(rng.choice(CLI_FLAGS))
    # Keep a run small unless a size is the point of the case: a legal
    # 16384 x 16384 x 1,000,000-frame run is not a bug, just long.
    sizes = [args[i + 1] for i, a in enumerate(args[:-1]) if a in ("--width", "--height", "--frames", "--warmup")]
    if sum(s in ("16384", "1000001") for s in sizes) > 0:
        args = [a for a in args if a not in ("--vk-validation",)]
    return args


def make_case(rng: random.Random) -> Case:
    roll = rng.random()
    if roll < 0.15:
        return Case("cli", data=rng.choice(seeds()), args=command_line(rng), scene_message=False)
    if roll < 0.25:
        special = rng.choice(SPECIALS)
        data = rng.choice(seeds()) if special == "fifo" else byte_flips(rng, rng.choice(seeds()))
        return Case("special-files", data=data, special=special)
    category = rng.choice(list(SCENE_MUTATORS))
    return Case(category, data=SCENE_MUTATORS[category](rng, rng.choice(seeds())))


# --- running and judging ----------------------------------------------------


@dataclass
class Verdict:
    category: str
    exit_code: int | None
    failure: str | None  # None: passed
    detail: str = ""


def feed_fifo(path: Path, data: bytes, proc: subprocess.Popen) -> None:
    """Writes `data` into the FIFO once the binary opens it; gives up when it exits."""
    while proc.poll() is None:
        try:
            fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
        except OSError:
            time.sleep(0.01)
            continue
        os.set_blocking(fd, True)
        try:
            os.write(fd, data)
        except OSError:
            pass  # the reader left early (a rejected scene)
        finally:
            os.close(fd)
        return


def scene_path(case: Case, work: Path) -> Path:
    special = case.special
    if special in ("dev-zero", "dev-null"):
        return Path("/dev/zero" if special == "dev-zero" else "/dev/null")
    if special == "missing":
        return work / "no-such-scene.json"
    if special == "directory":
        (work / "scene-dir").mkdir()
        return work / "scene-dir"
    if special in ("fifo", "fifo-garbage"):
        os.mkfifo(work / "scene.fifo")
        return work / "scene.fifo"
    path = work / "scene.json"
    path.write_bytes(b"" if special == "empty" else case.data)
    return path


def complete_output(path: Path) -> bool:
    """Judged by content, not by name: a command line may give a PNG any name."""
    data = path.read_bytes()
    if data.startswith(b"\x89PNG"):
        return data.endswith(b"IEND\xaeB`\x82")
    if data.startswith(b"{"):
        return _is_json(data)
    try:
        rows = list(csv.reader(data.decode().splitlines()))
    except UnicodeDecodeError:
        return False
    return data.endswith(b"\n") and len(rows) > 1 and all(len(row) == len(rows[0]) for row in rows)


def judge(case: Case, done_rc: int | None, stderr: str, out: Path, timed_out: bool) -> Verdict:
    def fail(kind: str, detail: str = "") -> Verdict:
        return Verdict(case.category, done_rc, kind, detail or stderr[-2000:])

    if timed_out:
        return fail("hang")
    if any(mark in stderr for mark in SANITIZER_MARKS):
        return fail("sanitizer")
    if done_rc is not None and done_rc < 0:
        return fail("signal", f"signal {-done_rc}")
    # 3 is the documented "no Vulkan device" or "no window" (a --present
    # upload, --device or --present window case on a machine without a
    # device or a display), not a crash.
    no_device = done_rc == 3 and ("no Vulkan device" in stderr or "no window" in stderr)
    if done_rc not in (0, 2) and not no_device:
        return fail("exit-code", f"exit {done_rc}: {stderr[-2000:]}")
    left = sorted(p.relative_to(out).as_posix() for p in out.rglob("*"))
    if done_rc == 2:
        lines = stderr.rstrip("\n").splitlines()
        if not lines or not lines[-1].startswith("raytracer: "):
            return fail("message")
        if case.scene_message and len(lines) != 1:
            return fail("message", "more than one line")
        if left:
            return fail("output-left", f"left at the output paths: {left}")
    elif done_rc == 0:
        if any(".tmp" in name for name in left):
            return fail("output-left", f"temporary left: {left}")
        torn = [p for p in out.rglob("*") if p.is_file() and not complete_output(p)]
        if torn:
            return fail("torn-output", str(torn))
    return Verdict(case.category, done_rc, None)


def run_case(binary: Path, case: Case, timeout: float) -> Verdict:
    with tempfile.TemporaryDirectory(prefix="rt-fuzz-") as tmp:
        work = Path(tmp)
        out = work / "out"
        out.mkdir()
        scene = scene_path(case, work)
        if case.category == "cli":
            args = [a.replace("{out}", str(out)) for a in case.args]
            argv = [str(binary), str(scene), *args]
            if "--present" not in args:
                argv += ["--present", "none"]
        else:
            renderer = "--sequential"
            argv = [
                str(binary),
                renderer,
                str(scene),
                *RUN_FLAGS,
                "--csv",
                str(out / "run.csv"),
                "--save-frame",
                f"0:{out / 'frame.png'}",
            ]
        proc = subprocess.Popen(
            argv,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            cwd=work,
            env={**os.environ, "ASAN_OPTIONS": "detect_leaks=1:abort_on_error=0"},
        )
        feeder = None
        if case.special in ("fifo", "fifo-garbage"):
            feeder = threading.Thread(target=feed_fifo, args=(scene, case.data, proc), daemon=True)
            feeder.start()
        try:
            _, err = proc.communicate(timeout=timeout)
            timed_out = False
        except subprocess.TimeoutExpired:
            proc.kill()
            _, err = proc.communicate()
            timed_out = True
        if feeder:
            feeder.join(timeout=5)
        return judge(case, proc.returncode, err.decode(errors="replace"), out, timed_out)


def keep_failure(keep: Path, index: int, case: Case, verdict: Verdict) -> None:
    keep.mkdir(parents=True, exist_ok=True)
    stem = keep / f"{verdict.failure}-{case.category}-{index}"
    if case.data is not None:
        stem.with_suffix(".json").write_bytes(case.data)
    stem.with_suffix(".txt").write_text(
        json.dumps(
            {"special": case.special, "args": case.args, "exit": verdict.exit_code, "detail": verdict.detail}, indent=2
        )
    )


def campaign(binary: Path, cases: int, seconds: float, seed: int, jobs: int, timeout: float, keep: Path | None) -> dict:
    deadline = time.monotonic() + seconds
    summary: dict[str, dict] = {}
    lock = threading.Lock()

    def one(index: int):
        if time.monotonic() > deadline:
            return
        # Drawn here, from the seed and the index, not all up front: a case
        # can hold 100 MB (huge arrays), and each reproduces on its own.
        case = make_case(random.Random(f"{seed}-{index}"))
        try:
            verdict = run_case(binary, case, timeout)
        except Exception as e:  # a driver bug must not end the campaign unreported
            verdict = Verdict(case.category, None, "driver-error", repr(e))
        with lock:
            row = summary.setdefault(case.category, {"cases": 0, "exit_0": 0, "exit_2": 0, "failures": {}})
            row["cases"] += 1
            if verdict.failure is None:
                key = f"exit_{verdict.exit_code}"
                row[key] = row.get(key, 0) + 1
            else:
                row["failures"][verdict.failure] = row["failures"].get(verdict.failure, 0) + 1
                print(f"FAIL {verdict.failure} {case.category} case {index}: {verdict.detail[:300]}", file=sys.stderr)
                if keep:
                    keep_failure(keep, index, case, verdict)

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        list(pool.map(one, range(cases)))
    return summary


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", type=Path, required=True, help="the raytracer binary (ideally ASan + UBSan)")
    parser.add_argument("--cases", type=int, default=1000, help="cases to generate (default 1000)")
    parser.add_argument("--seconds", type=float, default=float("inf"), help="stop starting cases after this long")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--jobs", type=int, default=2, help="runs at once (default 2)")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds before a run counts as a hang")
    parser.add_argument("--keep", type=Path, help="directory to keep failing inputs in")
    parser.add_argument("--report", type=Path, help="also write the summary (JSON) here")
    args = parser.parse_args(argv)
    summary = campaign(args.binary.resolve(), args.cases, args.seconds, args.seed, args.jobs, args.timeout, args.keep)
    text = json.dumps(summary, indent=2, sort_keys=True)
    print(text)
    if args.report:
        args.report.write_text(text + "\n")
    return 1 if any(row["failures"] for row in summary.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
