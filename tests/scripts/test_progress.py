"""What the scripts print while they install and build: the progress filter
on recorded ninja output (fixtures/ninja/), and scripts/lib/steps.sh with
real commands and a real CMake + Ninja build of a small project."""

import io
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from rtbench import builder, progress

FIXTURES = Path(__file__).parent / "fixtures" / "ninja"


def condensed(name: str) -> tuple[list[str], progress.BuildProgress]:
    show = progress.BuildProgress("building preset x", clock=lambda: 0.0)
    lines = [m for line in (FIXTURES / name).read_text().splitlines(keepends=True) if (m := show.feed(line))]
    return [*lines, show.summary()], show


def test_a_first_build_prints_a_line_every_ten_percent_and_a_last_one():
    lines, show = condensed("build-ok.log")  # 46 steps, as recorded from a build of the profile preset
    assert lines == [f"building preset x: {n}/46 ({100 * n // 46} %)" for n in (5, 10, 14, 19, 23, 28, 33, 37, 42)] + [
        "building preset x: ran 46 of 46 steps in 0 s"
    ]
    assert show.warnings == 0


def test_nothing_to_do_is_one_line():
    assert condensed("up-to-date.log")[0] == ["building preset x: up to date"]


def test_a_failed_build_keeps_its_whole_output_in_the_log(tmp_path):
    recorded = (FIXTURES / "build-failed.log").read_text()
    log = tmp_path / "build.log"
    done = subprocess.run(
        [sys.executable, "-m", "rtbench.progress", "building preset debug", "--log", log],
        input=recorded,
        capture_output=True,
        text=True,
        env=python_env(),
    )
    assert done.returncode == 0
    assert log.read_text() == recorded
    assert "error: ‘RT_WINDOW’ was not declared" not in done.stderr  # the error is for the caller to print
    assert done.stderr.splitlines()[-1].startswith("building preset debug: ran 21 of 45 steps in ")


def test_warnings_are_shown_and_counted():
    show = progress.BuildProgress("b", clock=lambda: 0.0)
    shown = [
        show.feed(line)
        for line in [
            "[1/3] Building CXX object a.o\n",
            "a.cpp:3:5: warning: unused 'x'\n",
            "    3 | int x;\n",
            "[3/3] Linking\n",
        ]
    ]
    assert shown == ["b: 1/3 (33 %)", "a.cpp:3:5: warning: unused 'x'", None, None]
    assert show.summary() == "b: ran 3 of 3 steps in 0 s, 1 compiler warning"
    out, log = io.StringIO(), io.StringIO()
    progress.filter_stream(["[1/1] x\n"], log, out, "c")
    assert log.getvalue() == "[1/1] x\n" and out.getvalue().startswith("c: ran 1 of 1 steps in ")


def python_env():
    scripts = str(Path(__file__).resolve().parents[2] / "scripts")
    return {**os.environ, "PYTHONPATH": scripts, "RT_PYTHON": sys.executable}


def run_steps(repo_root, tmp_path, body: str, cwd=None):
    """Runs `body` in bash with steps.sh sourced; the logs go under tmp_path."""
    script = f"set -euo pipefail\nsource {repo_root}/scripts/lib/steps.sh\n{body}"
    logs = tmp_path / "logs"
    logs.mkdir(exist_ok=True)
    return subprocess.run(
        ["bash", "-c", script, "try"],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
        env={**python_env(), "TMPDIR": str(logs)},
    )


def test_a_step_prints_one_line_and_its_whole_output_only_when_it_fails(repo_root, tmp_path):
    fine = run_steps(repo_root, tmp_path, 'step "doing fine" sh -c "echo hidden detail"')
    assert fine.returncode == 0 and fine.stdout == ""
    assert fine.stderr == "try: doing fine\n"
    after = run_steps(repo_root, tmp_path, 'step "doing fine" true\nexit 4')  # a later failure that is no step's
    assert after.returncode == 4 and after.stderr == "try: doing fine\n", "no log kept, none named"
    assert list((tmp_path / "logs").iterdir()) == []

    failing = run_steps(
        repo_root,
        tmp_path,
        'step "doing badly" sh -c "for i in 1 2 3; do echo line \\$i; done; exit 3"\necho not reached',
    )
    assert failing.returncode == 3 and "not reached" not in failing.stdout
    assert "line 1\nline 2\nline 3\n" in failing.stderr
    assert "try: doing badly failed (exit 3)" in failing.stderr
    kept = failing.stderr.split("logs kept in ")[1].strip()
    assert "line 3" in (Path(kept) / "doing-badly.log").read_text()


PROJECT = {
    "CMakePresets.json": """
        {"version": 6, "configurePresets": [{"name": "p", "generator": "Ninja", "binaryDir": "${sourceDir}/build/p"}],
         "buildPresets": [{"name": "p", "configurePreset": "p"}]}
    """,
    "CMakeLists.txt": """
        cmake_minimum_required(VERSION 3.25)
        project(tiny C)
        file(GLOB sources ${CMAKE_SOURCE_DIR}/*.c)
        add_executable(raytracer ${sources})
    """,
    **{f"f{i}.c": f"int f{i}(void) {{ return {i}; }}\n" for i in range(12)},
    "main.c": "int main(void) { return 0; }\n",
}


def test_build_step_condenses_a_real_build_and_prints_a_failed_one_in_full(repo_root, tmp_path):
    for name, text in PROJECT.items():
        (tmp_path / name).write_text(textwrap.dedent(text))
    ok = run_steps(repo_root, tmp_path, 'step "configuring preset p" cmake --preset p\nbuild_step p -j2', cwd=tmp_path)
    assert ok.returncode == 0, ok.stderr
    lines = ok.stderr.splitlines()
    assert lines[0] == "try: configuring preset p"
    assert lines[-1].startswith("try: building preset p: ran 14 of 14 steps in ")
    assert 3 <= len(lines) <= 12, lines
    assert "Building C object" not in ok.stderr

    (tmp_path / "f7.c").write_text("int f7(void) { return undeclared_name; }\n")
    failed = run_steps(repo_root, tmp_path, "build_step p -j1", cwd=tmp_path)
    assert failed.returncode != 0
    assert "undeclared_name" in failed.stderr and "FAILED:" in failed.stderr, "the whole output"
    assert f"try: building preset p failed (exit {failed.returncode})" in failed.stderr


def test_the_bench_runners_build_prints_progress_and_raises_with_the_whole_output(tmp_path):
    for name, text in PROJECT.items():
        (tmp_path / name).write_text(textwrap.dedent(text))
    out = io.StringIO()
    binary = builder.build("p", tmp_path, 2, out)
    assert binary == tmp_path / "build/p/raytracer" and binary.is_file()
    lines = out.getvalue().splitlines()
    assert lines[0] == "bench: configuring preset p" and lines[-1].startswith("bench: building preset p: ran 14 of 14 ")

    (tmp_path / "f3.c").write_text("int f3(void) { return undeclared_name; }\n")
    with pytest.raises(builder.BuildError) as failed:
        builder.build("p", tmp_path, 1, io.StringIO())
    assert "undeclared_name" in str(failed.value) and "FAILED:" in str(failed.value)
