"""rtbench: the benchmark kit's Python package, with one way in:

    python3 -m rtbench bench|report|compare|gen-scene [ARGS]   (scripts/ on PYTHONPATH)

which the commands of scripts/ wrap: `scripts/bench`, `scripts/report.py`,
`scripts/compare.py`, `scripts/gen_scene.py` (see rtbench.cli). Small
modules of pure functions:

- cli:           the command dispatcher (`python3 -m rtbench`, the scripts of scripts/)
- interpreter:   the Python scripts of scripts/ run under a Python that has their packages (stdlib only)
- schema:        reads schema/rt_schema.json, the one source of truth of names
- names:         the names the package relies on, all taken from the schema
- atomic:        temp-file + rename writers (nothing is ever half-written)
- scenes:        the seeded scene generator (gen-scene)
- profiles:      declarative run matrices (profiles/*.toml), read and checked
- configurations: a profile expanded into configurations (command lines) and their run order
- noise:         machine-noise checks (CPU governor, load, spread between repetitions)
- builder:       builds the raytracer binary of a CMake preset
- manifests:     the run directory: made, locked, its manifest of runs written and resumed
- run_status:    the status words of a manifest (ok, failed, pending, ...), one vocabulary
- runner:        runs each configuration as its own process, recording how it ended
- progress:      a build's output condensed to a line every 10 % (stdlib only; scripts/lib/steps.sh)
- bench:         the bench command: profile -> runs -> report
- load:          run directories -> one tidy pandas DataFrame, with clear errors
- stats:         median, MAD, bootstrap CI, percentiles, modified z-score outliers
- compare:       the comparison of two sets of runs (pure): matching, ratios, verdicts, environment
- compare_input: reads the two sides of a comparison from run directories or archives
- compare_output: a comparison as terminal and Markdown tables, JSON and the ratio plot
- compare_cli:   the compare command (scripts/compare.py)
- metrics:       speedup, Karp-Flatt, processor counts, cost vs spheres (power-law fits)
- thesis:        the thesis' published numbers and what they recompute to
- tables:        Markdown and LaTeX tables
- plots:         matplotlib (Agg) figures, PNG and SVG
- report_writer: the report command: puts it together into report/README.md
"""
