"""The render model's vocabulary (docs/render-model.md section 9): every step
of the model is one word, defined under that word in the scalar kernel, the
SIMD kernel (Highway's PascalCase; packet types end in X) and the shader,
and the docs' table lists exactly these words with the parameters of their
one contract. A twin whose contract differs carries its own name, which the
table lists in that language's column. Renaming a twin in one language, or
changing one twin's parameters, fails here."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# (word, docs/render-model.md section, the contract's parameters) in the model's order.
FUNCTIONS = [
    ("primaryRay", "2", ("x", "y")),
    ("intersectSphere", "3", ("ray", "sphere")),
    ("hitRecord", "3, 4", ("ray", "t", "index")),
    ("nearestHitOfAll", "3", ("ray",)),
    ("inverseDirection", "3", ("direction",)),
    ("traversalPad", "3", ("origin",)),
    ("boxReachable", "3", ("lo", "hi", "ray", "inverse", "pad", "best")),
    ("nearestHitInBvh", "3", ("ray",)),
    ("nearestHit", "3", ("ray",)),
    ("localColor", "4", ("hit", "direction", "sphereColor")),
    ("reflectedRay", "5", ("ray", "hit")),
    ("shadeBounce", "5", ("hit", "ray", "color", "throughput")),
    ("traceSinglePass", "5", ("ray",)),
    ("foldSegment", "5", ("acc", "s")),
    ("traceTwoPass", "5", ("ray",)),
    ("toRgba8", "7", ("color",)),
]
TYPES = [("Ray", "3"), ("RaycastHit", "3"), ("PathSegment", "5")]

LANGUAGES = ("scalar", "SIMD", "GLSL")

# Twins whose contract differs from the word's carry their own name (section 9's notes):
OWN_NAMES = {
    # The packet's sphere test also keeps the nearer of its hit and the lane's best: a lane cannot branch.
    ("intersectSphere", "SIMD"): "IntersectSphereIntoBest",
    # The shader's boxes come widened by the scene's pad at upload, not by this ray's pad.
    ("boxReachable", "GLSL"): "prewidenedBoxReachable",
}

# Parameters a language adds to the contract's, by name, in their order. The
# scene and frame inputs (camera, spheres, BVH, shading) are parameters on
# the CPU and push constants or buffers in the shader; the SIMD kernel adds
# its lane mask `active` and its counters `tally`.
EXTRAS = {
    ("primaryRay", "scalar"): ("camera", "extent"),
    ("primaryRay", "SIMD"): ("f", "v"),  # v: the row's coordinate, computed once per row
    ("intersectSphere", "SIMD"): ("spheres", "active", "bestT", "bestIndex"),  # the best it folds its hit into
    ("hitRecord", "scalar"): ("spheres",),
    ("hitRecord", "SIMD"): ("spheres",),
    ("nearestHitOfAll", "scalar"): ("spheres",),
    ("nearestHitOfAll", "SIMD"): ("spheres", "active", "tally"),
    ("traversalPad", "scalar"): ("bvh",),
    ("traversalPad", "SIMD"): ("bvh",),
    ("boxReachable", "SIMD"): ("active", "entry"),  # entry: where each lane enters, for the wide walks' order
    ("boxReachable", "GLSL"): ("entry",),  # for the binary walk's near-child-first order
    ("nearestHitInBvh", "scalar"): ("spheres", "bvh"),
    ("nearestHitInBvh", "SIMD"): ("spheres", "active", "tally"),  # the BVH is spheres.bvh
    ("nearestHit", "scalar"): ("spheres", "bvh"),
    ("nearestHit", "SIMD"): ("f", "active", "tally"),
    ("localColor", "scalar"): ("in",),
    ("localColor", "SIMD"): ("shading",),
    ("shadeBounce", "scalar"): ("in",),
    ("shadeBounce", "SIMD"): ("shading",),
    ("traceSinglePass", "scalar"): ("in",),
    ("traceSinglePass", "SIMD"): ("f", "active", "tally"),
    ("foldSegment", "scalar"): ("in",),
    ("foldSegment", "SIMD"): ("shading",),
    ("traceTwoPass", "scalar"): ("in", "segments"),  # the shader's segments are a local array
    ("traceTwoPass", "SIMD"): ("f", "active", "scratch", "tally"),
    ("toRgba8", "SIMD"): ("out", "n"),  # stores a packet's pixels where the others return one
}

# A contract parameter a language passes in another form: as several
# parameters, or none where another parameter carries it.
SPELLED = {
    # The SIMD kernel's spheres are arrays: a sphere is its index i into them.
    ("intersectSphere", "SIMD"): {"sphere": ("i",)},
    # RaycastHitX carries the sphere's colour, gathered once with the hit (section 9).
    ("localColor", "SIMD"): {"sphereColor": ()},
}

# Words defined more than once under one name in a language: the twin is
# the one definition that matches; the others are overloads for callers
# outside the kernels and must stay as many as listed here.
OVERLOADS = {
    # render/accel/bvh.h: the same pad from the bound of |origin| (and the
    # pad model's parts), as the BVH's build and the grid's use it.
    ("traversalPad", "scalar"): 4,
    # The same test with the sphere's values given rather than its index (the wide BVH's leaf blocks).
    ("intersectSphere", "SIMD"): 2,
}

SCALAR = [*sorted((REPO / "src/render/scalar").glob("*.h")), REPO / "src/render/accel/bvh.h"]
SIMD = sorted((REPO / "src/render/simd").glob("*.h")) + sorted((REPO / "src/render/simd").glob("*.cc"))
GLSL = sorted((REPO / "shaders").glob("*.comp")) + sorted((REPO / "shaders").glob("*.glsl"))
FILES = {"scalar": SCALAR, "SIMD": SIMD, "GLSL": GLSL}


def simd_function(word: str) -> str:
    return word[0].upper() + word[1:]


def simd_type(word: str) -> str:
    return word + "X"


def twin_name(word: str, language: str) -> str:
    default = simd_function(word) if language == "SIMD" else word
    return OWN_NAMES.get((word, language), default)


def text_of(files: list[Path]) -> str:
    return "\n".join(f.read_text() for f in files)


def definition_pattern(name: str) -> str:
    """A definition starts at column 0 with its return type: calls are indented, comments start with //."""
    return rf"^[A-Za-z_][\w:<>, *&]*[\s*&]{name}\("


def defines_function(source: str, name: str) -> bool:
    return re.search(definition_pattern(name), source, re.MULTILINE) is not None


def defines_type(source: str, name: str) -> bool:
    return re.search(rf"^(?:struct|class) {name} \{{", source, re.MULTILINE) is not None


def split_top_level(text: str) -> list[str]:
    """`text` split at the commas outside any brackets (template arguments included)."""
    parts, depth, current = [], 0, ""
    for c in text:
        depth += (c in "(<[{") - (c in ")>]}")
        if c == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += c
    return [*parts, current] if current.strip() else parts


def parameter_lists(source: str, name: str, language: str) -> list[tuple[str, ...]]:
    """The parameter names, in order, of every definition of `name`: each
    parameter's last identifier (types, qualifiers, GLSL's in/out and array
    bounds dropped), and Highway's leading tag `d` left out."""
    lists = []
    for match in re.finditer(definition_pattern(name), source, re.MULTILINE):
        depth, end = 1, match.end()
        while depth:
            depth += (source[end] == "(") - (source[end] == ")")
            end += 1
        names = []
        for parameter in split_top_level(source[match.end() : end - 1]):
            declarator = re.sub(r"\[[^\]]*\]", "", parameter.split("=")[0])
            names.append(re.findall(r"\w+", declarator)[-1])
        if language == "SIMD" and names[:1] == ["d"]:
            names = names[1:]
        lists.append(tuple(names))
    return lists


def contract_mismatch(word: str, language: str, declared: tuple[str, ...], found: tuple[str, ...]) -> str | None:
    """Why `found` is not the word's contract in `language` (None: it is)."""
    spelled = SPELLED.get((word, language), {})
    expected = tuple(name for p in declared for name in spelled.get(p, (p,)))
    extras = EXTRAS.get((word, language), ())
    core = tuple(p for p in found if p not in extras)
    added = tuple(p for p in found if p in extras)
    if core != expected:
        return f"contract parameters {core}, the table's {declared} read as {expected}"
    if added != extras:
        return f"language-specific parameters {added}, documented {extras}"
    return None


def languages_missing(simd_name: str, glsl_and_scalar_name: str, defines) -> list[str]:
    """The languages in which `defines` finds no definition under the step's name."""
    wanted = [("scalar", SCALAR, glsl_and_scalar_name), ("SIMD", SIMD, simd_name), ("GLSL", GLSL, glsl_and_scalar_name)]
    return [lang for lang, files, name in wanted if not defines(text_of(files), name)]


@pytest.mark.parametrize(("word", "section", "parameters"), FUNCTIONS)
def test_function_has_one_name_in_every_language(word: str, section: str, parameters: tuple[str, ...]) -> None:
    missing = [lang for lang in LANGUAGES if not defines_function(text_of(FILES[lang]), twin_name(word, lang))]
    assert not missing, f"{word} (section {section}) is not defined under its name in {missing}"


@pytest.mark.parametrize("language", LANGUAGES)
@pytest.mark.parametrize(("word", "section", "parameters"), FUNCTIONS)
def test_twin_takes_the_contracts_parameters(
    word: str, section: str, parameters: tuple[str, ...], language: str
) -> None:
    name = twin_name(word, language)
    found = parameter_lists(text_of(FILES[language]), name, language)
    assert len(found) == OVERLOADS.get((word, language), 1), f"{language} defines {name} {len(found)} times: {found}"
    reasons = [contract_mismatch(word, language, parameters, f) for f in found]
    matching = [f for f, why in zip(found, reasons, strict=True) if why is None]
    assert len(matching) == 1, f"{language} {name} (section {section}) is not the table's contract: {reasons}"


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


def test_parameter_lists_read_names_across_the_three_spellings() -> None:
    simd = "HWY_INLINE MaskF<D> BoxReachable(D d, const float lo[3], const std::span<T, 4> hi,\n    VecF<D>& entry) {"
    assert parameter_lists(simd, "BoxReachable", "SIMD") == [("lo", "hi", "entry")]
    glsl = "bool boxReachable(vec3 lo, inout Ray ray, out float entry) {"
    assert parameter_lists(glsl, "boxReachable", "GLSL") == [("lo", "ray", "entry")]
    assert parameter_lists("vec3 inverseDirection() {", "inverseDirection", "GLSL") == [()]
    two = "float traversalPad(float a) {}\nfloat traversalPad(const Bvh& bvh, float b) {}\n  traversalPad(x, y);"
    assert parameter_lists(two, "traversalPad", "scalar") == [("a",), ("bvh", "b")]


def test_a_changed_twin_no_longer_matches_the_contract() -> None:
    box = ("lo", "hi", "ray", "inverse", "pad", "best")
    assert contract_mismatch("boxReachable", "scalar", box, box) is None
    assert contract_mismatch("boxReachable", "SIMD", box, (*box, "active", "entry")) is None
    assert contract_mismatch("boxReachable", "scalar", box, ("node", "ray", "inverse", "pad", "best"))
    assert contract_mismatch("boxReachable", "scalar", box, ("hi", "lo", "ray", "inverse", "pad", "best"))
    assert contract_mismatch("boxReachable", "SIMD", box, box)  # the documented lane mask and entry are missing
    assert contract_mismatch("boxReachable", "GLSL", box, (*box[:-1], "entry"))  # best read from a global
    sphere = ("ray", "sphere")
    packet = ("ray", "spheres", "i", "active", "bestT", "bestIndex")
    assert contract_mismatch("intersectSphere", "SIMD", sphere, packet) is None
    assert contract_mismatch("intersectSphere", "SIMD", sphere, ("spheres", "i", "ray", *packet[3:]))


def docs_tables() -> tuple[list[tuple[str, ...]], list[tuple[str, ...]]]:
    """Rows of the two tables in docs/render-model.md section 9: the types
    (section, scalar, SIMD, GLSL) and the steps (section, scalar, SIMD,
    GLSL, parameters)."""
    text = (REPO / "docs/render-model.md").read_text()
    section = text.split("\n## 9. ", 1)[1].split("\n## ", 1)[0]
    cell = r" `(\w+)` \|"
    types = re.findall(rf"^\| ([\d, ]+) \|{cell}{cell}{cell}$", section, re.MULTILINE)
    steps = re.findall(rf"^\| ([\d, ]+) \|{cell}{cell}{cell} `\(([\w, ]*)\)` \|$", section, re.MULTILINE)
    return [(s.strip(), *rest) for s, *rest in types], [(s.strip(), *rest) for s, *rest in steps]


def test_docs_table_lists_the_vocabulary() -> None:
    types, steps = docs_tables()
    assert types == [(s, w, simd_type(w), w) for w, s in TYPES]
    want = [(s, *(twin_name(w, lang) for lang in LANGUAGES), ", ".join(p)) for w, s, p in FUNCTIONS]
    assert steps == want


def test_push_constants_are_declared_from_one_list() -> None:
    """Both GPU renderers' shaders declare their block from RT_FRAME_CONSTANTS (shaders/gpu_interface.h), in the
    one file they include, and so does the C++ mirror."""
    assert "RT_FRAME_CONSTANTS(RT_GLSL_MEMBER)" in (REPO / "shaders/frame_inputs.glsl").read_text()
    assert '#include "frame_inputs.glsl"' in (REPO / "shaders/raytrace.comp").read_text()
    assert '#include "frame_inputs.glsl"' in (REPO / "shaders/ray_tracing_stages.glsl").read_text()
    for stage in ("raytrace.rgen", "sphere.rint", "sphere.rchit", "sphere.rmiss"):
        assert '#include "ray_tracing_stages.glsl"' in (REPO / "shaders" / stage).read_text(), stage
    assert any("RT_FRAME_CONSTANTS(RT_CPP_MEMBER)" in f.read_text() for f in (REPO / "src/gpu").rglob("*.h"))
