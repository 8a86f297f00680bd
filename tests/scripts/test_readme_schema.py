"""README.md documents the CSV schema by hand; this keeps that copy in step
with schema/rt_schema.json, the one definition the binary writes from."""

import re

from rtbench import schema


def _section(text: str, heading: str) -> str:
    start = text.index(heading)
    end = text.find("\n## ", start + len(heading))
    return text[start : end if end >= 0 else len(text)]


def test_readme_csv_table_lists_exactly_the_schema_columns(repo_root):
    section = _section((repo_root / "README.md").read_text(encoding="utf-8"), "## Per-frame CSV")
    documented = []
    for line in section.splitlines():
        if line.startswith("| `"):
            first_cell = line.split("|")[1]
            documented += re.findall(r"`([a-z_]+)`", first_cell)
    assert documented == schema.frame_csv_columns()


def test_readme_names_every_metadata_key(repo_root):
    section = _section((repo_root / "README.md").read_text(encoding="utf-8"), "## Run metadata")
    missing = [k for k in schema.run_metadata_keys() if f"`{k}`" not in section]
    assert missing == []
