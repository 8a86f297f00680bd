# Sourced by the bash scripts (scripts/bench, test, raytracer,
# tracy-capture-runs): the Python that has the project's packages. On Debian
# that is the system interpreter (apt installs pandas & co. for it), even
# when another python3 comes first on PATH. The Python scripts
# (scripts/report.py, compare.py) make the same choice in
# scripts/rtbench/interpreter.py when the python3 that starts them lacks the
# packages: change both together.
if [ -z "${RT_PYTHON:-}" ]; then
  if [ -x /usr/bin/python3 ]; then RT_PYTHON=/usr/bin/python3; else RT_PYTHON=python3; fi
fi
export RT_PYTHON

# rtbench COMMAND [ARGS]: replaces the calling script with the Python
# package's command (`python3 -m rtbench COMMAND`, scripts/rtbench) run by
# that Python.
rtbench() {
  local scripts
  scripts="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  PYTHONPATH="$scripts${PYTHONPATH:+:$PYTHONPATH}" exec "$RT_PYTHON" -m rtbench "$@"
}
