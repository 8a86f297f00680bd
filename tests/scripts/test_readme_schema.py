"""The docs describe the schema by hand (docs/output.md: the CSV columns and
the metadata keys; docs/architecture.md: the renderer table); this keeps
those copies in step with schema/rt_schema.json, the one definition the
binary writes from. (Named for where the tables lived before docs/.)"""

import re

from rtbench import schema

OUTPUT_PAGE = "docs/output.md"
ARCHITECTURE_PAGE = "docs/architecture.md"


def _section(text: str, heading: str) -> str:
    start = text.index(heading)
    end = text.find("\n## ", start + len(heading))
    return text[start : end if end >= 0 else len(text)]


def _page(repo_root, page: str) -> str:
    return (repo_root / page).read_text(encoding="utf-8")


def test_docs_csv_table_lists_exactly_the_schema_columns(repo_root):
    section = _section(_page(repo_root, OUTPUT_PAGE), "## Per-frame CSV")
    documented = []
    for line in section.splitlines():
        if line.startswith("| `"):
            first_cell = line.split("|")[1]
            documented += re.findall(r"`([a-z_]+)`", first_cell)
    assert documented == schema.frame_csv_columns()


def test_docs_name_every_metadata_key(repo_root):
    section = _section(_page(repo_root, OUTPUT_PAGE), "## Run metadata")
    missing = [k for k in schema.run_metadata_keys() if f"`{k}`" not in section]
    assert missing == []


def metadata_paths(*path: str):
    """Every key path below `path` that the schema fixes: ("host", "os"), ..."""
    for field in schema.run_metadata_fields(*path):
        yield (*path, field)
        yield from metadata_paths(*path, field)


def test_docs_name_every_nested_metadata_key(repo_root):
    """The keys inside the metadata's objects (the schema's `fields`) are
    named in the section too, each as a word: a key the schema gains or
    renames and docs/output.md does not fails here."""
    section = _section(_page(repo_root, OUTPUT_PAGE), "## Run metadata")
    paths = [p for key in schema.run_metadata_keys() for p in metadata_paths(key)]
    assert ("host", "cpu_model") in paths and ("build", "nix", "nixpkgs_rev") in paths, "the walk reaches every depth"
    missing = [".".join(p) for p in paths if not re.search(rf"\b{re.escape(p[-1])}\b", section)]
    assert missing == []


# --- the renderer table of docs/architecture.md, "## Renderers" --------------------------------------
RENDERER_TABLE_HEADER = "| thesis class | our renderer (`--flag`) | kernel | scheduler | code |"
RENDERER_CELL = re.compile(r"`([a-z_]+)` \(`(--[a-z-]+)`\)")
CPU_RENDERER = re.compile(r"CpuRenderer<(\w+)Kernel, (\w+)Scheduler>")


def renderer_table(text: str) -> list[list[str]]:
    """The rows of the renderer table of docs/architecture.md, as cells."""
    section = _section(text, "## Renderers")
    lines = section[section.index(RENDERER_TABLE_HEADER) :].splitlines()[2:]
    rows = []
    for line in lines:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip("|").split("|")])
    return rows


def renderer_table_disagreements(
    text: str, renderers: list[dict], kernels: list[str], schedulers: list[str]
) -> list[str]:
    """What the renderer table says otherwise than the schema's
    renderers: the names in schema order, each one's flag, kernel and
    scheduler (a renderer with neither, as gpu, must not name a CPU one),
    and the CpuRenderer<Kernel, Scheduler> its code cell names."""
    rows = renderer_table(text)
    named = [RENDERER_CELL.search(row[1]) for row in rows]
    found = [m.group(1) if m else row[1] for m, row in zip(named, rows)]
    expected = [r["name"] for r in renderers]
    if found != expected:
        return [f"renderers {found}, schema {expected}"]
    problems = []
    for r, row, m in zip(renderers, rows, named):
        kernel, scheduler, code = row[2].split()[0], row[3], row[4]
        if m.group(2) != r["flag"]:
            problems.append(f"{r['name']}: flag {m.group(2)}, schema {r['flag']}")
        if r["kernel"] != kernel and (r["kernel"] is not None or kernel in kernels):
            problems.append(f"{r['name']}: kernel {kernel}, schema {r['kernel']}")
        if r["scheduler"] != scheduler and (r["scheduler"] is not None or scheduler in schedulers):
            problems.append(f"{r['name']}: scheduler {scheduler}, schema {r['scheduler']}")
        template = CPU_RENDERER.search(code)
        pair = (template.group(1).lower(), template.group(2).lower()) if template else None
        if r["kernel"] is not None and pair != (r["kernel"], r["scheduler"]):
            problems.append(f"{r['name']}: code {code!r} is not CpuRenderer<{r['kernel']}, {r['scheduler']}>")
    return problems


def _schema_renderer_facts():
    s = schema.schema()
    return s["renderers"], [k["name"] for k in s["kernels"]], [k["name"] for k in s["schedulers"]]


def test_docs_renderer_table_is_the_schemas(repo_root):
    text = _page(repo_root, ARCHITECTURE_PAGE)
    assert len(renderer_table(text)) == len(schema.renderer_names())
    assert renderer_table_disagreements(text, *_schema_renderer_facts()) == []


def test_the_renderer_table_check_sees_each_kind_of_disagreement(repo_root):
    """Each cell the check reads, changed in a copy of the page, is found."""
    text = _page(repo_root, ARCHITECTURE_PAGE)
    table = _section(text, "## Renderers")
    edits = [
        ("| `simd_only` (`--simd-only`) | simd | serial |", "| `simd_only` (`--simd-single`) | simd | serial |"),
        ("| `tbb_only` (`--tbb-only`) | scalar | tbb |", "| `tbb_only` (`--tbb-only`) | simd | tbb |"),
        ("| `simd_tbb` (`--simd`) | simd | tbb |", "| `simd_tbb` (`--simd`) | simd | serial |"),
        ("| `gpu` (`--gpu`) | compute shader |", "| `gpu` (`--gpu`) | scalar |"),
        ("`CpuRenderer<ScalarKernel, TbbScheduler>`", "`CpuRenderer<ScalarKernel, SerialScheduler>`"),
    ]
    for old, new in edits:
        assert table.count(old) == 1, old
        changed = text.replace(old, new)
        assert renderer_table_disagreements(changed, *_schema_renderer_facts()) != [], new
    dropped = "\n".join(line for line in text.splitlines() if not line.startswith("| (none: the reference"))
    assert renderer_table_disagreements(dropped, *_schema_renderer_facts()) != []
