"""The render model's vocabulary (docs/render-model.md section 9): every step
of the model is one word, defined under that word in the scalar kernel, the
SIMD kernel (Highway's PascalCase; packet types end in X) and the shader,
and the docs' table lists exactly these words. Renaming a twin in one
language only fails here."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# (word, docs/render-model.md section) in the model's order.
FUNCTIONS = [
    ("primaryRay", "2"),
    ("intersectSphere", "3"),
    ("hitRecord", "3, 4"),
    ("nearestHitOfAll", "3"),
    ("inverseDirection", "3"),
    ("traversalPad", "3"),
    ("boxReachable", "3"),
    ("nearestHitInBvh", "3"),
    ("nearestHit", "3"),
    ("localColor", "4"),
    ("reflectedRay", "5"),
    ("shadeBounce", "5"),
    ("traceSinglePass", "5"),
    ("foldSegment", "5"),
    ("traceTwoPass", "5"),
    ("toRgba8", "7"),
]
TYPES = [("Ray", "3"), ("RaycastHit", "3"), ("PathSegment", "5")]

SCALAR = [*sorted((REPO / "src/render/scalar").glob("*.h")), REPO / "src/render/accel/bvh.h"]
SIMD = sorted((REPO / "src/render/simd").glob("*.h")) + sorted((REPO / "src/render/simd").glob("*.cc"))
GLSL = sorted((REPO / "shaders").glob("*.comp")) + sorted((REPO / "shaders").glob("*.glsl"))


def simd_function(word: str) -> str:
    return word[0].upper() + word[1:]


def simd_type(word: str) -> str:
    return word + "X"


def text_of(files: list[Path]) -> str:
    return "\n".join(f.read_text() for f in files)


def defines_function(source: str, name: str) -> bool:
    """A definition starts at column 0 with its return type: calls are indented, comments start with //."""
    return re.search(rf"^[A-Za-z_][\w:<>, *&]*[\s*&]{name}\(", source, re.MULTILINE) is not None


def defines_type(source: str, name: str) -> bool:
    return re.search(rf"^(?:struct|class) {name} \{{", source, re.MULTILINE) is not None


def languages_missing(simd_name: str, glsl_and_scalar_name: str, defines) -> list[str]:
    """The languages in which `defines` finds no definition under the step's name."""
    wanted = [("scalar", SCALAR, glsl_and_scalar_name), ("SIMD", SIMD, simd_name), ("GLSL", GLSL, glsl_and_scalar_name)]
    return [lang for lang, files, name in wanted if not defines(text_of(files), name)]


@pytest.mark.parametrize(("word", "section"), FUNCTIONS)
def test_function_has_one_name_in_every_language(word: str, section: str) -> None:
    missing = languages_missing(simd_function(word), word, defines_function)
    assert not missing, f"{word} (section {section}) is not defined under its name in {missing}"


@pytest.mark.parametrize(("word", "section"), TYPES)
def test_type_has_one_name_in_every_language(word: str, section: str) -> None:
    missing = languages_missing(simd_type(word), word, defines_type)
    assert not missing, f"{word} (section {section}) is not defined under its name in {missing}"


def test_definition_patterns_tell_a_definition_from_a_call() -> None:
    assert defines_function("template <class D>\nHWY_INLINE RayX<D> ReflectedRay(D d) {", "ReflectedRay")
    assert defines_function("Ray reflectedRay(Ray ray, RaycastHit hit) {", "reflectedRay")
    assert not defines_function("  ray = reflectedRay(ray, hit);", "reflectedRay")
    assert not defines_function("// reflectedRay(ray, hit) is the bounce", "reflectedRay")
    assert not defines_function("Ray reflectedRayOf(Ray ray) {", "reflectedRay")
    assert defines_type("template <class D>\nstruct RayX {", "RayX")
    assert not defines_type("struct RayXY {", "RayX")


def docs_table() -> list[tuple[str, str, str, str]]:
    """Rows (section, scalar, SIMD, GLSL) of the table in docs/render-model.md section 9."""
    text = (REPO / "docs/render-model.md").read_text()
    section = text.split("\n## 9. ", 1)[1].split("\n## ", 1)[0]
    rows = re.findall(r"^\| ([\d, ]+) \| `(\w+)` \| `(\w+)` \| `(\w+)` \|$", section, re.MULTILINE)
    return [(s.strip(), a, b, c) for s, a, b, c in rows]


def test_docs_table_lists_the_vocabulary() -> None:
    want = [(s, w, simd_type(w), w) for w, s in TYPES] + [(s, w, simd_function(w), w) for w, s in FUNCTIONS]
    assert docs_table() == want


def test_push_constants_are_declared_from_one_list() -> None:
    """Both GPU renderers' shaders declare their block from RT_FRAME_CONSTANTS (shaders/gpu_interface.h), in the
    one file they include, and so does the C++ mirror."""
    assert "RT_FRAME_CONSTANTS(RT_GLSL_MEMBER)" in (REPO / "shaders/frame_inputs.glsl").read_text()
    assert '#include "frame_inputs.glsl"' in (REPO / "shaders/raytrace.comp").read_text()
    assert '#include "frame_inputs.glsl"' in (REPO / "shaders/ray_tracing_stages.glsl").read_text()
    for stage in ("raytrace.rgen", "sphere.rint", "sphere.rchit", "sphere.rmiss"):
        assert '#include "ray_tracing_stages.glsl"' in (REPO / "shaders" / stage).read_text(), stage
    assert any("RT_FRAME_CONSTANTS(RT_CPP_MEMBER)" in f.read_text() for f in (REPO / "src/gpu").rglob("*.h"))
