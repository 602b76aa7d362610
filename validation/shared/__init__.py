"""References and helpers shared by the checks (`validation.checks`), the
benchmarks (`validation.bench`), the long runs (`validation.longrun`) and the
fixture generators (`validation.fixtures`): independent reference
computations, the drivers of the other codes (LAMMPS, OpenMM), the systems
they are compared on, readers of quatrot's outputs and the check record.
Imports nothing else of `validation`."""
