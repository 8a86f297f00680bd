"""The documentation's relative links lead somewhere: every Markdown link and
image in README.md and the pages under docs/ (and the other committed pages
beside them) names a file or folder that exists, and a `#anchor` into a
Markdown file names one of its headings. Also the README's promises about
itself: short, and the quick start before the findings."""

from __future__ import annotations

import re
import unicodedata
from pathlib import Path
from urllib.parse import unquote

import pytest

# The pages checked: the README, then every Markdown file below these folders.
PAGE_FOLDERS = ("docs", "profiles", "report", "data", "src")
README_MAX_WORDS = 2000
QUICK_START = "scripts/raytracer --sequential scenes/random100.json"
FINDINGS_TABLE_HEADER = "| the thesis found |"

FENCE = re.compile(r"^\s*(```|~~~)")
INLINE_CODE = re.compile(r"(`+)(?:(?!\1).)+?\1")
# [text](target "title") and ![alt](target); the text may hold one level of brackets.
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE_DEFINITION = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def pages(root: Path) -> list[Path]:
    found = [root / "README.md"]
    for folder in PAGE_FOLDERS:
        found += sorted((root / folder).rglob("*.md"))
    return found


def prose_lines(text: str):
    """(line number, line) outside fenced code blocks."""
    fenced = None
    for number, line in enumerate(text.splitlines(), 1):
        fence = FENCE.match(line)
        if fence:
            if fenced is None:
                fenced = fence.group(1)
            elif fence.group(1) == fenced:
                fenced = None
            continue
        if fenced is None:
            yield number, line


def link_targets(text: str):
    """(line number, target) of every inline link, image and reference definition."""
    for number, line in prose_lines(text):
        definition = REFERENCE_DEFINITION.match(line)
        if definition:
            yield number, definition.group(1)
            continue
        for match in INLINE_LINK.finditer(INLINE_CODE.sub("", line)):
            yield number, match.group(1)


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: its rendered text lower-cased, without
    punctuation (letters, marks, digits, `_`, `-` and spaces stay), spaces
    made hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text only
    text = text.replace("`", "").replace("*", "")
    kept = (c for c in text.lower() if c in " -_" or unicodedata.category(c)[0] in "LMN")
    return "".join(kept).replace(" ", "-")


def anchors(text: str) -> set[str]:
    """Every heading's anchor; a repeated one gets -1, -2, ... as on GitHub."""
    seen: dict[str, int] = {}
    found = set()
    for _, line in prose_lines(text):
        heading = HEADING.match(line)
        if not heading:
            continue
        base = slug(heading.group(2))
        count = seen.get(base, 0)
        seen[base] = count + 1
        found.add(base if count == 0 else f"{base}-{count}")
    return found


def broken_links(root: Path, page: Path) -> list[str]:
    """What is wrong with the page's relative links, one line each."""
    text = page.read_text(encoding="utf-8")
    problems = []
    for number, target in link_targets(text):
        if not target or SCHEME.match(target):
            continue
        path_part, _, anchor = target.partition("#")
        path_part = unquote(path_part)
        if path_part.startswith("/"):
            file = root / path_part.lstrip("/")
        elif path_part:
            file = page.parent / path_part
        else:
            file = page
        where = f"{page.relative_to(root)}:{number}: {target}"
        if not file.exists():
            problems.append(f"{where}: no such file")
        elif anchor and file.suffix == ".md" and file.is_file():
            if unquote(anchor).lower() not in anchors(file.read_text(encoding="utf-8")):
                problems.append(f"{where}: no heading with that anchor in {file.resolve().relative_to(root)}")
    return problems


def test_every_relative_link_and_anchor_resolves(repo_root):
    checked = pages(repo_root)
    assert len(checked) > 10 and all(p.is_file() for p in checked)
    problems = [problem for page in checked for problem in broken_links(repo_root, page)]
    assert problems == []


def test_the_link_check_finds_a_missing_file_and_a_missing_anchor(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "page.md").write_text("# A page\n\n## Run metadata (JSON sidecar)\n\n## Step 1. `--frames`\n")
    (tmp_path / "README.md").write_text(
        "\n".join(
            [
                "[fine](docs/page.md#run-metadata-json-sidecar) ![img](docs/page.md)",
                "[also fine](docs/page.md#step-1---frames) [here](#top) ",
                "```sh",
                "[not a link](docs/missing.md)",
                "```",
                "`[not a link either](docs/missing.md)` [web](https://example.org/x.md#y)",
                "[gone](docs/gone.md) ![gone too](docs/gone.png)",
                "[bad anchor](docs/page.md#run-metadata)",
                "# Top",
            ]
        )
    )
    problems = broken_links(tmp_path, tmp_path / "README.md")
    assert [p.split(": ", 1)[1] for p in problems] == [
        "docs/gone.md: no such file",
        "docs/gone.png: no such file",
        "docs/page.md#run-metadata: no heading with that anchor in docs/page.md",
    ]


@pytest.mark.parametrize(
    ("heading", "anchor"),
    [
        ("Benchmarks: `scripts/bench`", "benchmarks-scriptsbench"),
        ("10. Half precision (the thesis' ablation)", "10-half-precision-the-thesis-ablation"),
        ("With Nix (any Linux, x86-64 or aarch64)", "with-nix-any-linux-x86-64-or-aarch64"),
        ("`raytracer` command line", "raytracer-command-line"),
        ("Watching a scene: `--window`", "watching-a-scene---window"),
    ],
)
def test_slug_is_githubs(heading, anchor):
    assert slug(heading) == anchor


def test_readme_is_short(repo_root):
    words = len((repo_root / "README.md").read_text(encoding="utf-8").split())
    assert words <= README_MAX_WORDS


def test_readme_gives_the_quick_start_before_the_findings(repo_root):
    text = (repo_root / "README.md").read_text(encoding="utf-8")
    assert QUICK_START in text and FINDINGS_TABLE_HEADER in text
    assert text.index(QUICK_START) < text.index(FINDINGS_TABLE_HEADER)
    assert "scripts/test" in text[: text.index(FINDINGS_TABLE_HEADER)], "the test command, in the quick start"
