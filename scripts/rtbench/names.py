"""The names rtbench relies on, each taken from or checked against
schema/rt_schema.json (the one source of truth, read through rtbench.schema).

Code elsewhere in rtbench imports these constants instead of spelling
column, metadata or stage names itself, so a rename in the schema fails here,
at import, instead of silently producing empty tables.
"""

from __future__ import annotations

from rtbench import schema

REPO_ROOT = schema.REPO_ROOT


def _column(name: str) -> str:
    """A frame-CSV column the library needs; fails if the schema lacks it."""
    if name not in schema.frame_csv_columns():
        raise ImportError(f"rtbench needs CSV column {name!r}, which schema/rt_schema.json does not define")
    return name


def _meta_key(name: str) -> str:
    """A metadata key the library needs; fails if the schema lacks it."""
    if name not in schema.run_metadata_keys():
        raise ImportError(f"rtbench needs metadata key {name!r}, which schema/rt_schema.json does not define")
    return name


def _meta_field(*path: str) -> str:
    """A key inside a metadata object (path: the object's key, then the key in
    it) that the library needs; fails if the schema lacks it."""
    if path[-1] not in schema.run_metadata_fields(*path[:-1]):
        raise ImportError(f"rtbench needs metadata key {'.'.join(path)!r}, which schema/rt_schema.json does not define")
    return path[-1]


def _axis(name: str) -> str:
    """A run-time axis the library needs (the schema's axes); fails if the schema lacks it."""
    if name not in AXES:
        raise ImportError(f"rtbench needs axis {name!r}, which schema/rt_schema.json does not define")
    return name


# The run-time axes (the schema's axes: accel, traversal, ..., precision),
# each declared once there with its option, values, default, the renderers
# that take it and what it requires of the axes before it; the raytracer's
# command line applies the same declarations (src/app/cli.cpp). Each axis
# is its CSV column where it has one, and its key in the metadata's config.
AXES: dict[str, dict] = schema.axes()
AXIS_FLAGS: dict[str, str] = {axis: d["flag"] for axis, d in AXES.items()}
# Each renderer's backend; "cpu" is the schema's backend of the renderers
# that run on the CPU, the others render on a Vulkan device.
BACKENDS: dict[str, str] = {name: r["backend"] for name, r in schema.renderers().items()}
CPU_BACKEND = "cpu"
# The axes of the GPU renderers: those that only renderers on a Vulkan
# device take (the compute renderer's walk, gpu_rt's reorder), in schema
# order, each a CSV column. Labels, tables and the loader treat them alike.
GPU_AXES: list[str] = [
    _column(axis)
    for axis, d in AXES.items()
    if d["renderers"] and all(BACKENDS[r] != CPU_BACKEND for r in d["renderers"])
]

# Frame CSV columns with a role in the statistics.
RUN_ID = _column("run_id")
SCENE = _column("scene")
RENDERER = _column("renderer")
THREADS = _column("threads")
LANES = _column("lanes")
SIMD_TARGET = _column("simd_target")
GRAIN = _column("grain")
PARTITION = _column("partition")
DEVICE = _column("device")
ALGORITHM = _column("algorithm")
EARLY_EXIT = _column("early_exit")
ACCEL = _axis(_column("accel"))
TRAVERSAL = _axis(_column("traversal"))
HYBRID_THRESHOLD = _axis(_column("hybrid_threshold"))
# The GPU renderer's walk of the BVH (the schema's gpu_bvhs).
GPU_BVH = _axis(_column("gpu_bvh"))
assert GPU_BVH in GPU_AXES, "schema/rt_schema.json: axes gpu_bvh"
# The ray-tracing-pipeline renderer's (gpu_rt) one variant: whether it
# reorders hits before shading (the schema's gpu_rt_reorders). It is a GPU
# axis like the one above, of another renderer (GPU_AXES).
GPU_RT_REORDER = _axis(_column("gpu_rt_reorder"))
assert GPU_RT_REORDER in GPU_AXES, "schema/rt_schema.json: axes gpu_rt_reorder"
# The GPU renderer's schedule and path: axes once, of one value each since
# their other variants were retired (the schema's retired_gpu_variants;
# RETIRED_GPU_AXES). The CSV keeps both columns, which read that value for
# the gpu renderer; the loader leaves the runs of a retired value out.
GPU_SCHEDULE = _column("gpu_schedule")
GPU_PATH = _column("gpu_path")
# The floating-point type of the render model's arithmetic (the schema's
# precisions): f32 unless the run used --precision f16, the thesis' half-
# precision experiment. A CSV written before the column lacks it: f32.
PRECISION = _axis(_column("precision"))
WIDTH = _column("width")
HEIGHT = _column("height")
FRAME = _column("frame")
WARMUP = _column("warmup")
RENDER_MS = _column("render_ms")
GPU_MS = _column("gpu_ms")
# --counters: the SIMD kernel's tallies of one frame (docs/render-model.md),
# or the GPU renderer's per subgroup (the schema's column descriptions); each
# kind of lane work as (lane slots, lanes active): the vector lanes (subgroup
# invocations) its steps occupied and those that did useful work.
RAYS = _column("rays")
RAYS_PER_DEPTH = _column("rays_per_depth")
NODE_VISITS = _column("node_visits")
SPHERE_TESTS = _column("sphere_tests")
LANE_WORK = {
    "node": (_column("node_lane_slots"), _column("node_lanes_active")),
    "sphere": (_column("sphere_lane_slots"), _column("sphere_lanes_active")),
    "shade": (_column("shade_lane_slots"), _column("shade_lanes_active")),
}
COUNTER_COLUMNS = [RAYS, RAYS_PER_DEPTH, NODE_VISITS, SPHERE_TESTS, *(c for pair in LANE_WORK.values() for c in pair)]
# rays_per_depth: the rays of depth 0, 1, ... joined by this.
DEPTH_SEPARATOR = "/"
# Columns that are empty where they do not apply (a traversal where the SIMD
# kernel does not walk a BVH, the GPU variants for the CPU renderers,
# counters without --counters), and that a CSV written before them lacks:
# the loader reads such a CSV as if they were empty.
OPTIONAL_COLUMNS = [TRAVERSAL, HYBRID_THRESHOLD, *GPU_AXES, GPU_SCHEDULE, GPU_PATH, PRECISION, *COUNTER_COLUMNS]
# The host wall time of each phase of the frame loop (the schema's phases:
# Update, Render, Present), whose sum is the time of the whole frame.
PHASE_MS = [_column(f"{phase.lower()}_ms") for phase in schema.schema()["phases"]]

# Metadata sidecar keys read by the loader.
META_CONFIG = _meta_key("config")
META_BUILD = _meta_key("build")
META_HOST = _meta_key("host")
META_SCENE = _meta_key("scene")
META_RUN_ID = _meta_key("run_id")
META_DEVICE = _meta_key("device")
META_LIBRARIES = _meta_key("libraries")
META_PREPARE_MS = _meta_key("prepare_ms")
META_ACCEL_STRUCTURE = _meta_key("accel_structure")
# Keys inside the metadata's objects.
META_SCENE_SPHERES = _meta_field(META_SCENE, "spheres")
META_SCENE_LOAD_MS = _meta_field(META_SCENE, "load_ms")
META_ACCEL_BUILD_MS = _meta_field(META_ACCEL_STRUCTURE, "build_ms")
META_CONFIG_WARMUP_FRAMES = _meta_field(META_CONFIG, "warmup_frames")
META_CONFIG_MEASURED_FRAMES = _meta_field(META_CONFIG, "measured_frames")
META_CONFIG_SIMD_TARGET = _meta_field(META_CONFIG, "simd_target")
META_HOST_OS = _meta_field(META_HOST, "os")
META_HOST_KERNEL = _meta_field(META_HOST, "kernel")
META_BUILD_VERSION = _meta_field(META_BUILD, "version")
META_BUILD_COMPILER = _meta_field(META_BUILD, "compiler")
META_BUILD_COMPILER_FLAGS = _meta_field(META_BUILD, "compiler_flags")
META_BUILD_NIX = _meta_field(META_BUILD, "nix")
META_NIXPKGS_REV = _meta_field(META_BUILD, META_BUILD_NIX, "nixpkgs_rev")
META_DEVICE_NAME = _meta_field(META_DEVICE, "name")
META_DEVICE_DRIVER_NAME = _meta_field(META_DEVICE, "driver_name")
META_DEVICE_DRIVER_VERSION = _meta_field(META_DEVICE, "driver_version")
META_DEVICE_DRIVER_INFO = _meta_field(META_DEVICE, "driver_info")
META_DEVICE_API_VERSION = _meta_field(META_DEVICE, "api_version")
# --agreement: how far the run's image of frame 0 is from the double-precision
# reference (docs/render-model.md section 8); null without it.
META_AGREEMENT = _meta_key("agreement")
# --counters: the axis that turns the counter columns on (metadata config.counters).
COUNTERS = _axis(_meta_field(META_CONFIG, "counters"))

# Columns the loader adds to the schema's columns (not in the CSV files);
# those taken from the metadata are named as its keys.
STAGE = "stage"
SPHERES = "spheres"  # the scene's sphere count, from the metadata
# Start-up times of the run, from the metadata (NaN where a sidecar lacks
# them: runs before they were recorded, accel none for the build).
LOAD_MS = META_SCENE_LOAD_MS
BUILD_MS = META_ACCEL_BUILD_MS
PREPARE_MS = META_PREPARE_MS
REPETITION = "repetition"
CONFIG_ID = "config_id"
BUILD_TYPE = _meta_field(META_BUILD, "build_type")
CPU_MODEL = _meta_field(META_HOST, "cpu_model")
LOGICAL_CORES = _meta_field(META_HOST, "logical_cores")
# host.emulation: null natively; the emulator, emulated CPU and host architecture otherwise.
HOST_EMULATION = _meta_field(META_HOST, "emulation")
EMULATOR = _meta_field(META_HOST, HOST_EMULATION, "emulator")
EMULATED_CPU = _meta_field(META_HOST, HOST_EMULATION, "cpu")
EMULATION_HOST_ARCHITECTURE = _meta_field(META_HOST, HOST_EMULATION, "host_architecture")
SOURCE = "source"
GIT_COMMIT = _meta_field(META_BUILD, "git_commit")
GIT_DIRTY = _meta_field(META_BUILD, "git_dirty")
# The agreement of a run's image with the double-precision reference, from
# the metadata's agreement object: the share of pixels within the tolerance
# (0 to 1), the PSNR in dB (infinite for identical images) and the largest
# channel difference; NaN where the run had no --agreement.
WITHIN_TOLERANCE = _meta_field(META_AGREEMENT, "within_tolerance")
PSNR_DB = _meta_field(META_AGREEMENT, "psnr_db")
MAX_CHANNEL_DIFFERENCE = _meta_field(META_AGREEMENT, "max_channel_difference")
AGREEMENT_COLUMNS = [WITHIN_TOLERANCE, PSNR_DB, MAX_CHANNEL_DIFFERENCE]

# The columns that identify one configuration in the tidy frame.
CONFIG_KEYS = [
    SCENE,
    SPHERES,
    RENDERER,
    STAGE,
    ALGORITHM,
    EARLY_EXIT,
    ACCEL,
    TRAVERSAL,
    HYBRID_THRESHOLD,
    GPU_BVH,
    GPU_SCHEDULE,
    GPU_PATH,
    GPU_RT_REORDER,
    PRECISION,
    THREADS,
    LANES,
    SIMD_TARGET,
    GRAIN,
    PARTITION,
    WIDTH,
    HEIGHT,
    DEVICE,
    BUILD_TYPE,
]

# The schema's `early_exit` column: "'+'-joined ... or 'none'".
EARLY_EXIT_SEPARATOR = "+"
NO_EARLY_EXIT = "none"

RENDERERS: list[str] = schema.renderer_names()
RENDERER_FLAGS: dict[str, str] = schema.renderer_flags()
# Renderer options (threads, lanes, grain, partition) -> flag, and which
# renderer accepts which: a renderer takes only the options the schema lists.
OPTION_FLAGS: dict[str, str] = schema.renderer_options()
RENDERER_OPTIONS: dict[str, list[str]] = {r: schema.accepted_options(r) for r in RENDERERS}
# Renderers that always use one structure whatever --accel says (embree: its own BVH).
OWN_ACCEL: dict[str, str] = {r: row["own_accel"] for r, row in schema.renderers().items() if row.get("own_accel")}
LANE_WIDTHS: list[int] = schema.lane_widths()
PARTITIONS: list[str] = list(schema.schema()["partitions"])
PRESENT_MODES: list[str] = schema.present_modes()
STAGES: dict[str, dict] = schema.stages()
ALGORITHMS: list[str] = list(schema.schema()["algorithms"])
EARLY_EXITS: list[str] = list(schema.schema()["early_exits"])
ACCELS: list[str] = [a["name"] for a in schema.schema()["accels"]]
# The accel of brute force (the thesis' algorithm, and the default).
BRUTE_FORCE: str = ACCELS[0]
# --accel auto: the binary settles on none or bvh, and its CSV says which;
# a profile names the one it measures.
AUTO_ACCEL = "auto"
assert AUTO_ACCEL in ACCELS, "schema/rt_schema.json: accels"
RUN_ACCELS: list[str] = [a for a in ACCELS if a != AUTO_ACCEL]
TRAVERSALS: list[str] = [t["name"] for t in schema.schema()["traversals"]]
# --gpu-bvh auto: the binary probes the walks and its CSV names the one it
# kept; a profile names the walks it measures.
AUTO_GPU_BVH = AUTO_ACCEL
assert AUTO_GPU_BVH in [b["name"] for b in schema.schema()["gpu_bvhs"]], "schema/rt_schema.json: gpu_bvhs"
GPU_BVHS: list[str] = [b["name"] for b in schema.schema()["gpu_bvhs"] if b["name"] != AUTO_GPU_BVH]
GPU_RT_REORDERS: list[str] = [r["name"] for r in schema.schema()["gpu_rt_reorders"]]
PRECISIONS: list[str] = [p["name"] for p in schema.schema()["precisions"]]
CSV_COLUMNS: list[str] = schema.frame_csv_columns()
COLUMN_TYPES: dict[str, str] = {c["name"]: c["type"] for c in schema.schema()["frame_csv"]}
SCHEMA_VERSION: int = schema.schema()["version"]


def _member(name: str, key: str, members: list[str]) -> str:
    """A name of one of the schema's lists that the library needs; fails if the schema lacks it."""
    if name not in members:
        raise ImportError(f"rtbench needs {key} {name!r}, which schema/rt_schema.json does not define")
    return name


# The SIMD kernel walks a BVH in one of the traversals; packets unless told
# otherwise (the only way before the traversal axis). Hybrid takes a threshold.
BVH = _member("bvh", "accels", ACCELS)
PACKET = _member("packet", "traversals", TRAVERSALS)
HYBRID = _member("hybrid", "traversals", TRAVERSALS)
# The GPU renderer (--gpu) and its walk as it ran before the GPU axes
# (binary BVH): the default, which labels leave unsaid and the loader gives
# older CSVs.
GPU_RENDERER = _member("gpu", "renderers", RENDERERS)
BINARY = _member("binary", "gpu_bvhs", GPU_BVHS)
# The retired GPU axes (schema: retired_gpu_variants): column -> (the value
# the gpu renderer's rows read now, which the loader also gives older CSVs;
# the retired values, whose runs it leaves out). Also the profile keys that
# named them once (the schema's lists: gpu_schedules, gpu_paths), and where
# the retired variants' measurements are.
RETIRED_GPU_AXES: dict[str, tuple[str, list[str]]] = schema.retired_gpu_axes()
if sorted(RETIRED_GPU_AXES) != sorted([GPU_SCHEDULE, GPU_PATH]):
    raise ImportError(
        "rtbench expects gpu_schedule and gpu_path as the retired GPU axes (schema: retired_gpu_variants)"
    )
RETIRED_GPU_PROFILE_KEYS: dict[str, str] = {r["values"]: r["column"] for r in schema.schema()["retired_gpu_variants"]}
RETIRED_GPU_RECORDS: list[str] = list(dict.fromkeys(r["record"] for r in schema.schema()["retired_gpu_variants"]))
# The ray-tracing-pipeline renderer (--gpu-rt): the driver's own acceleration
# structure, hits shaded where they were traced unless told to reorder them.
GPU_RT_RENDERER = _member("gpu_rt", "renderers", RENDERERS)
NO_REORDER = _member("none", "gpu_rt_reorders", GPU_RT_REORDERS)
# The renderers on a Vulkan device that time their frames' work on the device
# (the gpu_ms column): the compute renderer and the ray-tracing pipeline.
GPU_MS_RENDERERS: list[str] = [GPU_RENDERER, GPU_RT_RENDERER]
# The peers: the renderer a user would otherwise pick on each backend (README,
# "Architecture": Embree on the CPU, the driver's ray-tracing pipeline on the
# GPU), which ours are measured against.
EMBREE_RENDERER = _member("embree", "renderers", RENDERERS)
PEERS: list[str] = [EMBREE_RENDERER, GPU_RT_RENDERER]
# The render model's precision, which every renderer runs in (and every run
# before the precision axis ran in), and the thesis' half precision.
F32 = _member("f32", "precisions", PRECISIONS)
F16 = _member("f16", "precisions", PRECISIONS)


def run_values(axis: str) -> list[str]:
    """The values of a choice axis that a run records, in schema order: all
    but auto, which the binary settles at run time (accel, gpu_bvh: its CSV
    names what it settled on) and a profile cannot measure as such."""
    return [v for v in AXES[axis]["values"] if v != AUTO_ACCEL]


def axis_renderers(axis: str) -> list[str]:
    """The renderers that take an axis (the schema's axes[].renderers), in schema order."""
    return [r for r in RENDERERS if r in AXES[axis]["renderers"]]


def takes_axis(renderer: str, axis: str) -> bool:
    """Whether `renderer` takes the axis (with default_for_all: a value
    besides the default, which every renderer has)."""
    return renderer in AXES[axis]["renderers"]


def axis_applies(axis: str, renderer: str, **settings) -> bool:
    """Whether a configuration has the axis: its renderer takes it and
    `settings` (the values of the axes it requires, e.g. accel="bvh") hold
    what the axis requires (the schema's axes[].requires)."""
    required = AXES[axis]["requires"].items()
    return takes_axis(renderer, axis) and all(settings.get(on) in allowed for on, allowed in required)


def axis_takers(axis: str) -> str:
    """The renderers that take an axis, in words for error messages: "the
    gpu renderer", "the simd_tbb, simd_only and gpu renderers"."""
    takers = axis_renderers(axis)
    if len(takers) == 1:
        return f"the {takers[0]} renderer"
    return f"the {', '.join(takers[:-1])} and {takers[-1]} renderers"


def where_axis_applies(axis: str) -> str:
    """Which configurations have an axis, in words for error messages: "the
    gpu renderer with accel bvh" (the values a run records of each axis it
    requires)."""
    required = AXES[axis]["requires"].items()
    return axis_takers(axis) + "".join(
        f" with {on} {' or '.join(v for v in run_values(on) if v in allowed)}" for on, allowed in required
    )


# Each GPU axis: (its values in schema order, its default).
GPU_AXIS_VALUES: dict[str, tuple[list[str], str]] = {
    axis: (run_values(axis), AXES[axis]["default"]) for axis in GPU_AXES
}


def reference_renderer() -> str:
    """The speedup baseline: the schema lists the scalar reference renderer first."""
    return RENDERERS[0]


def parse_early_exits(text: str) -> frozenset[str]:
    """The set of early exits in a CSV `early_exit` value ('none' -> empty set)."""
    if text in ("", NO_EARLY_EXIT):
        return frozenset()
    return frozenset(text.split(EARLY_EXIT_SEPARATOR))


def accepts(renderer: str, option: str) -> bool:
    """Whether `renderer` takes the renderer option `option` (schema: renderers[].options)."""
    return option in RENDERER_OPTIONS.get(renderer, [])


def counts_lanes(renderer: str) -> bool:
    """Whether `renderer` takes --counters (the schema's axes: the SIMD
    kernel's renderers and the GPU renderer, which counts per subgroup)."""
    return takes_axis(renderer, COUNTERS)


def takes_precision(renderer: str) -> bool:
    """Whether `renderer` takes --precision f16 (the schema's axes: the SIMD
    kernel's renderers and the GPU renderer; the raytracer refuses it for
    the others, which compute in f32 only)."""
    return takes_axis(renderer, PRECISION)


def precision_of(value) -> str:
    """A configuration's precision: the value, or F32 where it is empty or
    missing (a CSV or a profile from before the precision axis)."""
    return value if isinstance(value, str) and value else F32


def at_f32(df):
    """The rows of a frame or summary that ran at F32: what every table not
    about precision shows, so that an f16 run never enters a comparison of
    f32 ones (the half-precision section has them)."""
    return df[df[PRECISION] == F32]


def takes_traversal(renderer: str, accel: str) -> bool:
    """Whether a configuration has a traversal: the SIMD kernel walking the BVH."""
    return axis_applies(TRAVERSAL, renderer, accel=accel)


def gpu_axes_of(renderer: str, accel: str) -> list[str]:
    """The GPU axes a configuration has: the GPU renderer's BVH with accel
    bvh only; gpu_rt's reorder; none for the other renderers."""
    return [axis for axis in GPU_AXES if axis_applies(axis, renderer, accel=accel)]


# How a label shows a GPU axis' value that is not the default: the compute
# renderer's walks name their axis already (wide, grid); a bare "hit" would
# not, so the reorder says what it reorders.
GPU_TAG_FORMATS: dict[str, str] = {GPU_RT_REORDER: "{}-reorder"}


def gpu_tag(*gpu_values) -> list[str]:
    """The GPU variants (the values of the GPU_AXES, in their order; a
    missing one is none) that are not the defaults (which labels leave
    unsaid, as before the GPU axes), in axis order: [], ["wide"],
    ["hit-reorder"]. Each tag says its axis."""
    values = dict(zip(GPU_AXES, gpu_values))
    return [
        GPU_TAG_FORMATS.get(axis, "{}").format(v)
        for axis, v in values.items()
        if isinstance(v, str) and v and v != GPU_AXIS_VALUES[axis][1]
    ]


def traversal_tag(traversal: str, hybrid_threshold=None) -> list[str]:
    """[traversal] where it is not packets (which labels leave unsaid, as
    before the traversal axis), with the hybrid threshold where there is one:
    [], ["single"], ["hybrid8"]."""
    if not traversal or traversal == PACKET:
        return []
    try:
        threshold = str(int(hybrid_threshold))
    except (TypeError, ValueError):  # None, NaN or pandas' NA: no threshold
        threshold = ""
    return [f"{traversal}{threshold}"]


def renders_on_cpu(renderer: str) -> bool:
    """True for the CPU renderers; False for those that render on a Vulkan device."""
    return BACKENDS[renderer] == CPU_BACKEND


# The renderer options that a configuration's label shows (all of them are in
# the summary table), where its renderer takes them.
LABEL_OPTIONS = (THREADS, LANES)


def label_options(row) -> list[tuple[str, int]]:
    """(option, value) of the LABEL_OPTIONS that the row's renderer takes, per the schema."""
    return [(option, row[option]) for option in LABEL_OPTIONS if accepts(row[RENDERER], option)]


def accel_tag(row) -> list[str]:
    """[accel] where a configuration does not search by brute force (the
    thesis' algorithm, which labels leave unsaid), else []; then its
    variant_tag (a row without the traversal or GPU columns has none)."""
    accel = [] if row[ACCEL] == BRUTE_FORCE else [row[ACCEL]]
    return accel + variant_tag(row)


def variant_tag(row) -> list[str]:
    """A row's traversal_tag, its gpu_tag, then its precision_tag: how the
    configuration walked its accel, and in which precision, where that is
    not the default."""
    return walk_tag(row) + precision_tag(row.get(PRECISION, ""))


def walk_tag(row) -> list[str]:
    """A row's traversal_tag, then its gpu_tag: how the configuration walked
    its accel where that is not the default."""
    gpu = [row.get(axis, "") for axis in GPU_AXES]
    return traversal_tag(row.get(TRAVERSAL, ""), row.get(HYBRID_THRESHOLD)) + gpu_tag(*gpu)


def precision_tag(precision) -> list[str]:
    """[precision] where it is not F32 (which labels leave unsaid, as before
    the precision axis), else []."""
    return [] if precision_of(precision) == F32 else [precision]


def traversal_order(traversal: str) -> int:
    """Sort key: none first, then the traversals in schema order, unknown ones last."""
    return _order(traversal, TRAVERSALS)


def gpu_order(axis: str, value: str) -> int:
    """Sort key of a GPU axis' value: none first, then the schema order (the
    default first), unknown ones last."""
    return _order(value, GPU_AXIS_VALUES[axis][0])


def precision_order(precision) -> int:
    """Sort key: the schema's precisions in order (f32 first), unknown ones last."""
    return _order(precision_of(precision), PRECISIONS)


def _order(value, members: list[str]) -> int:
    if not isinstance(value, str) or not value:
        return -1
    return members.index(value) if value in members else len(members)


def stage_of(algorithm: str, early_exit: str) -> str:
    """The thesis stage that (algorithm, early exits) amount to, per the schema's
    stages list; combinations outside it get a descriptive label so ablation
    runs stay distinguishable instead of being folded into a stage."""
    exits = parse_early_exits(early_exit)
    for name, stage in STAGES.items():
        if stage["algorithm"] == algorithm and frozenset(stage["early_exits"]) == exits:
            return name
    return f"{algorithm}[{early_exit or NO_EARLY_EXIT}]"


def stage_order(stage: str) -> int:
    """Sort key: the schema's stages in their order, then everything else."""
    names = list(STAGES)
    return names.index(stage) if stage in names else len(names)


def renderer_order(renderer: str) -> int:
    """Sort key: renderers in schema order, unknown ones last."""
    return RENDERERS.index(renderer) if renderer in RENDERERS else len(RENDERERS)


def accel_order(accel: str) -> int:
    """Sort key: accels in schema order (brute force first), unknown ones last."""
    return ACCELS.index(accel) if accel in ACCELS else len(ACCELS)
