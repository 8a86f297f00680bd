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


def axes() -> dict[str, dict]:
    """Each run-time axis (the schema's axes) by name, in schema order, as
    declared, with its values as names ([] for a count or a toggle; 'list':
    the name of the schema list holding them, or None), the renderers that
    take it (every renderer where the entry lists none), and an empty
    'requires' and 'default_when', a false 'default_for_all' where it has none."""
    result: dict[str, dict] = {}
    for entry in schema()["axes"]:
        choice = entry["kind"] == "choice"
        result[entry["name"]] = {
            **entry,
            "list": entry["values"] if choice else None,
            "values": _names(entry["values"]) if choice else [],
            "renderers": list(entry.get("renderers", renderer_names())),
            "requires": dict(entry.get("requires", {})),
            "default_when": list(entry.get("default_when", [])),
            "default_for_all": bool(entry.get("default_for_all", False)),
        }
    return result


def retired_gpu_axes() -> dict[str, tuple[str, list[str]]]:
    """Each GPU axis whose variants were retired (retired_gpu_variants), by
    its CSV column: the one value it reads now (the first of its 'values'
    list) and the retired ones, in schema order."""
    axes: dict[str, tuple[str, list[str]]] = {}
    for retired in schema()["retired_gpu_variants"]:
        kept = schema()[retired["values"]][0]["name"]
        axes.setdefault(retired["column"], (kept, []))[1].append(retired["name"])
    return axes


def lane_widths() -> list[int]:
    return list(schema()["lane_widths"])


def frame_csv_columns() -> list[str]:
    return _names("frame_csv")


def run_metadata_keys() -> list[str]:
    return _names("run_metadata")


def run_metadata_fields(*path: str) -> list[str]:
    """The keys of the metadata object at `path`: ("host",) -> cpu_model, ...;
    ("build", "nix") -> nixpkgs_rev; ("outputs", "frames") -> the keys of each
    saved frame. Empty for an object without fixed keys (libraries)."""
    entries = schema()["run_metadata"]
    for depth, name in enumerate(path):
        entry = next((e for e in entries if e["name"] == name), None)
        if entry is None:
            raise KeyError(f"schema/rt_schema.json has no metadata key {'.'.join(path[: depth + 1])}")
        entries = entry.get("fields", [])
    return [e["name"] for e in entries]


def metadata_key_problems(meta: dict) -> list[str]:
    """Where the keys of a metadata sidecar and the schema's run_metadata
    differ, at every depth: a key written but not in the schema, or in the
    schema but not written. Null objects (no device, no window) have no keys."""
    return _key_problems(meta, schema()["run_metadata"], "")


def _key_problems(value: dict, fields: list[dict], where: str) -> list[str]:
    listed = [f["name"] for f in fields]
    problems = [f"{where}{k}: written, not in the schema" for k in value if k not in listed]
    problems += [f"{where}{k}: in the schema, not written" for k in listed if k not in value]
    for field in fields:
        problems += _field_problems(value.get(field["name"]), field, f"{where}{field['name']}")
    return problems


def _field_problems(value, field: dict, where: str) -> list[str]:
    if "fields" not in field:
        unlisted_object = isinstance(value, dict) and "keyed_by" not in field
        return [f"{where}: an object, but the schema lists no fields for it"] if unlisted_object else []
    if isinstance(value, list):  # a list of objects (outputs.frames)
        return [p for i, item in enumerate(value) for p in _object_problems(item, field, f"{where}[{i}]")]
    return _object_problems(value, field, where)


def _object_problems(value, field: dict, where: str) -> list[str]:
    if value is None:  # no device, no window, no acceleration structure, not run by Nix
        return []
    if not isinstance(value, dict):
        return [f"{where}: not an object, but the schema lists its fields"]
    return _key_problems(value, field["fields"], where + ".")


def stages() -> dict[str, dict]:
    return {s["name"]: s for s in schema()["stages"]}


def present_modes() -> list[str]:
    return _names("present_modes")


def scene_limits() -> tuple[float, float]:
    """(max_magnitude, min_length): the numbers a scene may hold (docs/render-model.md
    section 1, Limits); the C++ loader's constants come from the same entry."""
    limits = schema()["scene_limits"]
    return float(limits["max_magnitude"]), float(limits["min_length"])
