"""The one way in: `python3 -m rtbench COMMAND [ARGS]` (with scripts/ on
PYTHONPATH), which the commands of scripts/ wrap:

    python3 -m rtbench bench [ARGS]        scripts/bench        run a benchmark profile, then report on it
    python3 -m rtbench report RUN_DIR...   scripts/report.py    the report of finished runs
    python3 -m rtbench compare BASE NEW    scripts/compare.py   new vs base, configuration by configuration
    python3 -m rtbench gen-scene NAME...   scripts/gen_scene.py the committed scenes, or a random one

`python3 -m rtbench COMMAND --help` lists a command's options. A command's
module is imported only when it runs: gen-scene needs the standard library
alone, the others pandas & co. (Command.needs). This module needs the
standard library alone too, so the Python scripts of scripts/ start with it
and move to a Python that has a command's packages (rtbench.interpreter)
before they import any.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from dataclasses import dataclass

from rtbench import interpreter


@dataclass(frozen=True)
class Command:
    module: str  # has main(argv, prog) -> exit status
    prog: str  # the name its usage and messages give: that of its wrapper in scripts/
    summary: str
    # The modules outside the standard library that the command imports, at
    # once or later (tests/scripts/test_entry_points.py checks the list):
    # interpreter.ensure looks for them before the command starts.
    needs: tuple[str, ...] = ()


COMMANDS = {
    "bench": Command(
        "rtbench.bench",
        "bench",
        "run a benchmark profile, then report on it (scripts/bench)",
        ("numpy", "pandas", "matplotlib", "rich"),
    ),
    "report": Command(
        "rtbench.report_writer",
        "report.py",
        "the report of finished runs (scripts/report.py)",
        ("numpy", "pandas", "matplotlib"),
    ),
    "compare": Command(
        "rtbench.compare_cli",
        "compare.py",
        "compare two sets of runs: faster, slower or ~ per configuration (scripts/compare.py)",
        ("numpy", "pandas", "scipy", "matplotlib", "rich"),
    ),
    "gen-scene": Command(
        "rtbench.scenes", "gen_scene.py", "write the committed scenes, or a random one (scripts/gen_scene.py)"
    ),
}


def command_parser(prog: str | None, doc: str | None) -> argparse.ArgumentParser:
    """The argument parser every command starts from: its usage under `prog`
    (its wrapper's name in scripts/), and `doc`, its module's docstring, as
    the description of --help, its line breaks kept."""
    return argparse.ArgumentParser(prog=prog, description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)


def usage() -> str:
    lines = ["usage: python3 -m rtbench {" + ",".join(COMMANDS) + "} [ARGS]", ""]
    lines += [f"  {name:<10} {c.summary}" for name, c in COMMANDS.items()]
    return "\n".join(lines)


def missing_module(prog: str, error: ModuleNotFoundError) -> str:
    """What to do when this interpreter lacks a package the command needs.
    `python3 -m rtbench` runs under whichever Python started it; the
    commands of scripts/ switch to the one that has the packages
    (rtbench.interpreter, scripts/lib/python.sh)."""
    return (
        f"{prog}: this Python ({sys.executable}) has no module {error.name!r}. Run the command through "
        "scripts/ (scripts/bench, scripts/report.py, scripts/compare.py), which runs under $RT_PYTHON, else "
        "Debian's /usr/bin/python3 (scripts/setup-debian installs pandas, matplotlib, scipy and rich for it), "
        "or start it with such a Python: PYTHONPATH=scripts /usr/bin/python3 -m rtbench ..."
    )


def script(name: str, path: str, argv: list[str]) -> int:
    """A command run as one of the Python scripts of scripts/ (`path`):
    under a Python that has the modules it needs (interpreter.ensure, which
    may start `path` again under another Python), then as run() runs it."""
    command = COMMANDS[name]
    interpreter.ensure(command.prog, command.needs, path, argv)
    return run(name, argv)


def run(name: str, argv: list[str]) -> int:
    """Runs one command with its arguments; its exit status."""
    command = COMMANDS[name]
    try:
        module = importlib.import_module(command.module)
    except ModuleNotFoundError as e:
        if (e.name or "").split(".")[0] == __package__:
            raise
        print(missing_module(command.prog, e), file=sys.stderr)
        return 1
    try:
        return module.main(argv, prog=command.prog)
    except BrokenPipeError:  # e.g. `scripts/bench --dry-run | head`
        sys.stderr.close()
        return 0


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] in (["-h"], ["--help"]):
        print(f"{usage()}\n\n{__doc__}")
        return 0
    if not argv or argv[0] not in COMMANDS:
        print(usage(), file=sys.stderr)
        if argv:
            print(f"rtbench: unknown command {argv[0]!r}", file=sys.stderr)
        return 2
    return run(argv[0], argv[1:])
