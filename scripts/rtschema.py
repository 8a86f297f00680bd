"""The project's shared names, read from schema/rt_schema.json (the one source
of truth that the C++ build also generates its header from)."""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
SCHEMA_PATH = REPO_ROOT / "schema" / "rt_schema.json"


@lru_cache(maxsize=1)
def schema() -> dict:
    with SCHEMA_PATH.open(encoding="utf-8") as f:
        return json.load(f)


def renderer_names() -> list[str]:
    return [r["name"] for r in schema()["renderers"]]


def renderer_flags() -> dict[str, str]:
    return {r["name"]: r["flag"] for r in schema()["renderers"]}


def frame_csv_columns() -> list[str]:
    return [c["name"] for c in schema()["frame_csv"]]


def run_metadata_keys() -> list[str]:
    return [k["name"] for k in schema()["run_metadata"]]


def stages() -> dict[str, dict]:
    return {s["name"]: s for s in schema()["stages"]}
