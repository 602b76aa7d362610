"""
A sweep over integrators and time steps
=======================================

``quatrot.sweep.run`` runs every combination of a grid of scene overrides
as a Dask task and writes one table of results. Here the grid is the
integrator and the time step of the built-in ``dipole_in_field``; the
energy error of each run is read back from the table. Without a
``client`` a sweep starts a local cluster of worker processes; this
example uses an in-process cluster of threads (the runs release the GIL).
"""

import argparse
import logging
import tempfile

import matplotlib.pyplot as plt
from distributed import Client

import quatrot.sweep

parser = argparse.ArgumentParser()
parser.add_argument("--quick", action="store_true", help="fewer runs")
parser.add_argument("--out", default=None, help="the sweep's folder (default: a temporary one)")
args = parser.parse_args()
logging.getLogger("distributed").setLevel(logging.ERROR)  # no cluster chatter

dts = [0.02, 0.01] if args.quick else [0.04, 0.02, 0.01, 0.005]
kinds = ["gear_b", "no_squish", "dlm"]
out = args.out or tempfile.mkdtemp(prefix="sweep-")

# %%
with Client(processes=False, n_workers=2, threads_per_worker=1, dashboard_address=None) as client:
    results = quatrot.sweep.run("dipole_in_field", grid={"integrator.kind": kinds, "run.dt": dts}, out=out, client=client)
print(f"{len(results.rows)} runs, table {results.table}")

# %%
# Each row holds the run's overrides (``integrator.kind``, ``run.dt``) and
# its summary's numbers, as text, written in shortest round-trip form.
fig, ax = plt.subplots(figsize=(6, 4))
for kind in kinds:
    rows = [row for row in results.rows if row["integrator.kind"] == kind]
    ax.loglog([float(r["run.dt"]) for r in rows], [abs(float(r["final_energy_error"])) for r in rows], "o-", label=kind)
ax.set_xlabel("time step")
ax.set_ylabel("|final energy error|")
ax.legend()
fig.tight_layout()
