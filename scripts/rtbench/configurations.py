"""A profile (rtbench.profiles) expanded into configurations, each one
raytracer command line, and the order their repetitions run in.

Pure functions: the matrix of scenes x stages x accels x renderers x each
renderer's axes (x traversals and hybrid thresholds where the SIMD kernel
walks the BVH, x the GPU renderers' variants, x the renderer's precisions),
the profile's [[overrides]]
applied, and the schedule (round-robin, shuffle or blocked). A generated
scene keeps its stand-in path under profiles.GENERATED_SCENES until the
bench runner writes it into the run directory (place_generated_scenes).
"""

from __future__ import annotations

import itertools
import random
import re
from dataclasses import dataclass, replace
from pathlib import Path

from rtbench import names
from rtbench.profiles import (
    AGREEMENT_KEY,
    GENERATED_SCENES,
    OVERRIDE_AXES,
    OVERRIDE_AXIS_KEYS,
    PRECISIONS_KEY,
    RUN_AXES,
    SIZE_AXIS,
    TOP_AXES,
    Profile,
    ProfileError,
    Variant,
)

# The raytracer options of the run-time axes (the schema's axes[].flag).
ACCEL_FLAG = names.AXIS_FLAGS[names.ACCEL]
TRAVERSAL_FLAG = names.AXIS_FLAGS[names.TRAVERSAL]
HYBRID_THRESHOLD_FLAG = names.AXIS_FLAGS[names.HYBRID_THRESHOLD]
GPU_FLAGS = {axis: names.AXIS_FLAGS[axis] for axis in names.GPU_AXES}
# The GPU axes whose values a device may lack while it runs the renderer:
# hit reordering needs VK_NV_ray_tracing_invocation_reorder, which only some
# devices offer, so the bench probes each of its values (probe_args).
PROBED_AXES = (names.GPU_RT_REORDER,)
COUNTERS_FLAG = names.AXIS_FLAGS[names.COUNTERS]
# --precision f16 needs native f16 arithmetic (the CPU's Highway target, or
# the device's shaderFloat16), which the raytracer refuses without: the bench
# probes each renderer once more at f16 (probe_args). --agreement adds the
# image of frame 0 against the double-precision reference to the metadata.
PRECISION_FLAG = names.AXIS_FLAGS[names.PRECISION]
AGREEMENT_FLAG = "--agreement"
# Every axis and the raytracer option it sets: the renderer options of the
# schema (a renderer takes those its renderers[].options lists), then RUN_AXES.
RENDERER_AXES = {**names.OPTION_FLAGS, **RUN_AXES}
# The top-level axes a profile multiplies within each accel, in schema order
# (traversal, hybrid_threshold, gpu_bvh, gpu_rt_reorder, counters), and the
# value a configuration has where one does not apply (names.axis_applies):
# no flag on its command line, an empty column.
VARIANT_AXES = tuple(axis for axis in TOP_AXES if axis != names.ACCEL)
NOT_APPLICABLE = {"choice": "", "count": None, "toggle": False}


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
    accel: str = names.BRUTE_FORCE
    # "" where none applies (names.takes_traversal); None: the kernel's default threshold.
    traversal: str = ""
    hybrid_threshold: int | None = None
    # The GPU renderers' variants, "" where none applies (names.gpu_axes_of).
    gpu_bvh: str = ""
    gpu_rt_reorder: str = ""
    counters: bool = False
    # "" where the renderer table names no precisions (the binary's f32, no flag).
    precision: str = ""
    agreement: bool = False

    @property
    def gpu_axes(self) -> dict[str, str]:
        """The configuration's GPU variants by column (names.GPU_AXES), "" where none applies."""
        return {axis: getattr(self, axis) for axis in names.GPU_AXES}

    @property
    def id(self) -> str:
        """A file-name-safe identifier, unique within a profile (the accel in
        it where it is not brute force, the traversal where it is not packets,
        the GPU variants where they are not the defaults: names.gpu_tag)."""
        accel = [] if self.accel == names.BRUTE_FORCE else [self.accel]
        parts = [
            self.scene,
            self.renderer,
            self.variant.label,
            *accel,
            *names.traversal_tag(self.traversal, self.hybrid_threshold),
            *names.gpu_tag(*self.gpu_axes.values()),
            *names.precision_tag(self.precision),
            *(f"{axis}{value}" for axis, value in self.axes),
        ]
        return re.sub(r"[^A-Za-z0-9_.-]+", "_", "-".join(parts))

    def argv(self, binary: Path, csv: Path, meta: Path) -> list[str]:
        """The raytracer command line for one repetition of this configuration."""
        argv = [str(binary), names.RENDERER_FLAGS[self.renderer], self.scene_path, *self.variant.args()]
        for axis in names.AXES:
            argv += axis_args(axis, getattr(self, axis))
        if self.agreement:
            argv.append(AGREEMENT_FLAG)
        argv += ["--width", str(self.width), "--height", str(self.height)]
        argv += ["--warmup", str(self.warmup), "--frames", str(self.frames)]
        for axis, value in self.axes:
            if RENDERER_AXES[axis]:
                argv += [RENDERER_AXES[axis], value]
        argv += [*self.args, "--csv", str(csv), "--meta", str(meta), "--quiet"]
        return argv

    def describe(self) -> dict:
        """The configuration as plain data for the manifest."""
        return {
            "id": self.id,
            "scene": self.scene,
            "scene_path": self.scene_path,
            "renderer": self.renderer,
            "stage": self.variant.label,
            "algorithm": self.variant.algorithm,
            "early_exits": list(self.variant.early_exits),
            **{axis: getattr(self, axis) for axis in names.AXES},
            "agreement": self.agreement,
            "width": self.width,
            "height": self.height,
            "warmup": self.warmup,
            "frames": self.frames,
            "axes": dict(self.axes),
            "args": list(self.args),
        }


def axis_args(axis: str, value) -> list[str]:
    """An axis' options on a command line: none where its value is
    NOT_APPLICABLE (or no precision was named), the flag alone for a toggle
    that is on, else the flag and the value."""
    if value is None or value is False or value == "":
        return []
    return [names.AXIS_FLAGS[axis]] if value is True else [names.AXIS_FLAGS[axis], str(value)]


def axis_items(axis: str, values: list, cpu_count: int) -> list[tuple[str, str]]:
    """The values of one axis as (as the profile writes it, command-line
    value) pairs. threads accept "all" (every logical core) and ranges "A..B"
    (B may be "all"; each number of a range is written as itself), so one
    profile scales with the machine it runs on. An override matches the
    written value: on a 2-core machine "all" is 2 on the command line, but
    an override of threads 2 (a scaling point) does not reach it."""
    if axis != "threads":
        return [(str(v), str(v)) for v in values]
    out: list[tuple[str, str]] = []
    for v in values:
        numbers = parse_threads(v, cpu_count)
        out += [("all", str(numbers[0]))] if v == "all" else [(str(n), str(n)) for n in numbers]
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


def expand(
    profile: Profile,
    scene_paths: list[Path],
    cpu_count: int,
    renderers: list[str] | None = None,
    forced: dict | None = None,
) -> list[Config]:
    """Every configuration of the matrix (scene x stage x accel x renderer x
    its traversals x its GPU variants x its axes), scene-major and
    renderer-innermost, so that running them in this order already
    alternates renderers. `forced` (from the command line: width, height,
    warmup, frames) wins over the profile and its overrides."""
    configs = []
    for scene_path, variant, accel, renderer in itertools.product(
        scene_paths, profile.variants, profile.accels, profile.renderers
    ):
        if renderers and renderer not in renderers:
            continue
        spec = profile.renderers[renderer]
        axes = [axis for axis in RENDERER_AXES if axis in spec]
        ids = set()  # of this scene, stage, accel and renderer
        for variant_axes, precision, combo in itertools.product(
            axis_variants(profile, renderer, names.OWN_ACCEL.get(renderer, accel)),
            spec.get(PRECISIONS_KEY, [""]),
            itertools.product(*(axis_items(a, spec[a], cpu_count) for a in axes)),
        ):
            config = Config(
                scene=scene_path.stem,
                scene_path=str(scene_path),
                renderer=renderer,
                variant=variant,
                width=profile.width,
                height=profile.height,
                warmup=profile.warmup,
                frames=profile.frames,
                axes=tuple((a, value) for a, (_, value) in zip(axes, combo)),
                args=(*profile.args, *spec["args"]),
                accel=names.OWN_ACCEL.get(renderer, accel),
                **variant_axes,
                precision=precision,
                agreement=spec[AGREEMENT_KEY],
            )
            config = apply_overrides(sized(config), profile.overrides, dict(zip(axes, (w for w, _ in combo))))
            # Two written values of one command line ("all" and 2 on 2 cores) run once, the first kept.
            # A renderer with its own structure runs once, not once per accel.
            if (
                config is None
                or config.id in ids
                or (renderer in names.OWN_ACCEL and any(c.id == config.id for c in configs))
            ):
                continue
            ids.add(config.id)
            configs.append(replace(config, **(forced or {})))
    _check_unique(configs)
    return configs


def axis_variants(profile: Profile, renderer: str, accel: str) -> list[dict]:
    """The values of the VARIANT_AXES of each configuration a renderer runs
    at an accel, in schema order: the profile's values of each axis where
    the configuration has it (names.axis_applies, given the accel and the
    values chosen before: a hybrid threshold with traversal hybrid only),
    else NOT_APPLICABLE. A count the profile leaves out runs once with the
    renderer's own (None); a toggle is the profile's setting."""
    combos = [{names.ACCEL: accel}]
    for axis in VARIANT_AXES:
        combos = [{**c, axis: value} for c in combos for value in _axis_choices(profile, axis, renderer, c)]
    return [{axis: c[axis] for axis in VARIANT_AXES} for c in combos]


def _axis_choices(profile: Profile, axis: str, renderer: str, settings: dict) -> list:
    kind = names.AXES[axis]["kind"]
    if not names.axis_applies(axis, renderer, **settings):
        return [NOT_APPLICABLE[kind]]
    chosen = profile.axis_values(axis)
    if kind == "toggle":
        return [chosen]
    return list(chosen) or [None]


def probe_args(config: dict) -> tuple[str, ...]:
    """The options of a configuration (as Config.describe gives it, the
    manifest's form) that the probe of its renderer must also pass: the
    values of the PROBED_AXES it has, and a precision other than f32, so
    that a device (or CPU) which runs the renderer but lacks what one value
    needs is found before the runs."""
    args: list[str] = []
    for axis in PROBED_AXES:
        if config.get(axis):
            args += [names.AXIS_FLAGS[axis], config[axis]]
    if names.precision_of(config.get("precision")) != names.F32:
        args += [PRECISION_FLAG, config["precision"]]
    return tuple(args)


def sized(config: Config) -> Config:
    """The configuration at the image size of its `size` axis, if it has one."""
    size = dict(config.axes).get(SIZE_AXIS)
    if size is None:
        return config
    width, height = (int(n) for n in size.split("x"))
    return replace(config, width=width, height=height)


def apply_overrides(config: Config, overrides: tuple[dict, ...], written: dict[str, str]) -> Config | None:
    """Applies the matching [[overrides]] in order; None if one says skip.
    `written`: the configuration's axis values as the profile writes them
    (axis_items), which the overrides' threads and lanes match."""
    for o in overrides:
        if not _matches(config, o, written):
            continue
        if o.get("skip"):
            return None
        changes = {k: o[k] for k in ("width", "height", "warmup", "frames") if k in o}
        if "args" in o:
            changes["args"] = (*config.args, *o["args"])
        config = replace(config, **changes)
    return config


def place_generated_scenes(configs: list[Config], written: dict[str, str]) -> list[Config]:
    """The configurations with each stand-in path of a generated scene
    (GENERATED_SCENES) replaced by the path `written` gives it."""
    return [replace(c, scene_path=written.get(c.scene_path, c.scene_path)) for c in configs]


def generated_scenes(configs: list[Config]) -> list[str]:
    """The names of the generated scenes the configurations use, in order."""
    return list(dict.fromkeys(c.scene for c in configs if Path(c.scene_path).parent == GENERATED_SCENES))


def _matches(config: Config, override: dict, written: dict[str, str]) -> bool:
    return (
        config.renderer in override.get("renderers", [config.renderer])
        and config.variant.label in override.get("stages", [config.variant.label])
        and config.scene in override.get("scenes", [config.scene])
        and all(getattr(config, axis) in override[key] for axis, key in OVERRIDE_AXIS_KEYS.items() if key in override)
        and names.precision_of(config.precision) in override.get(PRECISIONS_KEY, [names.precision_of(config.precision)])
        and all(_axis_matches(written, override, axis) for axis in OVERRIDE_AXES)
    )


def _axis_matches(written: dict[str, str], override: dict, axis: str) -> bool:
    """True where the override names no values of this axis, or the
    configuration has the axis at one of them (as the profile writes it)."""
    if axis not in override:
        return True
    value = written.get(axis)
    return value is not None and value in {str(v) for v in override[axis]}


def _check_unique(configs: list[Config]) -> None:
    seen: set[str] = set()
    for c in configs:
        if c.id in seen:
            raise ProfileError(f"configuration {c.id} appears twice (a scene, stage, accel or axis value twice?)")
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
