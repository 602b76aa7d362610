"""Long runs (issue 15): verdicts at the run lengths users run, through
`quatrot.sweep` (issue 18), so the same grids run on a laptop or a cluster.
The studies here are run by the checks (`long_runs`, `accuracy_at_length`)
at the report's lengths and by `python -m validation.bench.longrun` at
`make bench`'s; this package imports only `validation.shared`.

* `systems`: the note's experiment's systems and configurations as scenes.
* `grid`: a grid of configurations and time steps run as a sweep, read back.
* `survival`: how long each run lasts; the largest stable step against run length.
* `accuracy`: energy error against run length at equal cost; the crossover time.
* `orientation`: orientation error against run length from restart chains.
* `experiment`: the correction experiment's grids, tables, verdicts and plot.
* `at_length`: accuracy per second against run length, energy and orientation.
"""
