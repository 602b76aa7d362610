"""What the benchmarks (`validation.bench`) and the ``performance`` check,
which reads their results, agree on."""

#: The lattice the benchmarks measure and LAMMPS runs beside quatrot: the
#: built-in dipole lattice with the truncated sum (cutoff 3.1) of LAMMPS's
#: lj/cut/dipole/cut, as before the Ewald sum became dipole_lattice_sc's
#: default (the long-range sums are compared by validation.bench.ewald).
LATTICE_SCENE = "dipole_lattice_sc_cutoff"
