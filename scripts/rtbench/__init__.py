"""rtbench: the benchmark kit's Python library.

Small modules of pure functions under thin command lines (`scripts/bench`,
`scripts/report.py`):

- names:    the names the library relies on, all taken from schema/rt_schema.json
- atomic:   temp-file + rename writers (nothing is ever half-written)
- profiles: declarative run matrices (profiles/*.toml) -> configurations
- noise:    machine-noise checks (CPU governor, load, spread between repetitions)
- runner:   builds the binary, runs each configuration as its own process
- load:     run directories -> one tidy pandas DataFrame, with clear errors
- stats:    median, MAD, bootstrap CI, percentiles, modified z-score outliers
- metrics:  speedup, Karp-Flatt, processor counts
- thesis:   the thesis' published numbers and what they recompute to
- tables:   Markdown and LaTeX tables
- plots:    matplotlib (Agg) figures, PNG and SVG
- report:   puts it together into report/README.md
"""
