"""Deterministic, seeded generator of the sphere scenes (docs/render-model.md section 1).

The committed scenes come from it and a test regenerates them byte for byte:

    python3 scripts/gen_scene.py default random20 random100 -o scenes/

A custom random scene: python3 scripts/gen_scene.py --random 500 --seed 7 -o /tmp/
(writes /tmp/random500-seed7.json).
"""

from __future__ import annotations

import argparse
import json
import math
import random
from pathlib import Path

from rtbench import atomic

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


def random_scene(count: int, seed: int) -> dict:
    """`count` spheres scattered in a disc the orbiting camera never enters."""
    rng = random.Random(seed)
    spread = 2.0 + 0.7 * math.sqrt(count)  # keeps density similar across counts
    orbit_radius = spread + 4.0
    spheres = []
    for _ in range(count):
        radius = rng.uniform(0.25, 1.0)
        # Uniform in the disc of radius `spread - radius` (sqrt for area).
        r = (spread - radius) * math.sqrt(rng.random())
        angle = rng.uniform(0.0, 2.0 * math.pi)
        y = rng.uniform(-1.5, 1.5)
        color = [rng.uniform(0.1, 1.0) for _ in range(3)]
        spheres.append(
            {
                "position": _round([r * math.cos(angle), y, r * math.sin(angle)]),
                "radius": round(radius, DECIMALS),
                "color": _round(color),
            }
        )
    return _scene(_round([0.0, 0.35 * orbit_radius, -orbit_radius]), spheres)


# The thesis' three scenes; their seeds are part of the published result.
RECIPES = {
    "default": default_scene,
    "random20": lambda: random_scene(20, seed=20),
    "random100": lambda: random_scene(100, seed=100),
}


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
    parser = argparse.ArgumentParser(prog=prog, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("names", nargs="*", metavar="NAME", help=f"built-in scene(s): {', '.join(RECIPES)}")
    parser.add_argument("--random", type=int, metavar="N", help="a random scene of N spheres")
    parser.add_argument("--seed", type=int, default=1, help="seed for --random (default 1)")
    parser.add_argument("-o", "--output-dir", type=Path, required=True, help="directory to write NAME.json into")
    args = parser.parse_args(argv)

    unknown = [name for name in args.names if name not in RECIPES]
    if unknown:
        parser.error(f"unknown scene {unknown[0]!r}; built-in scenes: {', '.join(RECIPES)}")
    jobs = [(name, RECIPES[name]()) for name in args.names]
    if args.random is not None:
        if args.random < 1:
            parser.error("--random needs at least 1 sphere")
        jobs.append((f"random{args.random}-seed{args.seed}", random_scene(args.random, args.seed)))
    if not jobs:
        parser.error("name at least one scene or give --random N")
    if not args.output_dir.is_dir():
        parser.error(f"output directory {args.output_dir} does not exist")
    for name, scene in jobs:
        path = args.output_dir / f"{name}.json"
        atomic.write_text(path, to_json(scene))
        print(f"wrote {path} ({len(scene['spheres'])} spheres)")
    return 0

