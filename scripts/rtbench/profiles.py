"""Benchmark profiles: declarative run matrices (profiles/*.toml, documented in
profiles/README.md), read and checked; rtbench.configurations expands them
into configurations and a schedule.

A profile names scenes, stages (or explicit algorithm / early-exit sets),
accels (how a ray finds its nearest sphere: the schema's accels),
traversals (how the SIMD kernel walks the BVH: the schema's traversals),
the GPU renderer's walks (gpu_bvhs: the schema's list of them), the gpu_rt
renderer's hit reordering (gpu_rt_reorders) and whether the counting
renderers count their lane work (counters), renderers with
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

    def gpu_axis_values(self, key: str) -> tuple[str, ...]:
        """The values a GPU key (GPU_KEYS: gpu_bvhs, ..., gpu_rt_reorders) names."""
        return getattr(self, key)


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
    _check_traversal_keys(values, renderers, path)
    _check_gpu_keys(values, renderers, path)
    return Profile(
        name=path.stem,
        path=path,
        description=values["description"],
        preset=values["preset"],
        scenes=tuple(values["scenes"]),
        variants=variants,
        accels=tuple(values["accels"]),
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
        traversals=tuple(values["traversals"]),
        hybrid_thresholds=tuple(values.get("hybrid_thresholds", ())),
        gpu_bvhs=tuple(values["gpu_bvhs"]),
        gpu_rt_reorders=tuple(values["gpu_rt_reorders"]),
        counters=values["counters"],
        architecture=values["architecture"],
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

# The profile keys of the GPU renderers' variants -> the CSV column (names.GPU_AXES) each sets.
GPU_KEYS = {
    "gpu_bvhs": names.GPU_BVH,
    "gpu_rt_reorders": names.GPU_RT_REORDER,
}

TOP_RULES = {
    "description": Rule("str"),
    "preset": Rule("str", "release"),
    "scenes": Rule("str", shape="list"),
    "stages": Rule("stage", shape="list"),
    "accels": Rule("str", [names.BRUTE_FORCE], shape="list", choices=tuple(names.RUN_ACCELS)),
    "traversals": Rule("str", [names.PACKET], shape="list", choices=tuple(names.TRAVERSALS)),
    # --hybrid-threshold: lanes; 0 would mean the kernel's default, which leaving the key out says.
    "hybrid_thresholds": Rule("int", OPTIONAL, shape="list", minimum=1),
    # The GPU renderer's walk: --gpu-bvh (accel bvh only).
    "gpu_bvhs": Rule("str", [names.BINARY], shape="list", choices=tuple(names.GPU_BVHS)),
    # The gpu_rt renderer's variant: --gpu-rt-reorder.
    "gpu_rt_reorders": Rule("str", [names.NO_REORDER], shape="list", choices=tuple(names.GPU_RT_REORDERS)),
    "counters": Rule("bool", False),
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
PRECISIONS_KEY = "precisions"
AGREEMENT_KEY = "agreement"
RENDERER_EXTRA_RULES = {
    PRECISIONS_KEY: Rule("str", OPTIONAL, shape="list", choices=tuple(names.PRECISIONS)),
    AGREEMENT_KEY: Rule("bool", False),
    "args": Rule("str", [], shape="list"),
}
# [[overrides]]: which configurations a table matches, and what it sets there.
OVERRIDE_RULES = {
    "renderers": Rule("str", OPTIONAL, shape="list", choices=tuple(names.RENDERERS)),
    "stages": Rule("str", OPTIONAL, shape="list"),
    "scenes": Rule("str", OPTIONAL, shape="list"),
    "accels": replace(TOP_RULES["accels"], default=OPTIONAL),
    # A configuration without a traversal (names.takes_traversal) never matches them.
    "traversals": replace(TOP_RULES["traversals"], default=OPTIONAL),
    # Likewise a configuration without that GPU axis (names.gpu_axes_of) never matches them.
    **{key: replace(TOP_RULES[key], default=OPTIONAL) for key in GPU_KEYS},
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


def _check_traversal_keys(values: dict, renderers: dict, path: Path) -> None:
    """traversals, hybrid_thresholds and counters must reach a configuration:
    the SIMD kernel's renderers (with accel bvh for a traversal)."""
    if len(set(values["traversals"])) != len(values["traversals"]):
        raise ProfileError(f"{path}: traversals names a traversal twice: {values['traversals']!r}")
    if len(set(values.get("hybrid_thresholds", []))) != len(values.get("hybrid_thresholds", [])):
        raise ProfileError(f"{path}: hybrid_thresholds names a threshold twice: {values['hybrid_thresholds']!r}")
    simd = [r for r in renderers if names.runs_simd_kernel(r)]
    kernel_renderers = ", ".join(r for r in names.RENDERERS if names.runs_simd_kernel(r))
    kernel = f"the renderers of the {names.SIMD_KERNEL} kernel ({kernel_renderers})"
    if values["traversals"] != [names.PACKET] and not (simd and names.BVH in values["accels"]):
        raise ProfileError(
            f"{path}: traversals: a traversal applies to {kernel} with accel {names.BVH} only, and this "
            f"profile has {'no such renderer' if not simd else f'no accel {names.BVH}'}"
        )
    if "hybrid_thresholds" in values and names.HYBRID not in values["traversals"]:
        raise ProfileError(f"{path}: hybrid_thresholds: applies to traversal {names.HYBRID}, which traversals lacks")
    counting = ", ".join(r for r in names.RENDERERS if names.counts_lanes(r))
    if values["counters"] and not any(names.counts_lanes(r) for r in renderers):
        raise ProfileError(
            f"{path}: counters: only the renderers that count ({counting}) take it, and this profile runs none of them"
        )


def _check_gpu_keys(values: dict, renderers: dict, path: Path) -> None:
    """gpu_bvhs and gpu_rt_reorders name each variant once and, where they
    ask for more than the default, reach a
    configuration: the renderer of the axis (names.GPU_AXIS_RENDERER: gpu, or
    gpu_rt for gpu_rt_reorders), with accel bvh for gpu_bvhs."""
    for key, axis in GPU_KEYS.items():
        chosen, default = values[key], names.GPU_AXIS_VALUES[axis][1]
        renderer = names.GPU_AXIS_RENDERER[axis]
        if len(set(chosen)) != len(chosen):
            raise ProfileError(f"{path}: {key} names a value twice: {chosen!r}")
        if chosen == [default]:
            continue
        if renderer not in renderers:
            raise ProfileError(
                f"{path}: {key}: applies to the {renderer} renderer only, which this profile does not run"
            )
        if axis == names.GPU_BVH and names.BVH not in values["accels"]:
            raise ProfileError(
                f"{path}: {key}: applies to the {renderer} renderer with accel {names.BVH} only, "
                f"and this profile has no accel {names.BVH}"
            )


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
