"""Shared by the profile-key tests: a profile from a few keys over random100
at stage optimized, its configurations, and what their command lines say."""

from pathlib import Path

from rtbench import configurations, names, profiles

SCENE = [Path("scenes/random100.json")]
EVERY_RENDERER = {renderer: {} for renderer in names.RENDERERS}


def profile(path: Path, **keys):
    raw = {"description": "test", "scenes": ["random100"], "stages": ["optimized"], **keys}
    return profiles.parse_profile(raw, path)


def expand(path: Path, **keys):
    return configurations.expand(profile(path, **keys), SCENE, 2)


def argv(config):
    return config.argv(Path("rt"), Path("x.csv"), Path("x.meta.json"))


def flag_value(config, flag):
    """The value the command line gives `flag`, or None where it has none."""
    line = argv(config)
    return line[line.index(flag) + 1] if flag in line else None
