"""Benchmark profiles: declarative run matrices (profiles/*.toml, documented in
profiles/README.md), read and checked; rtbench.configurations expands them
into configurations and a schedule.

A profile names scenes, stages (or explicit algorithm / early-exit sets),
the values of the run-time axes (the schema's axes, each under its profile
key: accels, traversals, hybrid_thresholds, gpu_bvhs, gpu_rt_reorders and
counters; their rules read from the axes' declarations), renderers with
their own axes (the renderer options the schema gives each, of threads,
lanes, grain and partition; and device, present), their precisions and
agreement check (precisions, agreement), the image
size, warm-up and measured frames, repetitions and the interleaving. Every
key is checked against one table of rules (TOP_RULES and the others below).
Everything here is pure: reading the TOML is the only I/O. A scene that
scenes/ lacks but the generator makes (`randomN`) resolves to a path under
GENERATED_SCENES, a stand-in for the run directory that the bench runner
replaces when it writes the scene there.
"""

from __future__ import annotations

import copy
import re
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

from rtbench import names, scenes

PROFILES_DIR = names.REPO_ROOT / "profiles"
SCENES_DIR = names.REPO_ROOT / "scenes"
# Where a generated scene goes: RUN_DIR/scenes/NAME.json, RUN_DIR standing in
# for the run directory until the runner makes it (a dry run shows it so).
GENERATED_SCENES = Path("RUN_DIR") / "scenes"

INTERLEAVE_MODES = ("round-robin", "shuffle", "blocked")
# `--lanes native`: the widest packet of the SIMD target chosen at run time;
# the other values are the schema's lane_widths.
NATIVE_LANES = "native"
# Axes every renderer takes: raytracer options of the run, not of the renderer.
# `size` ("WIDTHxHEIGHT") has no flag of its own: it sets the configuration's
# width and height (sized()), e.g. to run the gpu renderer at a second size.
SIZE_AXIS = "size"
RUN_AXES = {"device": "--device", "present": "--present", SIZE_AXIS: None}


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
class Profile:
    name: str
    path: Path
    description: str
    preset: str
    scenes: tuple[str, ...]
    variants: tuple[Variant, ...]
    accels: tuple[str, ...]
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
    # The SIMD kernel's traversals of the BVH (names.takes_traversal), and
    # traversal hybrid's thresholds (empty: the kernel's default).
    traversals: tuple[str, ...] = (names.PACKET,)
    hybrid_thresholds: tuple[int, ...] = ()
    # The GPU renderer's walk where accel is bvh (names.gpu_axes_of); by
    # default the way it ran before the walks.
    gpu_bvhs: tuple[str, ...] = (names.BINARY,)
    # The gpu_rt renderer's hit reordering; by default none, as it shades.
    gpu_rt_reorders: tuple[str, ...] = (names.NO_REORDER,)
    counters: bool = False
    # The machine the profile is written for ("": any): the bench refuses it
    # elsewhere, where it would measure something else (another SIMD target,
    # or an emulator).
    architecture: str = ""
    raw: dict = field(default_factory=dict, compare=False)

    def axis_values(self, axis: str):
        """What the profile names for a top-level axis (TOP_AXES), under its
        profile_key: a tuple of values (empty: the renderer's own, for a
        count), or true or false for a toggle."""
        return getattr(self, profile_key(axis))


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
    values = check_table(raw, TOP_RULES, path)
    variants = tuple(_variant(entry, path, i) for i, entry in enumerate(values["stages"]))
    renderers = _renderers(values["renderers"], path)
    overrides = tuple(_override(o, path, i, variants) for i, o in enumerate(values["overrides"]))
    for axis in TOP_AXES:
        _check_axis_key(axis, values, renderers, path)
    return Profile(
        name=path.stem,
        path=path,
        description=values["description"],
        preset=values["preset"],
        scenes=tuple(values["scenes"]),
        variants=variants,
        renderers=renderers,
        width=values["width"],
        height=values["height"],
        warmup=values["warmup"],
        frames=values["frames"],
        repetitions=values["repetitions"],
        interleave=values["interleave"],
        seed=values["seed"],
        args=tuple(values["args"]),
        timeout_s=float(values["timeout_s"]),
        overrides=overrides,
        raw=raw,
        architecture=values["architecture"],
        **{profile_key(axis): _axis_setting(values, axis) for axis in TOP_AXES},
    )


# --- what a profile may say: one rule per key, checked by check_table ---------

REQUIRED, OPTIONAL = object(), object()  # defaults: the key must be there / may be absent


@dataclass(frozen=True)
class Rule:
    """What one key of a profile table holds: values of `kind` (KINDS), as one
    value, a list of them, or an axis (one value or a non-empty list, read as
    a list); numbers at least `minimum`, strings matching `pattern`, and only
    `choices` where given. `what` describes the value in error messages."""

    kind: str
    default: object = REQUIRED
    shape: str = "one"  # "one", "list" or "axis"
    minimum: int | None = None
    choices: tuple = ()
    pattern: str | None = None
    what: str | None = None


def _plain(*types):
    return lambda v: isinstance(v, types) and not isinstance(v, bool)


KINDS = {  # kind -> (description, test)
    "int": ("an integer", _plain(int)),
    "number": ("a number", _plain(int, float)),
    "str": ("a string", _plain(str)),
    "int|str": ("an integer or a string", _plain(int, str)),
    "bool": ("true or false", lambda v: isinstance(v, bool)),
    "table": ("a table", _plain(dict)),
    "stage": ("a stage name or a table {algorithm = ..., early_exits = [...]}", _plain(str, dict)),
}


# --- the run-time axes (the schema's axes) -----------------------------------

# The axes that a [renderers.NAME] table names (precisions: some renderers
# compute in f16, each table says which of its precisions it runs); every
# other axis is a top-level key.
RENDERER_TABLE_AXES = (names.PRECISION,)
TOP_AXES = tuple(axis for axis in names.AXES if axis not in RENDERER_TABLE_AXES)


def profile_key(axis: str) -> str:
    """An axis' profile key: the schema list of a choice's values (accels,
    gpu_bvhs), a count's name plus 's' (hybrid_thresholds), a toggle's name (counters)."""
    declaration = names.AXES[axis]
    return {"choice": declaration["list"], "count": f"{axis}s"}.get(declaration["kind"], axis)


def axis_rule(axis: str) -> Rule:
    """What an axis' profile key holds, from its declaration: a list of the
    values a run records (names.run_values; default: the axis' default), a
    list of counts of at least its minimum (absent: the renderer's own), or
    true or false (default: the axis' default)."""
    declaration = names.AXES[axis]
    if declaration["kind"] == "toggle":
        return Rule("bool", declaration["default"])
    if declaration["kind"] == "count":
        return Rule("int", OPTIONAL, shape="list", minimum=declaration["minimum"])
    default = OPTIONAL if axis in RENDERER_TABLE_AXES else [declaration["default"]]
    return Rule("str", default, shape="list", choices=tuple(names.run_values(axis)))


def _axis_setting(values: dict, axis: str):
    """A top-level axis' value in a Profile: a tuple (empty where an optional key is absent) or a bool."""
    value = values.get(profile_key(axis), ())
    return value if isinstance(value, bool) else tuple(value)


TOP_RULES = {
    "description": Rule("str"),
    "preset": Rule("str", "release"),
    "scenes": Rule("str", shape="list"),
    "stages": Rule("stage", shape="list"),
    **{profile_key(axis): axis_rule(axis) for axis in TOP_AXES},
    "architecture": Rule("str", "", choices=("", "x86_64", "aarch64")),
    "width": Rule("int", 800, minimum=1),
    "height": Rule("int", 600, minimum=1),
    "warmup": Rule("int", 1, minimum=0),
    "frames": Rule("int", 5, minimum=1),
    "repetitions": Rule("int", 1, minimum=1),
    "interleave": Rule("str", "round-robin", choices=INTERLEAVE_MODES),
    "seed": Rule("int", 1, minimum=0),
    "args": Rule("str", [], shape="list"),
    "timeout_s": Rule("number", 600, minimum=1),
    "renderers": Rule("table"),
    "overrides": Rule("table", [], shape="list"),
}
STAGE_RULES = {
    "algorithm": Rule("str", choices=tuple(names.ALGORITHMS)),
    "early_exits": Rule("str", [], shape="list", choices=tuple(names.EARLY_EXITS)),
}
# Keys of [renderers.NAME] that are not axes of a raytracer option:
# `precisions` runs the renderer once per precision with --precision (the
# thesis' half-precision experiment; only the renderers that take it, names.takes_precision);
# `agreement` adds --agreement, the image of frame 0 against the double-precision reference.
PRECISIONS_KEY = profile_key(names.PRECISION)
AGREEMENT_KEY = "agreement"
RENDERER_EXTRA_RULES = {
    PRECISIONS_KEY: axis_rule(names.PRECISION),
    AGREEMENT_KEY: Rule("bool", False),
    "args": Rule("str", [], shape="list"),
}
# The top-level choice axes an override can match on, by profile key: a
# configuration without such an axis (names.axis_applies) never matches its values.
OVERRIDE_AXIS_KEYS = {axis: profile_key(axis) for axis in TOP_AXES if names.AXES[axis]["kind"] == "choice"}
# [[overrides]]: which configurations a table matches, and what it sets there.
OVERRIDE_RULES = {
    "renderers": Rule("str", OPTIONAL, shape="list", choices=tuple(names.RENDERERS)),
    "stages": Rule("str", OPTIONAL, shape="list"),
    "scenes": Rule("str", OPTIONAL, shape="list"),
    **{key: replace(TOP_RULES[key], default=OPTIONAL) for key in OVERRIDE_AXIS_KEYS.values()},
    # A configuration's precision: f32 where its renderer table names no precisions.
    PRECISIONS_KEY: replace(RENDERER_EXTRA_RULES[PRECISIONS_KEY], default=OPTIONAL),
    # Axis values of the configuration as the profile writes them (a number
    # never matches the threads "all" resolves to), e.g. to run the thread
    # counts of a scaling study on one scene only.
    "threads": Rule("int", OPTIONAL, shape="list", minimum=1),
    "lanes": Rule("int|str", OPTIONAL, shape="list", choices=(*names.LANE_WIDTHS, NATIVE_LANES)),
    **{key: replace(TOP_RULES[key], default=OPTIONAL) for key in ("width", "height", "warmup", "frames", "args")},
    "skip": Rule("bool", OPTIONAL),
}
# The axes an override can match on.
OVERRIDE_AXES = ("threads", "lanes")
# The values of each axis of [renderers.NAME]; a renderer option the schema
# gains later takes any integer or string until it has a rule here.
AXIS_RULES = {
    "threads": Rule(
        "int|str",
        OPTIONAL,
        "axis",
        minimum=1,
        pattern=r"all|\d+|(\d+|all)\.\.(\d+|all)",
        what='a positive integer, "all" or a range "A..B" (B may be "all")',
    ),
    "lanes": Rule("int|str", OPTIONAL, "axis", choices=(*names.LANE_WIDTHS, NATIVE_LANES)),
    "grain": Rule("int", OPTIONAL, "axis", minimum=1),
    "partition": Rule("str", OPTIONAL, "axis", choices=tuple(names.PARTITIONS)),
    "device": Rule("int|str", OPTIONAL, "axis", minimum=0),
    "present": Rule("str", OPTIONAL, "axis", choices=tuple(names.PRESENT_MODES)),
    SIZE_AXIS: Rule("str", OPTIONAL, "axis", pattern=r"[1-9]\d*x[1-9]\d*", what='an image size "WIDTHxHEIGHT"'),
}
ANY_AXIS = Rule("int|str", OPTIONAL, "axis")


def renderer_rules(renderer: str) -> dict[str, Rule]:
    """The keys of [renderers.NAME]: the options the schema says it accepts,
    the run's axes (device, present), its precisions, agreement and extra args."""
    axes = [*names.RENDERER_OPTIONS[renderer], *RUN_AXES]
    return {**{axis: AXIS_RULES.get(axis, ANY_AXIS) for axis in axes}, **RENDERER_EXTRA_RULES}


def describe(rule: Rule) -> str:
    """What a rule accepts, in words: 'an integer >= 1', 'a list, each one of a, b'."""
    one = rule.what or KINDS[rule.kind][0]
    if rule.choices:
        one = f"one of {', '.join(map(str, rule.choices))}"
    elif rule.minimum is not None and not rule.what:
        one += f" >= {rule.minimum}"
    return {"one": one, "list": f"a list, each {one}", "axis": f"{one}, or a non-empty list of them"}[rule.shape]


def _fits(item, rule: Rule) -> bool:
    if not KINDS[rule.kind][1](item):
        return False
    if rule.choices:
        return item in rule.choices
    if isinstance(item, str):
        return rule.pattern is None or re.fullmatch(rule.pattern, item) is not None
    return rule.minimum is None or item >= rule.minimum


def check_value(value, rule: Rule, path: Path, key: str):
    """The value if it follows the rule (an axis as a list), else a ProfileError naming file and key."""
    if rule.shape == "one":
        items = [value]
    elif isinstance(value, list):
        items = value
    else:
        items = [value] if rule.shape == "axis" else None
    if items is None or (rule.shape == "axis" and not items) or not all(_fits(item, rule) for item in items):
        raise ProfileError(f"{path}: {key} must be {describe(rule)}, not {value!r}")
    return items if rule.shape == "axis" else value


def check_table(table: dict, rules: dict[str, Rule], path: Path, where: str = "", what: str = "key") -> dict:
    """Checks every key of a TOML table against its rule: no unknown keys (a
    retired one is named as such), no missing required ones, each value as
    its rule says. Returns the values with the defaults filled in (absent
    OPTIONAL keys stay absent)."""
    _refuse_retired_keys(table, path, where)
    unknown = sorted(set(table) - set(rules))
    if unknown:
        raise ProfileError(f"{path}: unknown {what} '{where}{unknown[0]}' (known: {', '.join(sorted(rules))})")
    missing = [key for key, rule in rules.items() if rule.default is REQUIRED and key not in table]
    if missing:
        raise ProfileError(f"{path}: missing key(s) {', '.join(where + key for key in missing)}")
    values = {}
    for key, rule in rules.items():
        if key in table:
            values[key] = check_value(table[key], rule, path, where + key)
        elif rule.default is not OPTIONAL:
            values[key] = copy.copy(rule.default)
    return values


def _refuse_retired_keys(table: dict, path: Path, where: str) -> None:
    """The keys of the retired GPU axes (names.RETIRED_GPU_PROFILE_KEYS:
    gpu_schedules, gpu_paths): refused, saying that the GPU renderer runs
    their one remaining value now and where the retired variants' measurements are."""
    retired = [key for key in names.RETIRED_GPU_PROFILE_KEYS if key in table]
    if retired:
        key = retired[0]
        kept, gone = names.RETIRED_GPU_AXES[names.RETIRED_GPU_PROFILE_KEYS[key]]
        raise ProfileError(
            f"{path}: {where}{key}: retired: the GPU renderer always runs {kept} now, so leave the key out; the "
            f"measurements of the retired {' and '.join(gone)} are in {', '.join(names.RETIRED_GPU_RECORDS)}"
        )


def _variant(entry, path: Path, index: int) -> Variant:
    """A stage name from the schema, or {algorithm = ..., early_exits = [...]}."""
    if isinstance(entry, str):
        if entry not in names.STAGES:
            raise ProfileError(f"{path}: stages[{index}]: unknown stage {entry!r} (schema: {', '.join(names.STAGES)})")
        stage = names.STAGES[entry]
        return Variant(entry, stage["algorithm"], tuple(stage["early_exits"]), named_stage=True)
    values = check_table(entry, STAGE_RULES, path, f"stages[{index}].")
    ordered = tuple(e for e in names.EARLY_EXITS if e in values["early_exits"])
    label = names.stage_of(values["algorithm"], names.EARLY_EXIT_SEPARATOR.join(ordered) or names.NO_EARLY_EXIT)
    return Variant(label, values["algorithm"], ordered, named_stage=False)


def _renderers(table: dict, path: Path) -> dict[str, dict[str, list]]:
    """[renderers.NAME] tables, in file order, each axis a list of values."""
    check_table(table, {r: Rule("table", OPTIONAL) for r in names.RENDERERS}, path, "renderers.", what="renderer")
    if not table:
        raise ProfileError(f"{path}: renderers must be a table of [renderers.NAME] entries")
    result = {}
    for renderer, spec in table.items():
        where = f"renderers.{renderer}."
        refused = [key for key in spec if key in names.OPTION_FLAGS and not names.accepts(renderer, key)]
        if refused:
            accepted = ", ".join(names.RENDERER_OPTIONS[renderer]) or "none"
            raise ProfileError(
                f"{path}: {where}{refused[0]}: renderer {renderer} does not take {refused[0]} "
                f"(schema/rt_schema.json: its options are {accepted})"
            )
        result[renderer] = check_table(spec, renderer_rules(renderer), path, where)
        _check_precisions(result[renderer], renderer, path, where)
    return result


def _check_precisions(spec: dict, renderer: str, path: Path, where: str) -> None:
    """`precisions` only where the renderer takes --precision, each value once."""
    if PRECISIONS_KEY not in spec:
        return
    takers = ", ".join(r for r in names.RENDERERS if names.takes_precision(r))
    if not names.takes_precision(renderer):
        raise ProfileError(
            f"{path}: {where}{PRECISIONS_KEY}: renderer {renderer} does not take --precision "
            f"(only {takers} do: schema/rt_schema.json, precisions)"
        )
    chosen = spec[PRECISIONS_KEY]
    if not chosen or len(set(chosen)) != len(chosen):
        raise ProfileError(f"{path}: {where}{PRECISIONS_KEY} must name each precision once, not {chosen!r}")


def _check_axis_key(axis: str, values: dict, renderers: dict, path: Path) -> None:
    """A top-level axis' key names each value once and, where it asks for
    more than the axis' default, reaches a configuration: a renderer of the
    profile that takes the axis, and for each axis it requires (the schema's
    axes[].requires) one of the values it needs among the profile's."""
    key, chosen = profile_key(axis), values.get(profile_key(axis))
    if isinstance(chosen, list) and len(set(chosen)) != len(chosen):
        raise ProfileError(f"{path}: {key} names a value twice: {chosen!r}")
    if chosen in (None, [names.AXES[axis]["default"]], names.AXES[axis]["default"]):
        return
    if not any(names.takes_axis(r, axis) for r in renderers):
        raise ProfileError(f"{path}: {key}: applies to {names.axis_takers(axis)} only, which this profile does not run")
    for on, allowed in names.AXES[axis]["requires"].items():
        if not set(values[profile_key(on)]) & set(allowed):
            needed = f"{on} {' or '.join(v for v in names.run_values(on) if v in allowed)}"
            where = names.where_axis_applies(axis)
            raise ProfileError(f"{path}: {key}: applies to {where} only, and this profile has no {needed}")


def _override(entry: dict, path: Path, index: int, variants: tuple[Variant, ...]) -> dict:
    where = f"overrides[{index}]"
    check_table(entry, OVERRIDE_RULES, path, f"{where}.")
    labels = {v.label for v in variants}
    unknown = [s for s in entry.get("stages", []) if s not in labels]
    if unknown:
        raise ProfileError(f"{path}: {where}: stage {unknown[0]!r} is not among this profile's stages")
    return entry


# --- scenes ------------------------------------------------------------------


def resolve_scene(arg: str, scenes_dir: Path = SCENES_DIR) -> Path:
    """A scene given by name means scenes/NAME.json, else, for a name the
    generator makes (randomN and the corpus' families, rtbench/scenes.py),
    GENERATED_SCENES/NAME.json; a path is used as is."""
    candidate = Path(arg)
    if candidate.is_file():
        return candidate.resolve()
    if candidate.suffix != ".json" and "/" not in arg:
        named = scenes_dir / f"{arg}.json"
        if named.is_file():
            return named.resolve()
        if scenes.recipe(arg) is not None:
            return GENERATED_SCENES / f"{arg}.json"
        known = ", ".join(sorted(p.stem for p in scenes_dir.glob("*.json")))
        raise ProfileError(
            f"no scene {arg!r}: {named} does not exist and the generator makes default, randomN and "
            f"{', '.join(f'{family}N' for family in scenes.CORPUS_FAMILIES)} only (scenes: {known})"
        )
    raise ProfileError(f"scene file {arg} does not exist")
