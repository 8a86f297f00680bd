"""The Python a command runs under: standard library only, because it runs
before the command imports pandas & co.

`python3 scripts/report.py ...`, or `scripts/report.py ...` through its
`#!/usr/bin/env python3`, starts whichever python3 comes first on PATH: on a
machine with pyenv or a virtualenv that is often one without pandas,
matplotlib, scipy or rich. The Python that has them is the one
scripts/lib/python.sh picks for the bash commands: $RT_PYTHON when set (the
Nix apps and `nix develop` set it), else (only then) Debian's
/usr/bin/python3, which scripts/setup-debian installs the packages for.
`ensure` makes the Python scripts of scripts/ (report.py, compare.py) use
that one too: when the running Python lacks a module the command needs, the
script starts again under that Python (os.execv, same arguments); where
there is none, or it lacks them too, the command stops with one paragraph
naming the missing modules and how to get them.

The script starts again at most once: the variable REEXECUTED_FROM marks the
second start, which takes it out of its environment at once, so two Pythons
never hand the script back and forth, and a command it starts later does not
inherit the mark.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import sys

DEBIAN_PYTHON = "/usr/bin/python3"
# Set, to the first Python, only in the environment of the restarted script.
REEXECUTED_FROM = "RT_PYTHON_REEXECUTED_FROM"


def missing(modules) -> list[str]:
    """The modules, of those given, that this Python cannot import (found, not imported)."""
    return [m for m in modules if importlib.util.find_spec(m) is None]


def preferred() -> str | None:
    """The Python that has the project's packages, as scripts/lib/python.sh
    chooses it: $RT_PYTHON when set (and then only that one), else Debian's
    /usr/bin/python3 when there is one; None when neither is known. A bare
    name in $RT_PYTHON (python.sh falls back to `python3`) is looked up on
    PATH; one not found there is returned as given, for the message."""
    chosen = os.environ.get("RT_PYTHON")
    if chosen:
        return chosen if os.sep in chosen else shutil.which(chosen) or chosen
    return DEBIAN_PYTHON if os.access(DEBIAN_PYTHON, os.X_OK) else None


def ensure(prog: str, needs, script: str, argv: list[str]) -> None:
    """Returns when this Python has every module in `needs`; else runs
    `script argv` under the preferred Python instead (os.execv: this process
    becomes that one), or exits with status 1 and a message."""
    first = os.environ.pop(REEXECUTED_FROM, None)
    absent = missing(needs)
    if not absent:
        return
    target = preferred()
    # Not skipped when target is this very executable: the same one may find
    # other modules when started otherwise (this one with -S or -I, say).
    if first is not None or target is None:
        sys.exit(missing_message(prog, absent, target, first=first))
    os.environ[REEXECUTED_FROM] = sys.executable
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        os.execv(target, [target, os.path.abspath(script), *argv])
    except OSError as e:  # not there, not executable, not a program
        del os.environ[REEXECUTED_FROM]
        sys.exit(missing_message(prog, absent, target, failure=e.strerror or str(e)))


def missing_message(
    prog: str, absent: list[str], target: str | None, first: str | None = None, failure: str | None = None
) -> str:
    """One paragraph: which modules the Pythons tried lack, and how to get a
    Python that has them. `target` is preferred()'s answer (None: no other
    Python known), `first` the Python that started this one under `target`,
    `failure` why `target` could not be started."""
    modules = ", ".join(absent)
    where = "$RT_PYTHON" if os.environ.get("RT_PYTHON") else f"Debian's {DEBIAN_PYTHON}"
    if first is not None:
        text = f"neither {first} nor {where} ({target}) has {modules}, which {prog} needs"
    elif failure is not None:
        text = (
            f"this Python ({sys.executable}) has no {modules}, which {prog} needs, and {where} ({target}), "
            f"which should have them, cannot be run: {failure}"
        )
    else:
        text = (
            f"this Python ({sys.executable}) has no {modules}, which {prog} needs, and no other Python is "
            f"known to have them ($RT_PYTHON is not set, there is no {DEBIAN_PYTHON})"
        )
    return (
        f"{prog}: {text}. To get them: on Debian, scripts/setup-debian installs them for {DEBIAN_PYTHON}, "
        f"which scripts/{prog} then uses, whichever python3 starts it; with Nix, `nix run .#report -- "
        "RUN_DIR...` for the report, or `nix develop`, whose $RT_PYTHON has them; elsewhere, install them for "
        "a Python and name it in $RT_PYTHON."
    )
