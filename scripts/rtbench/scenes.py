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
"""

from __future__ import annotations

import argparse
import json
import math
import random
import re
from pathlib import Path

from rtbench import atomic, schema

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


# The committed scenes: the thesis' three (their seeds are part of the
# published result) and the larger ones of the scene-size study.
COMMITTED = ("default", "random20", "random100", "random1000", "random10000")


def recipe(name: str):
    """The scene a name stands for, as a function of no arguments: `default`,
    or `randomN` (N spheres, seed N); None for any other name."""
    if name == "default":
        return default_scene
    match = RANDOM_NAME.fullmatch(name)
    if match is None:
        return None
    count = int(match.group(1))
    return lambda: random_scene(count, seed=count)


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
    parser = argparse.ArgumentParser(
        prog=prog, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "names",
        nargs="*",
        metavar="NAME",
        help=f"scene(s): default or randomN (N spheres, seed N); committed: {', '.join(COMMITTED)}",
    )
    parser.add_argument("--random", type=int, metavar="N", help="a random scene of N spheres")
    parser.add_argument("--seed", type=int, default=1, help="seed for --random (default 1)")
    parser.add_argument("-o", "--output-dir", type=Path, required=True, help="directory to write NAME.json into")
    args = parser.parse_args(argv)

    unknown = [name for name in args.names if recipe(name) is None]
    if unknown:
        parser.error(f"unknown scene {unknown[0]!r}; scenes: default, randomN (N >= 1)")
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
