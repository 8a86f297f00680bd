"""Reads the two sides of a comparison from disk: each side's run
directories (or run archives, unpacked for the while), their frames as the
report loads them, and the run metadata and manifests the environment facts
come from (rtbench.compare holds what is computed from them)."""

from __future__ import annotations

from pathlib import Path

from rtbench import archive, load
from rtbench.compare import Comparison, Options, Side, compare_sides, environment


def run_records(run_dir: Path) -> tuple[dict, list[dict]]:
    """A run directory's manifest ({} without one) and the metadata sidecars
    of its finished runs, in the manifest's order."""
    manifest = load.read_manifest(run_dir) or {}
    return manifest, [load.read_metadata(meta_path) for _, meta_path, _, _ in load.run_entries(run_dir)]


def load_side(name: str, paths: list[Path], run_dirs: list[Path]) -> Side:
    """One side's runs (strictly, as the report loads them) and environment."""
    frames = load.load_runs(run_dirs)
    return Side(name, list(paths), [d.name for d in run_dirs], frames, environment(map(run_records, run_dirs)))


def compare_paths(base: list[Path], new: list[Path], options: Options) -> Comparison:
    """Loads both sides (archives unpacked for the while) and compares them."""
    with archive.unpacked(base) as base_dirs, archive.unpacked(new) as new_dirs:
        return compare_sides(load_side("base", base, base_dirs), load_side("new", new, new_dirs), options)
