"""Every committed reference report regenerates from its committed run
(data/reference-runs/README.md): a report in the repository is what the kit
makes of its data, not a hand-edited page.

The rule, on every supported release (Debian 12 and Debian 13 alike):

- README.md, tables/ and data/ regenerate byte for byte. They are the kit's
  numbers and text, so they must not depend on the pandas, NumPy or Python
  version: where a library's output changed (a row order, a last digit), the
  kit's code makes it explicit rather than this test looking away.
- plots/ regenerates byte for byte only under the matplotlib that drew the
  committed figures (FIGURES_MATPLOTLIB, Debian 12's; the references are
  generated there), and with NumPy's AVX-512 code switched off: on a CPU
  that has it, NumPy's AVX-512 logarithm differs from the scalar one in the
  last bit, which moves anti-aliased edges of the log-log figure
  (cost_vs_spheres.png) by 1/255 on 16 to 93 pixels; the committed
  figures were drawn without it. Another matplotlib draws the same figure
  with other bytes (anti-aliasing, SVG path data), so under it each figure
  must only be there, and be a PNG that decodes to the same pixel size, or
  an SVG that parses with the same width, height and viewBox, as the
  committed one.
- Either way the report has exactly the committed set of files.
"""

import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import matplotlib
import matplotlib.image
import pytest

from rtbench import report_writer

# (report directory, its committed run), as data/reference-runs/README.md lists them.
REFERENCES = [
    ("report/gpu-machine", "data/reference-runs/gpu-machine.tar.xz"),
    ("report/gpu-machine-scene-size", "data/reference-runs/gpu-machine-scene-size.tar.xz"),
    ("report/two-core-counters", "data/reference-runs/two-core-counters.tar.xz"),
    ("report", "data/reference-runs/two-core-paper.tar.xz"),
    ("report/two-core-paper-o0", "data/reference-runs/two-core-paper-o0.tar.xz"),
    ("report/gpu-machine-paper", "data/reference-runs/gpu-machine-paper.tar.xz"),
    ("report/gpu-machine-paper-o0", "data/reference-runs/gpu-machine-paper-o0.tar.xz"),
]
# The thesis' findings of the paper profile on both machines and both builds,
# side by side (docs/results.md, "Which of the thesis' findings hold where"),
# and the runs behind it in its column order.
FINDINGS_SIDE_BY_SIDE = "report/thesis-findings.md"
FINDINGS_RUNS = [
    "data/reference-runs/two-core-paper-o0.tar.xz",
    "data/reference-runs/two-core-paper.tar.xz",
    "data/reference-runs/gpu-machine-paper-o0.tar.xz",
    "data/reference-runs/gpu-machine-paper.tar.xz",
]
# The matplotlib that drew the committed figures (Debian 12's).
FIGURES_MATPLOTLIB = "3.6.3"
REPORT_PARTS = ("README.md", report_writer.TABLES_DIR, report_writer.DATA_DIR, report_writer.PLOTS_DIR)
FIGURE_SUFFIXES = (".png", ".svg")
SVG_SIZE = ("width", "height", "viewBox")


def report_files(root: Path) -> dict[str, Path]:
    """The files report.py writes under root (README and its three folders
    only: report/ also holds other reports in subfolders)."""
    files = {}
    for part in REPORT_PARTS:
        path = root / part
        for f in [path] if path.is_file() else sorted(p for p in path.glob("*") if p.is_file()):
            files[f.relative_to(root).as_posix()] = f
    return files


def numpy_avx512_features() -> list[str]:
    """The AVX-512 feature groups this NumPy dispatches to on this CPU (none
    on a CPU without AVX-512): the names NPY_DISABLE_CPU_FEATURES takes."""
    try:
        from numpy._core import _multiarray_umath as umath  # NumPy 2
    except ImportError:
        from numpy.core import _multiarray_umath as umath  # NumPy 1 (Debian 12)
    return [f for f in umath.__cpu_dispatch__ if f.startswith("AVX512") and umath.__cpu_features__.get(f)]


def regenerate(repo_root: Path, run: str, out: Path, byte_for_byte_figures: bool) -> None:
    """scripts/report.py on the committed run, into out. In a process of its
    own, so that where the figures are compared byte for byte NumPy starts
    with its AVX-512 code switched off (the module docstring says why)."""
    env = {**os.environ, "RT_PYTHON": sys.executable}
    disabled = numpy_avx512_features() if byte_for_byte_figures else []
    if disabled:
        env["NPY_DISABLE_CPU_FEATURES"] = " ".join(disabled)
    done = subprocess.run(
        [sys.executable, str(repo_root / "scripts/report.py"), str(repo_root / run), "-o", str(out), "-q"],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, f"report.py {run} failed:\n{done.stdout}{done.stderr}"


def figure_size(path: Path):
    """A PNG's decoded pixel shape (height, width, channels), or an SVG's
    width, height and viewBox; fails on a file that is neither."""
    if path.suffix == ".png":
        return matplotlib.image.imread(path).shape
    root = ET.parse(path).getroot()
    assert root.tag == "{http://www.w3.org/2000/svg}svg", f"{path}: not an SVG document"
    return {key: root.get(key) for key in SVG_SIZE}


@pytest.mark.parametrize("report_dir, run", REFERENCES, ids=[r for r, _ in REFERENCES])
def test_reference_report_regenerates_from_its_run(repo_root, tmp_path, report_dir, run):
    if run is None:
        pytest.skip(f"{report_dir}: its run is not committed (data/reference-runs/README.md)")
    if not (repo_root / run).is_file():
        pytest.skip(f"{run} is not committed yet")
    same_figures = matplotlib.__version__ == FIGURES_MATPLOTLIB
    regenerate(repo_root, run, tmp_path, byte_for_byte_figures=same_figures)
    committed, regenerated = report_files(repo_root / report_dir), report_files(tmp_path)
    assert sorted(committed) == sorted(regenerated)
    byte_for_byte = [name for name in committed if same_figures or not name.endswith(FIGURE_SUFFIXES)]
    differing = [name for name in byte_for_byte if committed[name].read_bytes() != regenerated[name].read_bytes()]
    assert differing == [], f"regenerate with: scripts/report.py {run} -o {report_dir}"
    # Under another matplotlib: the figures' formats and sizes (their bytes may differ).
    figures = [name for name in committed if name not in byte_for_byte]
    resized = [name for name in figures if figure_size(committed[name]) != figure_size(regenerated[name])]
    assert resized == [], f"figures of another size than the committed ones (matplotlib {matplotlib.__version__})"


def test_the_side_by_side_findings_regenerate_from_their_runs(repo_root, tmp_path):
    runs = [str(repo_root / run) for run in FINDINGS_RUNS]
    written = tmp_path / "thesis-findings.md"
    assert report_writer.main(["--findings", *runs, "-o", str(written), "-q"]) == 0
    committed = (repo_root / FINDINGS_SIDE_BY_SIDE).read_bytes()
    assert written.read_bytes() == committed, (
        f"regenerate with: scripts/report.py --findings {' '.join(FINDINGS_RUNS)} -o {FINDINGS_SIDE_BY_SIDE}"
    )


def test_a_report_from_an_archive_is_the_report_from_its_directory(tmp_path):
    """What the regeneration rests on: an archived run reports byte for byte
    as the directory it was packed from."""
    import tarfile

    from synthetic_runs import SyntheticConfig, write_run_dir

    run = write_run_dir(
        tmp_path / "20260101T000000Z-synthetic",
        {
            SyntheticConfig(): [[4.0, 2.0, 2.1, 1.9]],
            SyntheticConfig(renderer="sequential", threads=1, lanes=1): [[9.0, 8.0, 8.2, 7.9]],
        },
    )
    packed = tmp_path / "run.tar.xz"
    with tarfile.open(packed, "w:xz") as tar:
        tar.add(run, arcname=run.name)
    assert report_writer.main([str(run), "-o", str(tmp_path / "from-dir"), "-q"]) == 0
    assert report_writer.main([str(packed), "-o", str(tmp_path / "from-archive"), "-q"]) == 0
    from_dir, from_archive = report_files(tmp_path / "from-dir"), report_files(tmp_path / "from-archive")
    assert sorted(from_dir) == sorted(from_archive)
    assert [n for n in from_dir if from_dir[n].read_bytes() != from_archive[n].read_bytes()] == []
    assert f"`{run.name}`" in (tmp_path / "from-archive" / "README.md").read_text()


# docs/compare.md's cross-machine example: the two committed runs it compares.
CROSS_MACHINE = ("data/reference-runs/two-core-gpu-machine.tar.xz", "data/reference-runs/gpu-machine-254c4fa.tar.xz")


def test_the_cross_machine_example_in_docs_is_compares_output(repo_root, tmp_path):
    """Every line of the output pasted into docs/compare.md (between its
    heading and 'How to read it') is a line of what compare writes for the
    two committed runs today: the example is real and stays so."""
    from rtbench import compare_cli

    doc = (repo_root / "docs/compare.md").read_text().split("## Worked example: two machines", 1)[1]
    pasted = doc.split("#### Comparison: new vs base", 1)[1].split("How to read it:", 1)[0]
    lines = [line for line in pasted.splitlines() if line and not line.startswith("*(")]  # the omission note
    assert len(lines) > 80
    base, new = (str(repo_root / run) for run in CROSS_MACHINE)
    assert compare_cli.main([base, new, "--all-cores", "-o", str(tmp_path), "-q"]) == 0
    written = set((tmp_path / "compare.md").read_text().splitlines())
    assert [line for line in lines if line not in written] == []
