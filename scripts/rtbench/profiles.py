"""Benchmark profiles: declarative run matrices (profiles/*.toml, documented in
profiles/README.md) and their expansion into configurations and a schedule.

A profile names scenes, stages (or explicit algorithm / early-exit sets),
renderers with their own axes (threads, lanes, grain, device, present), the
image size, warm-up and measured frames, repetitions and the interleaving.
Everything here is pure: reading the TOML is the only I/O.
"""

from __future__ import annotations

import itertools
import random
import re
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

from rtbench import names

PROFILES_DIR = names.REPO_ROOT / "profiles"
SCENES_DIR = names.REPO_ROOT / "scenes"

# Per-renderer axes and the raytracer option each one sets. A renderer lists
# only the axes it accepts (the sequential renderer takes none of them).
RENDERER_AXES = {"threads": "--threads", "lanes": "--lanes", "grain": "--grain", "device": "--device", "present": "--present"}
RENDERER_KEYS = {*RENDERER_AXES, "args"}
TOP_KEYS = {
    "description", "preset", "scenes", "stages", "width", "height", "warmup", "frames",
    "repetitions", "interleave", "seed", "args", "timeout_s", "renderers", "overrides",
}
REQUIRED_KEYS = {"description", "scenes", "stages", "renderers"}
OVERRIDE_MATCH_KEYS = {"renderers", "stages", "scenes"}
OVERRIDE_SET_KEYS = {"width", "height", "warmup", "frames", "args", "skip"}
INTERLEAVE_MODES = ("round-robin", "shuffle", "blocked")
DEFAULTS = {
    "preset": "release", "width": 800, "height": 600, "warmup": 1, "frames": 5, "repetitions": 1,
    "interleave": "round-robin", "seed": 1, "args": [], "timeout_s": 600, "overrides": [],
}


class ProfileError(ValueError):
    """A profile or scene that cannot be used; the message names the file."""


@dataclass(frozen=True)
class Variant:
    """What the kernel does: one of the schema's stages, or an explicit
    algorithm + early-exit set for ablations outside the three stages."""

    label: str
    algorithm: str
    early_exits: tuple[str, ...]
    named_stage: bool

    def args(self) -> list[str]:
        if self.named_stage:
            return ["--stage", self.label]
        return ["--algorithm", self.algorithm, "--early-exit", ",".join(self.early_exits) or names.NO_EARLY_EXIT]


@dataclass(frozen=True)
class Config:
    """One configuration: run as its own raytracer process, once per repetition."""

    scene: str
    scene_path: str
    renderer: str
    variant: Variant
    width: int
    height: int
    warmup: int
    frames: int
    axes: tuple[tuple[str, str], ...] = ()
    args: tuple[str, ...] = ()

    @property
    def id(self) -> str:
        """A file-name-safe identifier, unique within a profile."""
        parts = [self.scene, self.renderer, self.variant.label, *(f"{axis}{value}" for axis, value in self.axes)]
        return re.sub(r"[^A-Za-z0-9_.-]+", "_", "-".join(parts))

    def argv(self, binary: Path, csv: Path, meta: Path) -> list[str]:
        """The raytracer command line for one repetition of this configuration."""
        argv = [str(binary), names.RENDERER_FLAGS[self.renderer], self.scene_path, *self.variant.args()]
        argv += ["--width", str(self.width), "--height", str(self.height)]
        argv += ["--warmup", str(self.warmup), "--frames", str(self.frames)]
        for axis, value in self.axes:
            argv += [RENDERER_AXES[axis], value]
        argv += [*self.args, "--csv", str(csv), "--meta", str(meta), "--quiet"]
        return argv

    def describe(self) -> dict:
        """The configuration as plain data for the manifest."""
        return {
            "id": self.id, "scene": self.scene, "scene_path": self.scene_path, "renderer": self.renderer,
            "stage": self.variant.label, "algorithm": self.variant.algorithm,
            "early_exits": list(self.variant.early_exits), "width": self.width, "height": self.height,
            "warmup": self.warmup, "frames": self.frames, "axes": dict(self.axes), "args": list(self.args),
        }


@dataclass(frozen=True)
class Profile:
    name: str
    path: Path
    description: str
    preset: str
    scenes: tuple[str, ...]
    variants: tuple[Variant, ...]
    renderers: dict[str, dict[str, list]]
    width: int
    height: int
    warmup: int
    frames: int
    repetitions: int
    interleave: str
    seed: int
    args: tuple[str, ...]
    timeout_s: float
    overrides: tuple[dict, ...] = field(default_factory=tuple)
    raw: dict = field(default_factory=dict, compare=False)


# --- reading -----------------------------------------------------------------

def profile_path(name_or_path: str, profiles_dir: Path = PROFILES_DIR) -> Path:
    """`paper` means profiles/paper.toml; anything that names a file is used as is."""
    candidate = Path(name_or_path)
    if candidate.suffix == ".toml" or candidate.is_file():
        if not candidate.is_file():
            raise ProfileError(f"{candidate}: no such profile file")
        return candidate
    path = profiles_dir / f"{name_or_path}.toml"
    if not path.is_file():
        known = ", ".join(sorted(p.stem for p in profiles_dir.glob("*.toml")))
        raise ProfileError(f"no profile {name_or_path!r}: {path} does not exist (profiles: {known})")
    return path


def load_profile(name_or_path: str, profiles_dir: Path = PROFILES_DIR) -> Profile:
    """Reads and validates a profile; every error names the file and the key."""
    path = profile_path(name_or_path, profiles_dir)
    try:
        with path.open("rb") as f:
            raw = tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise ProfileError(f"{path}: not valid TOML: {e}") from None
    return parse_profile(raw, path)


def parse_profile(raw: dict, path: Path) -> Profile:
    """Validates the TOML document of a profile and fills in the defaults."""
    _check_keys(raw, TOP_KEYS, path, "")
    missing = sorted(REQUIRED_KEYS - raw.keys())
    if missing:
        raise ProfileError(f"{path}: missing key(s) {', '.join(missing)}")
    values = {**DEFAULTS, **raw}
    for key in ("width", "height", "frames", "repetitions"):
        _check_int(values[key], path, key, minimum=1)
    _check_int(values["warmup"], path, "warmup", minimum=0)
    _check_int(values["seed"], path, "seed", minimum=0)
    if values["interleave"] not in INTERLEAVE_MODES:
        raise ProfileError(f"{path}: interleave must be one of {', '.join(INTERLEAVE_MODES)}, not {values['interleave']!r}")
    scenes = _string_list(values["scenes"], path, "scenes")
    variants = tuple(_variant(entry, path, i) for i, entry in enumerate(_as_list(values["stages"], path, "stages")))
    renderers = _renderers(values["renderers"], path)
    overrides = tuple(_override(o, path, i, variants) for i, o in enumerate(_as_list(values["overrides"], path, "overrides")))
    return Profile(
        name=path.stem, path=path, description=str(values["description"]), preset=str(values["preset"]),
        scenes=tuple(scenes), variants=variants, renderers=renderers, width=values["width"],
        height=values["height"], warmup=values["warmup"], frames=values["frames"],
        repetitions=values["repetitions"], interleave=values["interleave"], seed=values["seed"],
        args=tuple(_string_list(values["args"], path, "args")), timeout_s=float(values["timeout_s"]),
        overrides=overrides, raw=raw,
    )


def _check_keys(table: dict, allowed: set[str], path: Path, where: str) -> None:
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ProfileError(f"{path}: unknown key {where}{unknown[0]!r} (known: {', '.join(sorted(allowed))})")


def _check_int(value, path: Path, key: str, minimum: int) -> None:
    if not isinstance(value, int) or isinstance(value, bool) or value < minimum:
        raise ProfileError(f"{path}: {key} must be an integer >= {minimum}, not {value!r}")


def _as_list(value, path: Path, key: str) -> list:
    if not isinstance(value, list):
        raise ProfileError(f"{path}: {key} must be a list, not {value!r}")
    return value


def _string_list(value, path: Path, key: str) -> list[str]:
    items = _as_list(value, path, key)
    if not all(isinstance(v, str) for v in items):
        raise ProfileError(f"{path}: {key} must be a list of strings, not {value!r}")
    return items


def _variant(entry, path: Path, index: int) -> Variant:
    """A stage name from the schema, or {algorithm = ..., early_exits = [...]}."""
    if isinstance(entry, str):
        if entry not in names.STAGES:
            raise ProfileError(f"{path}: stages[{index}]: unknown stage {entry!r} (schema: {', '.join(names.STAGES)})")
        stage = names.STAGES[entry]
        return Variant(entry, stage["algorithm"], tuple(stage["early_exits"]), named_stage=True)
    if not isinstance(entry, dict):
        raise ProfileError(f"{path}: stages[{index}] must be a stage name or a table")
    _check_keys(entry, {"algorithm", "early_exits"}, path, f"stages[{index}].")
    algorithm = entry.get("algorithm")
    if algorithm not in names.ALGORITHMS:
        raise ProfileError(f"{path}: stages[{index}].algorithm must be one of {', '.join(names.ALGORITHMS)}")
    exits = _string_list(entry.get("early_exits", []), path, f"stages[{index}].early_exits")
    bad = [e for e in exits if e not in names.EARLY_EXITS]
    if bad:
        raise ProfileError(f"{path}: stages[{index}]: unknown early exit {bad[0]!r} (schema: {', '.join(names.EARLY_EXITS)})")
    ordered = tuple(e for e in names.EARLY_EXITS if e in exits)
    label = names.stage_of(algorithm, names.EARLY_EXIT_SEPARATOR.join(ordered) or names.NO_EARLY_EXIT)
    return Variant(label, algorithm, ordered, named_stage=False)


def _renderers(table, path: Path) -> dict[str, dict[str, list]]:
    """[renderers.NAME] tables, in file order, each axis a list of values."""
    if not isinstance(table, dict) or not table:
        raise ProfileError(f"{path}: renderers must be a table of [renderers.NAME] entries")
    result = {}
    for renderer, spec in table.items():
        if renderer not in names.RENDERERS:
            raise ProfileError(f"{path}: unknown renderer {renderer!r} (schema: {', '.join(names.RENDERERS)})")
        if not isinstance(spec, dict):
            raise ProfileError(f"{path}: renderers.{renderer} must be a table")
        _check_keys(spec, RENDERER_KEYS, path, f"renderers.{renderer}.")
        axes = {axis: _axis_values(spec[axis], path, f"renderers.{renderer}.{axis}") for axis in RENDERER_AXES if axis in spec}
        axes["args"] = _string_list(spec.get("args", []), path, f"renderers.{renderer}.args")
        result[renderer] = axes
    return result


def _axis_values(value, path: Path, key: str) -> list:
    values = value if isinstance(value, list) else [value]
    if not values or not all(isinstance(v, (int, str)) and not isinstance(v, bool) for v in values):
        raise ProfileError(f"{path}: {key} must be a non-empty list of integers or strings")
    return values


def _override(entry, path: Path, index: int, variants: tuple[Variant, ...]) -> dict:
    where = f"overrides[{index}]"
    if not isinstance(entry, dict):
        raise ProfileError(f"{path}: {where} must be a table")
    _check_keys(entry, OVERRIDE_MATCH_KEYS | OVERRIDE_SET_KEYS, path, f"{where}.")
    for key in OVERRIDE_MATCH_KEYS & entry.keys():
        _string_list(entry[key], path, f"{where}.{key}")
    unknown = [r for r in entry.get("renderers", []) if r not in names.RENDERERS]
    if unknown:
        raise ProfileError(f"{path}: {where}: unknown renderer {unknown[0]!r}")
    labels = {v.label for v in variants}
    unknown = [s for s in entry.get("stages", []) if s not in labels]
    if unknown:
        raise ProfileError(f"{path}: {where}: stage {unknown[0]!r} is not among this profile's stages")
    for key in ("width", "height", "frames"):
        if key in entry:
            _check_int(entry[key], path, f"{where}.{key}", minimum=1)
    if "warmup" in entry:
        _check_int(entry["warmup"], path, f"{where}.warmup", minimum=0)
    if "args" in entry:
        _string_list(entry["args"], path, f"{where}.args")
    return entry


# --- scenes ------------------------------------------------------------------

def resolve_scene(arg: str, scenes_dir: Path = SCENES_DIR) -> Path:
    """A scene given by name means scenes/NAME.json; a path is used as is."""
    candidate = Path(arg)
    if candidate.is_file():
        return candidate.resolve()
    if candidate.suffix != ".json" and "/" not in arg:
        named = scenes_dir / f"{arg}.json"
        if named.is_file():
            return named.resolve()
        known = ", ".join(sorted(p.stem for p in scenes_dir.glob("*.json")))
        raise ProfileError(f"no scene {arg!r}: {named} does not exist (scenes: {known})")
    raise ProfileError(f"scene file {arg} does not exist")


# --- expansion ---------------------------------------------------------------

def axis_values(axis: str, values: list, cpu_count: int) -> list[str]:
    """The command-line values of one axis. threads accept "all" (every
    logical core) and ranges "A..B" (B may be "all"), so one profile scales
    with the machine it runs on."""
    if axis != "threads":
        return [str(v) for v in values]
    out: list[str] = []
    for v in values:
        out += [str(n) for n in parse_threads(v, cpu_count)]
    return list(dict.fromkeys(out))


def parse_threads(value, cpu_count: int) -> list[int]:
    """1 -> [1]; "all" -> [cpu_count]; "1..all" -> [1 .. cpu_count]."""
    def one(text) -> int:
        n = cpu_count if text == "all" else int(text)
        if n < 1:
            raise ValueError
        return n

    try:
        if isinstance(value, str) and ".." in value:
            lo, hi = value.split("..", 1)
            return list(range(one(lo), one(hi) + 1))
        return [one(value)]
    except ValueError:
        raise ProfileError(f"threads value {value!r}: expected a positive integer, 'all' or 'A..B'") from None


def expand(profile: Profile, scene_paths: list[Path], cpu_count: int, renderers: list[str] | None = None,
           forced: dict | None = None) -> list[Config]:
    """Every configuration of the matrix, scene-major and renderer-innermost, so
    that running them in this order already alternates renderers. `forced`
    (from the command line: width, height, warmup, frames) wins over the
    profile and its overrides."""
    configs = []
    for scene_path, variant, renderer in itertools.product(scene_paths, profile.variants, profile.renderers):
        if renderers and renderer not in renderers:
            continue
        spec = profile.renderers[renderer]
        axes = [axis for axis in RENDERER_AXES if axis in spec]
        for combo in itertools.product(*(axis_values(a, spec[a], cpu_count) for a in axes)):
            config = Config(
                scene=scene_path.stem, scene_path=str(scene_path), renderer=renderer, variant=variant,
                width=profile.width, height=profile.height, warmup=profile.warmup, frames=profile.frames,
                axes=tuple(zip(axes, combo)), args=(*profile.args, *spec["args"]),
            )
            config = apply_overrides(config, profile.overrides)
            if config is not None:
                configs.append(replace(config, **(forced or {})))
    _check_unique(configs)
    return configs


def apply_overrides(config: Config, overrides: tuple[dict, ...]) -> Config | None:
    """Applies the matching [[overrides]] in order; None if one says skip."""
    for o in overrides:
        if not _matches(config, o):
            continue
        if o.get("skip"):
            return None
        changes = {k: o[k] for k in ("width", "height", "warmup", "frames") if k in o}
        if "args" in o:
            changes["args"] = (*config.args, *o["args"])
        config = replace(config, **changes)
    return config


def _matches(config: Config, override: dict) -> bool:
    return (
        config.renderer in override.get("renderers", [config.renderer])
        and config.variant.label in override.get("stages", [config.variant.label])
        and config.scene in override.get("scenes", [config.scene])
    )


def _check_unique(configs: list[Config]) -> None:
    seen: set[str] = set()
    for c in configs:
        if c.id in seen:
            raise ProfileError(f"configuration {c.id} appears twice (a scene, stage or axis value listed twice?)")
        seen.add(c.id)


def schedule(configs: list[Config], repetitions: int, interleave: str, seed: int) -> list[tuple[int, Config]]:
    """The order of runs as (repetition, config) pairs.

    round-robin: every configuration once per round, so slow drift (thermal,
    other load) hits all renderers alike; shuffle: the same, in a seeded
    random order per round (google-benchmark's random interleaving);
    blocked: all repetitions of one configuration back to back."""
    if interleave == "blocked":
        return [(rep, c) for c in configs for rep in range(repetitions)]
    order: list[tuple[int, Config]] = []
    for rep in range(repetitions):
        round_ = list(configs)
        if interleave == "shuffle":
            random.Random(seed * 1_000_003 + rep).shuffle(round_)
        order += [(rep, c) for c in round_]
    return order
