"""The includes of src/ form no cycle and point down the layers only: each
folder (each room of src/gpu) includes from itself and from what it builds
on, never from above, so the CMake libraries can link in one direction
(src/CMakeLists.txt, src/gpu/CMakeLists.txt). The checker is tried on
small made-up trees first, so that its passing on src/ means something."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

# What each layer builds on directly; a layer may include from itself, from
# these and from whatever they build on. shaders/ is the C++ and GLSL
# shared headers, which every layer may include and which include nothing
# of src/.
BUILDS_ON: dict[str, tuple[str, ...]] = {
    "core": (),
    "scene": ("core",),
    "render": ("scene",),
    "gpu/vulkan": ("core",),
    "gpu/present": ("gpu/vulkan", "render"),
    "gpu/compute": ("gpu/present", "render"),
    # The ray-tracing pipeline renderer shares the compute room's GPU layout.
    "gpu/raytracing": ("gpu/compute",),
    "window": ("gpu/present",),
    "app": ("gpu/raytracing", "window"),
}
SHARED = "shaders"
# The CMake library of each layer; rt_gpu is the rooms of src/gpu together.
LIBRARIES: dict[str, tuple[str, ...]] = {
    "rt_core": ("core",),
    "rt_scene": ("scene",),
    "rt_render": ("render",),
    "rt_gpu_vulkan": ("gpu/vulkan",),
    "rt_gpu_present": ("gpu/present",),
    "rt_gpu_compute": ("gpu/compute",),
    "rt_gpu_raytracing": ("gpu/raytracing",),
    "rt_gpu": ("gpu/vulkan", "gpu/present", "gpu/compute", "gpu/raytracing"),
    "rt_window": ("window",),
    "rt_app": ("app",),
}
# Quoted includes that name files CMake generates in the build tree.
GENERATED = {
    "rt_schema.h",
    "rt_schema_metadata.h",
    "rt_schema_axes.h",
    "raytrace_spirv.h",
    "raytrace_f16_spirv.h",
    "raytrace_rgen_spirv.h",
    "raytrace_rgen_reorder_spirv.h",
    "sphere_rint_spirv.h",
    "sphere_rchit_spirv.h",
    "sphere_rmiss_spirv.h",
}

SOURCE_SUFFIXES = (".h", ".cpp", ".cc")
QUOTED_INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)
LINK = re.compile(r"target_link_libraries\(\s*(\w+)([^)]*)\)")


def allowed_layers(layer: str) -> set[str]:
    """`layer`, everything it builds on, directly or not, and the shared headers."""
    allowed, todo = {SHARED}, [layer]
    while todo:
        current = todo.pop()
        if current not in allowed:
            allowed.add(current)
            todo.extend(BUILDS_ON[current])
    return allowed


def layer_of(path: Path, root: Path) -> str:
    """The layer a file of `root` (a repository) belongs to: its folder under
    src/ (a room of src/gpu counts as its own layer), or shaders."""
    parts = path.relative_to(root).parts
    if parts[0] == SHARED:
        return SHARED
    assert parts[0] == "src", path
    layer = "/".join(parts[1:3]) if parts[1] == "gpu" else parts[1]
    assert layer in BUILDS_ON, f"{path}: a folder of src/ that BUILDS_ON does not place"
    return layer


def sources(root: Path) -> list[Path]:
    return sorted(
        p
        for folder in ("src", SHARED)
        if (root / folder).is_dir()
        for p in (root / folder).rglob("*")
        if p.suffix in SOURCE_SUFFIXES
    )


def resolve(name: str, including: Path, root: Path) -> Path | None:
    """Where the compiler finds a quoted include: beside the including file,
    else in the include directories (src/, shaders/); None for a generated one."""
    for directory in (including.parent, root / "src", root / SHARED):
        candidate = directory / name
        if candidate.is_file():
            return candidate.resolve()
    assert name in GENERATED, f'{including}: #include "{name}" names no file of src/ or shaders/'
    return None


def include_graph(root: Path) -> dict[Path, list[Path]]:
    """Every source file of src/ and shaders/ with the files its quoted includes name."""
    graph = {}
    for path in sources(root):
        found = (resolve(name, path, root) for name in QUOTED_INCLUDE.findall(path.read_text()))
        graph[path.resolve()] = [target for target in found if target is not None]
    return graph


def unit_graph(graph: dict[Path, list[Path]]) -> dict[Path, list[Path]]:
    """The include graph between units, a header and its source file taken
    as one (src/gpu/vulkan/context.h and .cpp are the unit .../context): a
    .cpp including a header whose own header includes the .cpp's is a cycle
    too, one that no single header shows. A -inl.h file is a fragment of each
    file that includes it (Highway's per-target scheme: a .cc includes it once
    per target; the packet kernels' two halves include the same one), so its
    includes count as that file's own, and it is no unit of its own."""
    includers: dict[Path, list[Path]] = {}
    for source, targets in graph.items():
        for target in targets:
            includers.setdefault(target, []).append(source)

    def fragment(path: Path) -> bool:
        return path.name.endswith("-inl.h") and bool(includers.get(path))

    def inlined(targets: list[Path], seen: frozenset[Path]) -> list[Path]:
        out: list[Path] = []
        for target in targets:
            if fragment(target) and target not in seen:
                out += inlined(graph.get(target, []), seen | {target})
            elif not fragment(target):
                out.append(target)
        return out

    units: dict[Path, set[Path]] = {}
    for source, targets in graph.items():
        if fragment(source):
            continue
        unit = source.with_suffix("")
        units.setdefault(unit, set()).update(
            t.with_suffix("") for t in inlined(targets, frozenset()) if t.with_suffix("") != unit
        )
    return {unit: sorted(targets) for unit, targets in units.items()}


def include_cycles(graph: dict[Path, list[Path]]) -> list[list[Path]]:
    """One cycle (as the nodes along it, the first repeated last) per back
    edge a depth-first search meets."""
    visiting, done, cycles = [], set(), []

    def visit(node: Path) -> None:
        visiting.append(node)
        for target in graph.get(node, []):
            if target in visiting:
                cycles.append([*visiting[visiting.index(target) :], target])
            elif target not in done:
                visit(target)
        visiting.pop()
        done.add(node)

    for node in graph:
        if node not in done:
            visit(node)
    return cycles


def upward_includes(root: Path, graph: dict[Path, list[Path]]) -> list[str]:
    root = root.resolve()
    return [
        f"{source.relative_to(root)} includes {target.relative_to(root)}"
        for source, targets in graph.items()
        for target in targets
        if layer_of(target, root) not in allowed_layers(layer_of(source, root))
    ]


def upward_links(root: Path) -> list[str]:
    """Links of the libraries in src/**/CMakeLists.txt to a library above them."""
    found = []
    for cmake in sorted((root / "src").rglob("CMakeLists.txt")):
        for target, arguments in LINK.findall(cmake.read_text()):
            if target not in LIBRARIES:
                continue
            allowed = set().union(*(allowed_layers(layer) for layer in LIBRARIES[target]))
            for library in arguments.split():
                if library in LIBRARIES and not set(LIBRARIES[library]) <= allowed:
                    found.append(f"{target} links {library}")
    return found


def write_tree(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return root


def test_the_layers_build_on_known_layers_without_a_cycle():
    for layer, below in BUILDS_ON.items():
        assert set(below) <= set(BUILDS_ON), layer
        assert layer not in set().union(*(allowed_layers(b) for b in below)), f"{layer} builds on itself"


def test_the_checker_finds_a_cycle_and_an_arrow_up(tmp_path):
    root = write_tree(
        tmp_path,
        {
            "src/core/a.h": '#pragma once\n#include "core/b.h"\n',
            "src/core/b.h": '#pragma once\n#include "render/c.h"\n',
            "src/render/c.h": '#pragma once\n#include "core/a.h"\n#include "rt_schema.h"\n',
            "src/render/d.cpp": '#include "c.h"\n',
            "src/CMakeLists.txt": "target_link_libraries(rt_core PUBLIC rt_render)\n",
        },
    )
    graph = include_graph(root)
    cycles = include_cycles(graph)
    assert [[p.name for p in cycle] for cycle in cycles] == [["a.h", "b.h", "c.h", "a.h"]]
    assert [[p.name for p in cycle] for cycle in include_cycles(unit_graph(graph))] == [["a", "b", "c", "a"]]
    assert upward_includes(root, graph) == ["src/core/b.h includes src/render/c.h"]
    assert upward_links(root) == ["rt_core links rt_render"]


def test_the_checker_accepts_includes_down_the_layers(tmp_path):
    root = write_tree(
        tmp_path,
        {
            "shaders/shared.h": "#define SHARED 1\n",
            "src/core/a.h": '#pragma once\n#include "shared.h"\n',
            "src/gpu/present/p.h": '#pragma once\n#include "core/a.h"\n#include "gpu/vulkan/v.h"\n',
            "src/gpu/vulkan/v.h": '#pragma once\n#include "core/a.h"\n',
            "src/gpu/compute/c.cpp": '#include "gpu/present/p.h"\n',
        },
    )
    graph = include_graph(root)
    assert include_cycles(unit_graph(graph)) == []
    assert upward_includes(root, graph) == []


def test_a_fragment_belongs_to_the_file_that_includes_it(tmp_path):
    root = write_tree(
        tmp_path,
        {
            "src/render/k.h": "#pragma once\n",
            "src/render/k.cc": '#include "render/k-inl.h"\n#include "render/k.h"\n',
            "src/render/k-inl.h": '#include "render/k.h"\n#include "render/q-inl.h"\n',
            "src/render/q-inl.h": '#include "core/a.h"\n',
            "src/core/a.h": "#pragma once\n",
        },
    )
    units = unit_graph(include_graph(root))
    assert {u.name: [t.name for t in targets] for u, targets in units.items()} == {"k": ["a"], "a": []}


def test_a_fragment_of_two_files_belongs_to_each(tmp_path):
    # The packet kernels' two halves include one fragment, which includes the
    # header of the first: no cycle; a fragment including the second half's
    # header through the first's would be one.
    files = {
        "src/render/k.h": "#pragma once\n",
        "src/render/k.cc": '#include "render/k-inl.h"\n#include "render/k.h"\n',
        "src/render/k_counted.cc": '#include "render/k-inl.h"\n#include "render/k.h"\n',
        "src/render/k-inl.h": '#include "render/k.h"\n',
    }
    units = unit_graph(include_graph(write_tree(tmp_path / "ok", files)))
    assert {u.name: [t.name for t in targets] for u, targets in units.items()} == {"k": [], "k_counted": ["k"]}
    files["src/render/k.h"] = '#pragma once\n#include "render/j.h"\n'
    files["src/render/j.h"] = "#pragma once\n"
    files["src/render/j.cpp"] = '#include "render/j.h"\n#include "render/k-inl.h"\n'
    cyclic = unit_graph(include_graph(write_tree(tmp_path / "cycle", files)))
    assert [[p.name for p in cycle] for cycle in include_cycles(cyclic)] == [["j", "k", "j"]]


def test_the_checker_finds_a_cycle_through_a_source_file(tmp_path):
    # As gpu/device.h and gpu/context.h were: device.h includes context.h,
    # whose Context is defined in context.cpp, which includes device.h.
    root = write_tree(
        tmp_path,
        {
            "src/core/context.h": "#pragma once\nclass Device;\n",
            "src/core/context.cpp": '#include "core/context.h"\n#include "core/device.h"\n',
            "src/core/device.h": '#pragma once\n#include "core/context.h"\n',
        },
    )
    graph = include_graph(root)
    assert include_cycles(graph) == []
    assert [[p.name for p in cycle] for cycle in include_cycles(unit_graph(graph))] == [
        ["context", "device", "context"]
    ]


def test_the_plumbing_room_includes_nothing_of_the_others(tmp_path):
    root = write_tree(
        tmp_path,
        {
            "src/gpu/present/p.h": "#pragma once\n",
            "src/gpu/compute/c.h": "#pragma once\n",
            "src/gpu/vulkan/v.cpp": '#include "gpu/present/p.h"\n#include "gpu/compute/c.h"\n',
        },
    )
    assert upward_includes(root, include_graph(root)) == [
        "src/gpu/vulkan/v.cpp includes src/gpu/present/p.h",
        "src/gpu/vulkan/v.cpp includes src/gpu/compute/c.h",
    ]


@pytest.fixture(scope="module")
def src_graph(repo_root: Path) -> dict[Path, list[Path]]:
    return include_graph(repo_root)


def test_src_has_no_include_cycle(src_graph, repo_root):
    cycles = [
        " -> ".join(str(p.relative_to(repo_root.resolve())) for p in cycle)
        for cycle in include_cycles(unit_graph(src_graph))
    ]
    assert cycles == []


def test_src_includes_point_down_the_layers(src_graph, repo_root):
    assert upward_includes(repo_root, src_graph) == []


def test_src_libraries_link_down_the_layers(repo_root):
    assert upward_links(repo_root) == []


def test_every_room_of_src_gpu_is_a_layer(repo_root):
    rooms = {f"gpu/{p.name}" for p in (repo_root / "src/gpu").iterdir() if p.is_dir()}
    assert rooms == {layer for layer in BUILDS_ON if layer.startswith("gpu/")}
