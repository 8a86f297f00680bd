"""Every run-time axis of the schema (schema/rt_schema.json, axes) goes
through the raytracer's one generic path, and rtbench reads the same rules:
for each axis, renderer, value and requirement the schema declares (the
cases are made from the declarations, none is listed by hand), the binary
refuses an axis exactly where rtbench says a configuration does not have it
(names.takes_axis, names.axis_applies), naming the option, and accepts it
everywhere else."""

from __future__ import annotations

import subprocess

import pytest

from rtbench import names, schema

AXES = schema.axes()
RENDERER_FLAGS = schema.renderer_flags()
# A check the command line makes after the axes (--frames 0 without
# --window): a command line refused by it has passed every axis check, and
# nothing is rendered.
AFTER_THE_AXES = ["--frames", "0"]
AFTER_THE_AXES_MESSAGE = "raytracer: --frames: --frames 0 (run until the window is closed) needs --window"


def given(axis: str, value) -> list[str]:
    """The axis at a value on a command line; a toggle is its flag alone."""
    flag = AXES[axis]["flag"]
    return [flag] if AXES[axis]["kind"] == "toggle" else [flag, str(value)]


def values_of(axis: str) -> list:
    """The values to try: every choice, a count's minimum, a toggle on."""
    kind = AXES[axis]["kind"]
    return {"choice": AXES[axis]["values"], "count": [AXES[axis].get("minimum")], "toggle": [True]}[kind]


def satisfying(axis: str) -> tuple[list[str], dict]:
    """The options that give the axes an axis requires the first value each
    allows (and what those require in turn), and those values by axis."""
    args: list[str] = []
    settings: dict = {}
    for on, allowed in AXES[axis]["requires"].items():
        earlier_args, earlier = satisfying(on)
        args += [*earlier_args, *given(on, allowed[0])]
        settings.update(earlier, **{on: allowed[0]})
    return args, settings


def own_accel_differs(renderer: str, axis: str, value) -> bool:
    """A renderer with its own structure (schema own_accel) takes no other accel."""
    return axis == names.ACCEL and renderer in names.OWN_ACCEL and value != names.OWN_ACCEL[renderer]


def run(raytracer, repo_root, renderer: str, *args: str) -> subprocess.CompletedProcess:
    argv = [raytracer, RENDERER_FLAGS[renderer], str(repo_root / "scenes/random20.json"), *args]
    return subprocess.run(argv, capture_output=True, text=True, timeout=60)


def last_line(done: subprocess.CompletedProcess) -> str:
    return done.stderr.splitlines()[-1] if done.stderr else ""


REFUSALS = [(axis, r) for axis in AXES for r in names.RENDERERS if not names.takes_axis(r, axis)]
ACCEPTED = [
    (axis, r, v) for axis in AXES for r in names.RENDERERS if names.takes_axis(r, axis) for v in values_of(axis)
]
REQUIREMENTS = [
    (axis, on, other, r)
    for axis in AXES
    for on, allowed in AXES[axis]["requires"].items()
    for other in values_of(on)
    if other not in allowed
    for r in names.RENDERERS
    if names.takes_axis(r, axis) and not own_accel_differs(r, on, other)
]


def test_the_cases_cover_every_axis_and_requirement():
    assert {axis for axis, _ in REFUSALS} | {axis for axis, _, _ in ACCEPTED} == set(AXES)
    assert {axis for axis, _, _ in ACCEPTED} == set(AXES), "every axis has a renderer that takes it"
    assert {(axis, on) for axis, on, _, _ in REQUIREMENTS} == {(a, on) for a in AXES for on in AXES[a]["requires"]}


@pytest.mark.parametrize("axis, renderer", REFUSALS)
def test_an_axis_is_refused_by_every_renderer_that_does_not_take_it(raytracer, repo_root, axis, renderer):
    declaration = AXES[axis]
    # Where every renderer has the default (default_for_all), another value;
    # else the default, the axis' least value for a count (whose default
    # may be below it: the renderer's own).
    others = [v for v in declaration["values"] if v != declaration["default"]]
    value = others[0] if declaration["default_for_all"] else declaration["default"]
    if declaration["kind"] == "count":
        value = max(value, declaration["minimum"])
    done = run(raytracer, repo_root, renderer, *given(axis, value), *AFTER_THE_AXES)
    assert done.returncode == 2, done.stderr
    assert last_line(done).startswith(f"raytracer: {declaration['flag']}: renderer {renderer} does not take"), (
        done.stderr
    )
    assert all(RENDERER_FLAGS[r] in last_line(done) for r in names.axis_renderers(axis)), "it names who takes it"
    if declaration["default_for_all"]:
        done = run(raytracer, repo_root, renderer, *given(axis, declaration["default"]), *AFTER_THE_AXES)
        assert last_line(done) == AFTER_THE_AXES_MESSAGE, "every renderer takes the default"


@pytest.mark.parametrize("axis, renderer, value", ACCEPTED)
def test_an_axis_is_accepted_by_its_renderers_where_what_it_requires_holds(raytracer, repo_root, axis, renderer, value):
    args, settings = satisfying(axis)
    done = run(raytracer, repo_root, renderer, *args, *given(axis, value), *AFTER_THE_AXES)
    assert done.returncode == 2, done.stderr
    if own_accel_differs(renderer, axis, value):
        assert f"renderer {renderer} always uses its own {names.OWN_ACCEL[renderer]}" in last_line(done)
        return
    assert last_line(done) == AFTER_THE_AXES_MESSAGE, done.stderr
    assert names.axis_applies(axis, renderer, **settings), "rtbench gives the configuration the axis too"


@pytest.mark.parametrize("axis, on, other, renderer", REQUIREMENTS)
def test_an_axis_is_refused_where_what_it_requires_does_not_hold(raytracer, repo_root, axis, on, other, renderer):
    args, settings = satisfying(on)
    value = values_of(axis)[0]
    done = run(raytracer, repo_root, renderer, *args, *given(on, other), *given(axis, value), *AFTER_THE_AXES)
    assert done.returncode == 2, done.stderr
    flag = AXES[axis]["flag"]
    assert last_line(done).startswith(f"raytracer: {flag}: {' '.join(given(axis, value))} needs {AXES[on]['flag']} ")
    assert not names.axis_applies(axis, renderer, **settings, **{on: other}), "nor does rtbench give it the axis"
