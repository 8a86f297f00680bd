"""Deterministic, seeded generator of the sphere scenes (docs/render-model.md section 1).

The committed scenes come from it and a test regenerates them byte for byte:

    python3 scripts/gen_scene.py default random20 random100 random1000 random10000 -o scenes/

`randomN` is N spheres with seed N (the thesis' random20 and random100, and
any other N: `gen_scene.py random10 -o /tmp/` writes /tmp/random10.json; the
bench runner generates such a scene into the run directory when a profile
names one that scenes/ lacks). A custom random scene:
python3 scripts/gen_scene.py --random 500 --seed 7 -o /tmp/ (writes
/tmp/random500-seed7.json).

How the spheres spread as N grows: up to DISC_LIMIT (100) spheres, the
thesis-era layout: a disc of radius 2 + 0.7 sqrt(N) and fixed height 3
(random20 and random100 keep their bytes). Above it the cluster grows in
all three dimensions: the disc of N = 100 (radius 9, height 3) scaled by
s = cbrt(N / 100), so its volume grows with N and the number of spheres per
unit volume stays that of random100 (a ray crosses about as many spheres per
unit length at every N). The camera's orbit radius and height scale by the
same s, so the cluster fills the same part of the 60 degree view at every N
and spheres only get smaller on screen (random100000 is random100 seen from
ten times as far, with 1000 times the spheres). The sphere radii (0.25 to 1)
do not change. (A scene of more than 100 spheres generated before this
layout, e.g. with --random 500, had the disc's fixed height: it differs.)

The corpus: families of uneven sizes and density, named like randomN (N
spheres, seed N), for the scenes where one global traversal pad or a
uniform grid pays (docs/render-model.md section 3). `groundN`: a ground
sphere of radius 1000 whose top touches y = 0 under three spheres of
radius 1 and N - 4 of radius 0.18-0.22 on a jittered unit grid (the
layout of the best-known sphere scene's cover). `clustersN`: 20 balls of
spheres, their radii 0.5-1.5 times a common one, so their densities differ
about 27-fold, in a box 8 cluster radii wide; a twentieth of the spheres
loose in the box. `crowdN`: small spheres (0.05-0.15) packed on top of a
sphere of radius at least 100, a ring of 12 spheres of radius 6 far out
around the camera. `heavytailN`: Pareto radii (index 1.2, from 0.1),
clamped to a third of the half width of the box they sit in. `nestedN`: the camera inside
a sky sphere that holds nests of 1-5 spheres, each inside its parent
(concentric or off-centre). Each family's camera orbits the origin
outside every sphere but the sky, and looks at the part that matters.
The families draw only Random.random() (its bytes are those of every
Python 3), never gauss, choice or paretovariate.
"""

from __future__ import annotations

import json
import math
import random
import re
from pathlib import Path

from rtbench import atomic, cli, schema

# Every number is written with this many decimals, so the files are stable
# across Python versions and platforms.
DECIMALS = 4


def _round(values):
    return [round(float(v), DECIMALS) + 0.0 for v in values]


def _scene(camera_position: list[float], spheres: list[dict]) -> dict:
    """A scene of the render model: the camera orbits the origin at its
    position's distance; light and render settings are the same in every scene."""
    return {
        "camera": {
            "position": camera_position,
            "fov": 60.0,
            "focusPoint": [0.0, 0.0, 0.0],
            "orbitVelocity": 0.5,
        },
        "lightData": {
            "directionalLightDirection": [-1.0, -1.0, 1.0],
            "directionalLightColor": [1.0, 1.0, 1.0],
            "ambientLightColor": [0.1, 0.1, 0.1],
        },
        "spheres": spheres,
        "render": {
            "maxDepth": 5,
            "reflectivity": 0.5,
            "shininess": 32.0,
            "specularStrength": 0.5,
            "background": [0.1, 0.15, 0.25],
        },
    }


def default_scene() -> dict:
    """Three hand-placed spheres: two mirrors of each other over a large ground sphere."""
    return _scene(
        [0.0, 1.0, -6.0],
        [
            {"position": [-1.1, 0.0, 0.0], "radius": 1.0, "color": [0.9, 0.2, 0.2]},
            {"position": [1.1, 0.0, 0.6], "radius": 1.0, "color": [0.2, 0.4, 0.9]},
            {"position": [0.0, -101.0, 0.0], "radius": 100.0, "color": [0.8, 0.8, 0.8]},
        ],
    )


# Up to this many spheres the disc layout of the thesis' scenes; above it the
# layout scales in 3D (module docstring).
DISC_LIMIT = 100
RANDOM_NAME = re.compile(r"random([1-9][0-9]*)")


def _layout(count: int) -> tuple[float, float, float]:
    """(disc radius, half height, camera orbit radius) of a random scene of
    `count` spheres: the thesis' disc up to DISC_LIMIT, then that of
    DISC_LIMIT scaled by cbrt(count / DISC_LIMIT) in every direction."""
    if count <= DISC_LIMIT:
        spread = 2.0 + 0.7 * math.sqrt(count)  # keeps density similar across counts
        return spread, 1.5, spread + 4.0
    scale = (count / DISC_LIMIT) ** (1.0 / 3.0)
    spread, half_height, orbit_radius = _layout(DISC_LIMIT)
    return spread * scale, half_height * scale, orbit_radius * scale


def random_scene(count: int, seed: int) -> dict:
    """`count` spheres scattered in a disc the orbiting camera never enters."""
    spread, half_height, orbit_radius = _layout(count)
    max_magnitude, _ = schema.scene_limits()
    if max(spread, orbit_radius) > max_magnitude:
        raise ValueError(
            f"random{count}: the cluster would reach {orbit_radius:.3g}, beyond the scene limit "
            f"{max_magnitude:g} (scene_limits in schema/rt_schema.json)"
        )
    rng = random.Random(seed)
    spheres = []
    for _ in range(count):
        radius = rng.uniform(0.25, 1.0)
        # Uniform in the disc of radius `spread - radius` (sqrt for area).
        r = (spread - radius) * math.sqrt(rng.random())
        angle = rng.uniform(0.0, 2.0 * math.pi)
        y = rng.uniform(-half_height, half_height)
        color = [rng.uniform(0.1, 1.0) for _ in range(3)]
        spheres.append(
            {
                "position": _round([r * math.cos(angle), y, r * math.sin(angle)]),
                "radius": round(radius, DECIMALS),
                "color": _round(color),
            }
        )
    return _scene(_round([0.0, 0.35 * orbit_radius, -orbit_radius]), spheres)


# --- the corpus: uneven sizes and density (module docstring) -----------------


def _between(rng: random.Random, lo: float, hi: float) -> float:
    """Uniform in [lo, hi) from rng.random() alone (stable across Pythons)."""
    return lo + (hi - lo) * rng.random()


def _colour(rng: random.Random) -> list[float]:
    return [_between(rng, 0.1, 1.0) for _ in range(3)]


def _sphere(position, radius: float, color) -> dict:
    return {"position": _round(position), "radius": round(radius, DECIMALS), "color": _round(color)}


def _in_ball(rng: random.Random, radius: float) -> list[float]:
    """Uniform in the ball of `radius` about the origin (rejection from its cube)."""
    while True:
        p = [_between(rng, -1.0, 1.0) for _ in range(3)]
        if p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= 1.0:
            return [radius * v for v in p]


def _orbit_camera(orbit_radius: float, height: float) -> list[float]:
    return _round([0.0, height, -orbit_radius])


def _check_limits(name: str, spheres: list[dict], camera: list[float]) -> None:
    max_magnitude, min_length = schema.scene_limits()
    reach = max(max(abs(v) for v in camera), *(max(map(abs, s["position"])) for s in spheres))
    if reach > max_magnitude or max(s["radius"] for s in spheres) > max_magnitude:
        raise ValueError(
            f"{name}: the scene would reach {reach:.3g}, beyond the scene limit {max_magnitude:g} "
            "(scene_limits in schema/rt_schema.json)"
        )
    if min(s["radius"] for s in spheres) < min_length:
        raise ValueError(f"{name}: a radius below the scene limit {min_length:g}")


def _need(name: str, count: int, least: int) -> None:
    if count < least:
        raise ValueError(f"{name}{count}: the family needs at least {least} spheres")


GROUND_RADIUS = 1000.0


def _on_ground(x: float, z: float, radius: float) -> float:
    """The height of a sphere of `radius` resting on the ground sphere at (x, z)."""
    return math.sqrt(max(GROUND_RADIUS * GROUND_RADIUS - x * x - z * z, 0.0)) - GROUND_RADIUS + radius


def ground_scene(count: int, seed: int) -> dict:
    """A ground sphere of radius 1000 (top at y = 0), three spheres of radius 1
    on it at x = -4, 0, 4 and count - 4 small ones on the unit cells nearest
    the origin, jittered within their cell so that none overlap."""
    _need("ground", count, 4)
    rng = random.Random(seed)
    big = [(-4.0, 0.0), (0.0, 0.0), (4.0, 0.0)]
    small = count - 4
    cells = []
    side = 2 * math.isqrt(small) // 2 + 1  # odd, a little short of the cells needed
    while len(cells) < small:
        side += 2
        half = side // 2
        cells = [
            (i, j)
            for i in range(-half, half + 1)
            for j in range(-half, half + 1)
            if all(abs(i + 0.5 - bx) > 1.5 or abs(j + 0.5 - bz) > 1.5 for bx, bz in big)
        ]
    cells.sort(key=lambda c: ((c[0] + 0.5) ** 2 + (c[1] + 0.5) ** 2, c))
    spheres = [_sphere([0.0, -GROUND_RADIUS, 0.0], GROUND_RADIUS, [0.5, 0.5, 0.5])]
    for bx, bz in big:
        spheres.append(_sphere([bx, _on_ground(bx, bz, 1.0), bz], 1.0, _colour(rng)))
    reach = 0.0
    for i, j in cells[:small]:
        radius = _between(rng, 0.18, 0.22)
        x = i + _between(rng, 0.25, 0.75)
        z = j + _between(rng, 0.25, 0.75)
        reach = max(reach, math.hypot(x, z))
        spheres.append(_sphere([x, _on_ground(x, z, radius), z], radius, _colour(rng)))
    orbit = max(reach, 5.0) * 0.85 + 2.0  # over the grid's rim, as the cover looks at the big three
    camera = _orbit_camera(orbit, 0.15 * orbit)
    _check_limits(f"ground{count}", spheres, camera)
    return _scene(camera, spheres)


CLUSTERS = 20
LOOSE_SHARE = 0.05  # of the spheres, scattered over the whole box


def cluster_layout(count: int, rng: random.Random) -> tuple[list[list[float]], list[float], float]:
    """(centres, radii) of the clusters of a clustersN scene and the box's
    half width; the first draws of the scene's generator."""
    per_cluster = max(count / CLUSTERS, 1.0)
    common = 1.5 * (per_cluster / 50.0) ** (1.0 / 3.0)
    half = 8.0 * common
    radii = [common * _between(rng, 0.5, 1.5) for _ in range(CLUSTERS)]
    centres = [
        [
            _between(rng, -half + r, half - r),
            _between(rng, -half / 2 + r, half / 2 - r),
            _between(rng, -half + r, half - r),
        ]
        for r in radii
    ]
    return centres, radii, half


def clusters_scene(count: int, seed: int) -> dict:
    """CLUSTERS balls of small spheres in a wide box (the sphere i of the
    clustered ones joins ball i mod CLUSTERS), the loose ones anywhere in it."""
    _need("clusters", count, CLUSTERS)
    rng = random.Random(seed)
    centres, radii, half = cluster_layout(count, rng)
    loose = int(count * LOOSE_SHARE)
    spheres = []
    for i in range(count - loose):
        radius = _between(rng, 0.1, 0.3)
        centre, reach = centres[i % CLUSTERS], radii[i % CLUSTERS]
        offset = _in_ball(rng, max(reach - radius, 0.0))
        spheres.append(_sphere([c + o for c, o in zip(centre, offset)], radius, _colour(rng)))
    for _ in range(loose):
        radius = _between(rng, 0.1, 0.3)
        position = [_between(rng, -half, half), _between(rng, -half / 2, half / 2), _between(rng, -half, half)]
        spheres.append(_sphere(position, radius, _colour(rng)))
    orbit = 1.6 * half
    camera = _orbit_camera(orbit, 0.35 * orbit)
    _check_limits(f"clusters{count}", spheres, camera)
    return _scene(camera, spheres)


RING = 12


def crowd_scene(count: int, seed: int) -> dict:
    """count - 13 spheres of radius 0.05-0.15 packed in a disc on top of a
    huge sphere, and a ring of RING spheres of radius 6 far outside the
    camera's orbit."""
    _need("crowd", count, RING + 2)
    rng = random.Random(seed)
    crowd = count - 1 - RING
    disc = 4.0 * math.sqrt(crowd / 1000.0)  # a thousand spheres in a disc of radius 4, 1.5 high
    huge = 100.0 * max(1.0, disc / 4.0)
    spheres = [_sphere([0.0, -huge, 0.0], huge, [0.6, 0.6, 0.6])]
    ring = 5.0 * max(disc, 2.0) + 30.0
    for k in range(RING):
        angle = 2.0 * math.pi * k / RING
        spheres.append(_sphere([ring * math.cos(angle), 3.0, ring * math.sin(angle)], 6.0, _colour(rng)))
    for _ in range(crowd):
        radius = _between(rng, 0.05, 0.15)
        r = (disc - radius) * math.sqrt(rng.random())
        angle = _between(rng, 0.0, 2.0 * math.pi)
        x, z = r * math.cos(angle), r * math.sin(angle)
        ground = math.sqrt(huge * huge - x * x - z * z) - huge
        spheres.append(_sphere([x, ground + radius + _between(rng, 0.0, 1.5), z], radius, _colour(rng)))
    orbit = 2.5 * max(disc, 2.0)
    camera = _orbit_camera(orbit, 0.3 * orbit)
    _check_limits(f"crowd{count}", spheres, camera)
    return _scene(camera, spheres)


PARETO_INDEX = 1.2
PARETO_MIN = 0.1


def heavytail_scene(count: int, seed: int) -> dict:
    """Radii Pareto-distributed (the inverse of its distribution function
    on 1 - random(), in (0, 1]) and clamped to a third of the box's half
    width; centres uniform in the box, each sphere inside it."""
    _need("heavytail", count, 1)
    rng = random.Random(seed)
    half = 2.0 * count ** (1.0 / 3.0)
    largest = half / 3.0
    spheres = []
    for _ in range(count):
        radius = min(PARETO_MIN * (1.0 - rng.random()) ** (-1.0 / PARETO_INDEX), largest)
        position = [
            _between(rng, -half + radius, half - radius),
            _between(rng, -half / 2 + radius, half / 2 - radius),
            _between(rng, -half + radius, half - radius),
        ]
        spheres.append(_sphere(position, radius, _colour(rng)))
    reach = max(math.hypot(s["position"][0], s["position"][2]) + s["radius"] for s in spheres)
    orbit = 1.1 * reach + 2.0
    camera = _orbit_camera(orbit, 0.35 * orbit)
    _check_limits(f"heavytail{count}", spheres, camera)
    return _scene(camera, spheres)


def nested_scene(count: int, seed: int) -> dict:
    """The camera orbits inside a sky sphere; in it, nests of 1-5 spheres,
    each inside its parent: concentric in every other nest, off-centre in
    the rest (the child's surface at least 2% of the parent's radius inside)."""
    _need("nested", count, 2)
    rng = random.Random(seed)
    spread, half_height, orbit = _layout(max((count - 1) // 3, 1))
    spheres = [_sphere([0.0, 0.0, 0.0], 2.0 * orbit, [0.7, 0.75, 0.8])]
    nest = 0
    while len(spheres) < count:
        depth = min(1 + int(5 * rng.random()), count - len(spheres))
        radius = _between(rng, 0.5, 1.5)
        r = (spread - radius) * math.sqrt(rng.random())
        angle = _between(rng, 0.0, 2.0 * math.pi)
        centre = [r * math.cos(angle), _between(rng, -half_height, half_height), r * math.sin(angle)]
        for level in range(depth):
            if level:
                child = radius * _between(rng, 0.4, 0.8)
                offset = [0.0, 0.0, 0.0] if nest % 2 == 0 else _in_ball(rng, 0.98 * radius - child)
                centre, radius = [c + o for c, o in zip(centre, offset)], child
            spheres.append(_sphere(centre, radius, _colour(rng)))
        nest += 1
    camera = _orbit_camera(orbit, 0.35 * orbit)
    _check_limits(f"nested{count}", spheres, camera)
    return _scene(camera, spheres)


# The corpus families by name: NAME + N is N spheres with seed N.
FAMILIES = {
    "random": random_scene,
    "ground": ground_scene,
    "clusters": clusters_scene,
    "crowd": crowd_scene,
    "heavytail": heavytail_scene,
    "nested": nested_scene,
}
CORPUS_FAMILIES = tuple(f for f in FAMILIES if f != "random")
FAMILY_NAME = re.compile(r"([a-z]+?)([1-9][0-9]*)")

# The committed scenes: the thesis' three (their seeds are part of the
# published result), the larger ones of the scene-size study and the
# corpus (small enough for the exactness tests on every traversal).
CORPUS = ("ground500", "clusters500", "crowd500", "heavytail500", "nested200")
COMMITTED = ("default", "random20", "random100", "random1000", "random10000", *CORPUS)


def family_of(name: str) -> str | None:
    """The family of a generated scene's name (`random`, `ground`, ...), None
    for `default` and any name the generator does not make."""
    match = FAMILY_NAME.fullmatch(name)
    return match.group(1) if match and match.group(1) in FAMILIES else None


def recipe(name: str):
    """The scene a name stands for, as a function of no arguments: `default`,
    or FAMILYN (N spheres, seed N; FAMILY one of FAMILIES); None for any
    other name."""
    if name == "default":
        return default_scene
    family = family_of(name)
    if family is None:
        return None
    count = int(FAMILY_NAME.fullmatch(name).group(2))
    return lambda: FAMILIES[family](count, seed=count)


def to_json(scene: dict) -> str:
    """Two-space indented JSON with each 3-vector on one line."""

    def emit(value, indent: int) -> str:
        pad = "  " * indent
        if isinstance(value, dict):
            items = [f'{pad}  "{k}": {emit(v, indent + 1)}' for k, v in value.items()]
            return "{\n" + ",\n".join(items) + "\n" + pad + "}"
        if isinstance(value, list) and value and isinstance(value[0], dict):
            items = [f"{pad}  {emit(v, indent + 1)}" for v in value]
            return "[\n" + ",\n".join(items) + "\n" + pad + "]"
        return json.dumps(value)

    return emit(scene, 0) + "\n"


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    parser = cli.command_parser(prog, __doc__)
    parser.add_argument(
        "names",
        nargs="*",
        metavar="NAME",
        help=f"scene(s): default or FAMILYN, FAMILY one of {', '.join(FAMILIES)} (N spheres, seed N); "
        f"committed: {', '.join(COMMITTED)}",
    )
    parser.add_argument("--random", type=int, metavar="N", help="a random scene of N spheres")
    parser.add_argument("--seed", type=int, default=1, help="seed for --random (default 1)")
    parser.add_argument("-o", "--output-dir", type=Path, required=True, help="directory to write NAME.json into")
    args = parser.parse_args(argv)

    unknown = [name for name in args.names if recipe(name) is None]
    if unknown:
        parser.error(
            f"unknown scene {unknown[0]!r}; scenes: default, FAMILYN (N >= 1), FAMILY one of {', '.join(FAMILIES)}"
        )
    try:
        jobs = [(name, recipe(name)()) for name in args.names]
        if args.random is not None:
            if args.random < 1:
                parser.error("--random needs at least 1 sphere")
            jobs.append((f"random{args.random}-seed{args.seed}", random_scene(args.random, args.seed)))
    except ValueError as e:
        parser.error(str(e))
    if not jobs:
        parser.error("name at least one scene or give --random N")
    if not args.output_dir.is_dir():
        parser.error(f"output directory {args.output_dir} does not exist")
    for name, scene in jobs:
        path = args.output_dir / f"{name}.json"
        atomic.write_text(path, to_json(scene))
        print(f"wrote {path} ({len(scene['spheres'])} spheres)")
    return 0
