"""The project's shared names, read from schema/rt_schema.json (the one source
of truth that the C++ build also generates its header from).

Standard library only, so that every entry point (and the bash scripts that
ask it for a renderer's flag) can read the schema with any Python 3.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[2]
SCHEMA_PATH = REPO_ROOT / "schema" / "rt_schema.json"


@lru_cache(maxsize=1)
def schema() -> dict:
    with SCHEMA_PATH.open(encoding="utf-8") as f:
        return json.load(f)


def _names(key: str) -> list[str]:
    return [entry["name"] for entry in schema()[key]]


def renderer_names() -> list[str]:
    return _names("renderers")


def renderers() -> dict[str, dict]:
    """Each renderer's entry (flag, backend, kernel, scheduler, options), by name."""
    return {r["name"]: r for r in schema()["renderers"]}


def renderer_flags() -> dict[str, str]:
    return {name: r["flag"] for name, r in renderers().items()}


def renderer_options() -> dict[str, str]:
    """Every renderer option (threads, lanes, ...) and its command-line flag."""
    return {o["name"]: o["flag"] for o in schema()["renderer_options"]}


def accepted_options(renderer: str) -> list[str]:
    """The renderer options that `renderer` accepts, in schema order."""
    return list(renderers()[renderer]["options"])


def lane_widths() -> list[int]:
    return list(schema()["lane_widths"])


def frame_csv_columns() -> list[str]:
    return _names("frame_csv")


def run_metadata_keys() -> list[str]:
    return _names("run_metadata")


def stages() -> dict[str, dict]:
    return {s["name"]: s for s in schema()["stages"]}


def present_modes() -> list[str]:
    return _names("present_modes")


def scene_limits() -> tuple[float, float]:
    """(max_magnitude, min_length): the numbers a scene may hold (docs/render-model.md
    section 1, Limits); the C++ loader's constants come from the same entry."""
    limits = schema()["scene_limits"]
    return float(limits["max_magnitude"]), float(limits["min_length"])
