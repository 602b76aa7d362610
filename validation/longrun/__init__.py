"""Long runs (issue 15): verdicts at the run lengths users run, through
`quatrot.sweep` (issue 18), so the same grids run on a laptop or a cluster.

* `systems`: the note's experiment's systems and configurations as scenes.
* `grid`: a grid of configurations and time steps run as a sweep, read back.
* `survival`: how long each run lasts; the largest stable step against run length.
* `accuracy`: energy error against run length at equal cost; the crossover time.
"""
