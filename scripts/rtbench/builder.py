"""Builds the raytracer binary of a CMake preset for the bench runner."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

from rtbench import progress


class BuildError(RuntimeError):
    """The binary could not be built; carries the build's output tail."""


def configure_presets(repo_root: Path) -> list[str]:
    """The visible configure presets of CMakePresets.json."""
    data = json.loads((repo_root / "CMakePresets.json").read_text(encoding="utf-8"))
    return [p["name"] for p in data.get("configurePresets", []) if not p.get("hidden")]


def build(preset: str, repo_root: Path, jobs: int, out=None) -> Path:
    """Configures (once) and builds a preset; returns its raytracer binary.
    Ninja makes an up-to-date build a no-op, so this is cheap when nothing
    changed. Prints one line per step to `out` (a build's every 10 %,
    rtbench.progress); a failed step's BuildError carries its whole output."""
    if preset not in configure_presets(repo_root):
        presets = ", ".join(configure_presets(repo_root))
        raise BuildError(f"CMakePresets.json has no preset {preset!r} (presets: {presets})")
    build_dir = repo_root / "build" / preset
    steps = []
    if not (build_dir / "build.ninja").is_file():
        steps.append((f"configuring preset {preset}", ["cmake", "--preset", preset], False))
    steps.append(
        (
            f"building preset {preset}",
            ["cmake", "--build", "--preset", preset, f"-j{jobs}", "--target", "raytracer"],
            True,
        )
    )
    for label, argv, is_build in steps:
        _build_step(label, argv, is_build, repo_root, out)
    binary = build_dir / "raytracer"
    if not binary.is_file():
        raise BuildError(f"the build of preset {preset} did not produce {binary}")
    return binary


def _build_step(label: str, argv: list[str], is_build: bool, cwd: Path, out) -> None:
    """One line (a build: one every 10 % and a last one), the output kept for the error."""
    show = progress.BuildProgress(f"bench: {label}")
    if not is_build:
        print(f"bench: {label}", file=out, flush=True)
    lines = []
    proc = subprocess.Popen(
        argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace"
    )
    try:
        for line in proc.stdout:
            lines.append(line)
            message = show.feed(line)
            if message:
                print(message, file=out, flush=True)
        proc.wait()
    except BaseException:
        proc.kill()
        proc.wait()
        raise
    if is_build:
        print(show.summary(), file=out, flush=True)
    if proc.returncode != 0:
        raise BuildError(f"`{' '.join(argv)}` failed (exit {proc.returncode}); its whole output:\n{''.join(lines)}")
