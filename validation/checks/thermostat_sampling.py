"""Canonical runs: quatrot's thermostats (Langevin, Bussi and Nose-Hoover chains with NO_SQUISH and DLM, both spherical-top modes, and Nose-Hoover with scheme A) against exact canonical distributions, and LAMMPS's ``fix langevin ... omega yes`` with ``fix nve/sphere update dipole/dlm`` against the same distributions and against quatrot on the 1000-dipole lattice.

Exact references (:mod:`validation.shared.thermostat_references`, scipy): body
angular velocity components normal with variance ``T/I_a``, a rotor's
kinetic energy Gamma(3/2, T) with mean ``3T/2`` (any potential: in the
canonical ensemble momenta are independent of the orientations); free
spherical, symmetric and asymmetric tops; a dipole in a uniform field,
``p(cos theta) ~ exp(x cos theta)``, ``<cos theta> = coth x - 1/x``,
``x = mu E/T = 2``; an axial quadrupole on an asymmetric top in a non-axial
field gradient, the distribution of its axis by quadrature (two independent
quadratures, and the reference energy checked against quatrot's).

Samples are independent: Langevin thermostats each rotor on its own, so one
run of 1000 non-interacting rotors (a periodic lattice with a cutoff shorter
than the spacing) gives 1000 samples of its last frame; Bussi and
Nose-Hoover act on the total kinetic energy only, so they run independent
replicas of one rotor, each from its own seed, for 50 time units: an
asymmetric top, and (full mode) a spherical dipole with every spherical-top
mode of DLM and NO_SQUISH (its spin about the dipole is conserved, and the
global thermostats leave it out: scaled with the rest it kept the ratio of
two conserved momenta and the rotor was not ergodic, see
tests/thermostat_distributions.rs). Each check takes the smallest p-value of its tests
(Kolmogorov-Smirnov against the exact CDF, z tests of means with exact
variances), Bonferroni-adjusted for the number of tests, and passes when that
is at least ``ALPHA = 1e-4``: a correct implementation fails a check once in
1e4 runs. The measured value is ``-log10`` of the adjusted p-value (tolerance
4). A run at twice the temperature is rejected (adjusted p-value below 1e-12).

LAMMPS: its rotational Langevin torque is ``-(10/3) I omega / damp`` plus
uniform noise of the matching variance (read in ``fix_langevin.cpp``), a
friction ``10/(3 damp)``, not ``1/damp``: measured here from the decay of
the angular velocity of free spheres (ERRATA.md, traps). With that mapping
LAMMPS samples the dipole in a field exactly within statistical error, and
its 1000-dipole lattice at T = 1 has the potential and kinetic energies per
rotor of quatrot's Langevin, Bussi and Nose-Hoover runs within their errors
(block averages). Passing proves canonical sampling to the resolution of the
sample sizes (KS distances of ~0.04 for 1000 samples), not the dynamics
beyond the friction and relaxation times; the time-step bias is measured in
the benchmark report (``python -m validation.bench.thermostats``).

LAMMPS ``fix rigid/nvt`` (the Nose-Hoover chains of Kamberaj, Low and Neal
2005 on rigid bodies) is not compared: it integrates bodies built from atoms
(their inertia summed from the constituent particles), with translation and
rotation under one thermostat, while quatrot's rotors are point rotors of a
given inertia tensor carrying point multipoles and no translation. A
like-for-like run would need a LAMMPS molecule whose inertia and dipole
reproduce each rotor and the translational degrees of freedom held apart
from the thermostat; what a Nose-Hoover chain on rotation samples is checked
here instead against the exact distributions, and LAMMPS's own
Nose-Hoover chain on rotation, ``fix nvt/sphere``, which applies to dipolar
spheres directly, is compared on the lattice (it heats their coupled
components: a trap in ERRATA.md).
"""

from __future__ import annotations

import copy

import numpy as np
from scipy import stats

import quatrot
from validation.shared import thermostat_references as ref
from validation.shared.check import Check, Context
from validation.shared.lammps_driver import DipoleSystem, lammps_version, run_lammps

ALPHA = 1e-4
# -log10(ALPHA): the tolerance of the adjusted p-values.
P_TOLERANCE = -np.log10(ALPHA)
# A run wrong by a factor two must give adjusted p-values below this.
WRONG_BY_TWO_P = 1e-12
# Two estimates of one average, each with a block error: |difference| over
# the combined error (two-sided normal 6e-5).
Z_MAX = 4.0

T = 0.8
X = 2.0  # mu E / T of the dipole
FIELD = X * T
THETA0 = 1.0
# Traceless, non-axial: k = THETA0/(2T), exp(k u.G.u) weights x over y over z.
GRADIENT = 4.0 * T * np.array([1.0, -0.25, -0.75])
TOPS = {
    "spherical": 0.1,
    "symmetric": [0.1, 0.1, 0.25],
    "asymmetric": [0.1, 0.15, 0.25],
}
DT = 0.01
LANGEVIN = {"kind": "langevin", "temperature": T, "friction": 2.0}
BUSSI = {"kind": "bussi", "temperature": T, "tau": 0.1}
NOSE_HOOVER = {"kind": "nose_hoover", "temperature": T, "tau": 0.2}
KICK = {
    "dlm": {"kind": "dlm"},
    "dlm split": {"kind": "dlm", "spherical_tops": "split"},
    "no_squish": {"kind": "no_squish"},
    "no_squish split": {"kind": "no_squish", "spherical_tops": "split"},
}


def moments(inertia) -> np.ndarray:
    return np.broadcast_to(np.asarray(inertia, float), (3,)).astype(float)


def scene(system: str, inertia, integrator: dict, thermostat: dict, *, cells: int, dt: float, steps: int, seed: int, initial_temperature: float) -> dict:
    """``cells^3`` non-interacting rotors (a periodic simple-cubic lattice of
    spacing 1 with a cutoff of 0.5: no pair) in the field of ``system``
    ("free", "dipole", "quadrupole"), recording the first and last frames."""
    default = {"inertia": inertia}
    out = {
        "version": 1,
        "name": f"thermostat_{system}",
        "rotors": {"kind": "lattice", "lattice": "simple_cubic", "cells": cells, "spacing": 1.0, "default": default},
        "initial": {"kind": "random", "seed": seed, "temperature": initial_temperature},
        "integrator": integrator,
        "thermostat": thermostat,
        "run": {"dt": dt, "steps": steps},
        "record": {"trajectory": {"every": steps}},
    }
    if system == "dipole":
        default["dipole"] = [0.0, 0.0, 1.0]
        out["fields"] = {"uniform": [0.0, 0.0, FIELD]}
    if system == "quadrupole":
        default["quadrupole"] = (THETA0 * np.diag([-0.5, -0.5, 1.0])).tolist()
        out["fields"] = {"gradient": np.diag(GRADIENT).tolist()}
    if system != "free":
        out["interactions"] = {"boundary": {"kind": "periodic", "cutoff": 0.5}}
    return out


def last_frame(result: dict) -> tuple[np.ndarray, np.ndarray]:
    t = result["trajectory"]
    return np.asarray(t["orientations"][-1]), np.asarray(t["omega_body"][-1])


def body_to_space(q: np.ndarray) -> np.ndarray:
    """``R(Q) = A(Q)^T`` (eq 7) for quaternions (n, 4)."""
    q0, q1, q2, q3 = q.T
    return np.stack(
        [
            np.stack([q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)], -1),
            np.stack([2 * (q1 * q2 + q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 - q0 * q1)], -1),
            np.stack([2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3], -1),
        ],
        -2,
    )


def axis(q: np.ndarray) -> np.ndarray:
    """The space direction of body axis 3 (the dipole's and the quadrupole's)."""
    return body_to_space(q)[:, :, 2]


def p_values(system: str, inertia, q: np.ndarray, omega: np.ndarray, quadrupole: ref.AxialQuadrupole, temperature: float = T) -> dict[str, float]:
    """Every exact test of a sample of states at ``temperature``."""
    p = ref.maxwell_p_values(omega, moments(inertia), temperature)
    u = axis(q)
    if system == "dipole":
        x = FIELD / temperature
        p["cos theta ~ exp(x cos theta)"] = ref.ks_p(u[:, 2], lambda c: ref.dipole_cos_cdf(c, x))
        p["<cos theta> = coth x - 1/x"] = ref.mean_p(u[:, 2], ref.langevin_function(x), ref.dipole_cos_variance(x))
    if system == "quadrupole":
        p["u_z ~ quadrature"] = ref.ks_p(u[:, 2], quadrupole.cdf)
        m = quadrupole.axis_moments
        for a, name in ((0, "x"), (2, "z")):
            p[f"<u_{name}^2> = quadrature"] = ref.mean_p(u[:, a] ** 2, m[f"{name}2"], m[f"{name}4"] - m[f"{name}2"] ** 2)
    return p


def verdict(name: str, p: dict[str, float], proves: str, refs: dict, size: int) -> Check:
    adjusted = min(1.0, min(p.values()) * len(p))
    return Check(
        name=name,
        proves=proves,
        tolerance=P_TOLERANCE,
        measured=float(-np.log10(max(adjusted, 1e-300))),
        references=refs,
        details=f"{size} samples; p-values: " + ", ".join(f"{k} {v:.3g}" for k, v in p.items()),
    )


def replicas(system: str, inertia, integrator: dict, thermostat: dict, count: int, dt: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """The last states of ``count`` independent one-rotor runs of 50 time units."""
    steps = int(round(50.0 / dt))
    qs, ws = [], []
    for r in range(count):
        q, w = last_frame(quatrot.run(scene(system, inertia, integrator, thermostat, cells=1, dt=dt, steps=steps, seed=seed + r, initial_temperature=T)))
        qs.append(q[0])
        ws.append(w[0])
    return np.array(qs), np.array(ws)


def run(ctx: Context) -> list[Check]:
    refs_exact = {"scipy": __import__("scipy").__version__, "quatrot": quatrot.__version__}
    quadrupole = ref.AxialQuadrupole(THETA0, GRADIENT, T)
    checks = [_quadrupole_reference_check(quadrupole, refs_exact)]
    cells = 6 if ctx.quick else 10
    count = 60 if ctx.quick else 1000
    # Langevin: every kick integrator, independent rotors in one run.
    langevin_runs = {}
    for iname, integrator in KICK.items():
        if ctx.quick and "split" in iname:
            continue
        ctx.progress(f"langevin {iname}")
        for system, tops in (("free", list(TOPS)), ("dipole", ["spherical", "asymmetric"]), ("quadrupole", ["asymmetric"])):
            p, size = {}, 0
            for top in tops:
                initial = T / 4 if system == "free" else T
                result = quatrot.run(scene(system, TOPS[top], integrator, LANGEVIN, cells=cells, dt=DT, steps=1000, seed=ctx.seed, initial_temperature=initial))
                q, w = last_frame(result)
                langevin_runs[(iname, system, top)] = (q, w)
                p |= {f"{top}: {k}": v for k, v in p_values(system, TOPS[top], q, w, quadrupole).items()}
                size += len(q)
            checks.append(
                verdict(
                    f"langevin + {iname}, {system} ({', '.join(tops)}): canonical",
                    p,
                    "Langevin with this integrator samples the exact canonical distribution of the angular velocities (and of the orientations in a field) of independent rotors, to the resolution of the sample",
                    refs_exact,
                    size,
                )
            )
    # Twice the temperature is rejected by the same tests (1000 rotors even
    # in quick mode: the power is the point).
    q, w = last_frame(quatrot.run(scene("dipole", TOPS["spherical"], KICK["dlm"], LANGEVIN | {"temperature": 2 * T}, cells=10, dt=DT, steps=1000, seed=ctx.seed, initial_temperature=T)))
    p = p_values("dipole", TOPS["spherical"], q, w, quadrupole)
    largest = max(min(1.0, v * len(p)) for v in p.values())
    checks.append(
        Check(
            name="langevin at 2T judged at T: rejected",
            proves="the tests of this module reject a temperature wrong by a factor of two (every adjusted p-value below 1e-12), so their passing is not for lack of power",
            tolerance=float(np.log10(WRONG_BY_TWO_P)),
            measured=float(np.log10(max(largest, 1e-300))),
            references=refs_exact,
            details="p-values: " + ", ".join(f"{k} {v:.3g}" for k, v in p.items()),
        )
    )
    # Global thermostats: replicas of one asymmetric top (where the two
    # spherical-top modes of DLM and NO_SQUISH are the same step), and of a
    # spherical dipole (its spin about the dipole conserved and left out),
    # where they differ: every mode.
    pairs = [("bussi", BUSSI, n, KICK[n], DT, "asymmetric") for n in ("dlm", "no_squish")]
    pairs += [("nose_hoover", NOSE_HOOVER, n, KICK[n], DT, "asymmetric") for n in ("dlm", "no_squish")]
    pairs += [("nose_hoover", NOSE_HOOVER, "gear_a", {"kind": "gear_a"}, DT / 2, "asymmetric")]
    pairs += [(t, th, n, KICK[n], DT, "spherical") for t, th in (("bussi", BUSSI), ("nose_hoover", NOSE_HOOVER)) for n in KICK if not ctx.quick]
    for tname, thermostat, iname, integrator, dt, top in pairs:
        systems = ["dipole"] if top == "spherical" else ["dipole", "quadrupole"] + (["free"] if tname == "bussi" else [])
        if ctx.quick:
            systems = systems[:1]
        for system in systems:
            ctx.progress(f"{tname} {iname} {system} ({top}): {count} replicas")
            q, w = replicas(system, TOPS[top], integrator, thermostat, count, dt, ctx.seed)
            p = p_values(system, TOPS[top], q, w, quadrupole)
            checks.append(
                verdict(
                    f"{tname} + {iname}, {system} ({top} top, replicas): canonical",
                    p,
                    "this global thermostat with this integrator brings independent replicas of one rotor to the exact canonical distribution in 50 time units",
                    refs_exact,
                    len(q),
                )
            )
    checks += _lammps_checks(ctx, langevin_runs, quadrupole)
    return checks


def _quadrupole_reference_check(quadrupole: ref.AxialQuadrupole, refs: dict) -> Check:
    """quatrot's energy of the axial quadrupole is the reference's
    ``-theta0/2 u.G.u`` at random orientations, and the two quadratures agree."""
    rng = np.random.default_rng(5)
    q = rng.normal(size=(20, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    theta_b = THETA0 * np.diag([-0.5, -0.5, 1.0])
    worst = quadrupole.normalisation_agreement()
    for qi in q:
        energy, _, _ = quatrot.multipole_evaluate(np.zeros((1, 3)), qi[None, :], quadrupoles_body=theta_b[None], field_gradient=np.diag(GRADIENT))
        u = axis(qi[None, :])[0]
        expected = -0.5 * THETA0 * u @ (GRADIENT * u)
        worst = max(worst, abs(energy - expected) / max(1.0, abs(expected)))
    return Check(
        name="quadrupole reference density: quatrot's energy and the two quadratures",
        proves="the density of the quadrupole checks is exp(-V/T) of quatrot's own energy (an axial quadrupole in the gradient, 20 random orientations) and the Bessel-function marginal and the 2-d quadrature agree; not the sampling",
        tolerance=1e-10,
        measured=float(worst),
        references=refs,
    )


# ---------------------------------------------------------------------------
# LAMMPS


def _damp(friction: float) -> float:
    """The ``damp`` of LAMMPS's omega thermostat with this friction."""
    return 10.0 / (3.0 * friction)


def _grid(n_side: int, spacing: float) -> np.ndarray:
    r = np.arange(n_side) * spacing
    return np.array([[x, y, z] for x in r for y in r for z in r], float)


def _maxwell_omega(rng, n: int, inertia: float, temperature: float) -> np.ndarray:
    return rng.normal(size=(n, 3)) * np.sqrt(temperature / inertia)


def _unit(rng, n: int) -> np.ndarray:
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1)[:, None]


def _lammps_checks(ctx: Context, langevin_runs, quadrupole) -> list[Check]:
    version = lammps_version()
    refs = {"LAMMPS": version, "scipy": __import__("scipy").__version__}
    rng = np.random.default_rng(ctx.seed)
    side = 6 if ctx.quick else 10
    n = side**3
    checks = []
    # 1. The friction of fix langevin ... omega yes: free spheres (I = 0.1),
    #    omega(t + s) against omega(t), lag s with exp(-gamma s) = exp(-1/2).
    friction = 2.0
    damp = _damp(friction)
    lag, dt = 0.25, 0.005
    free = DipoleSystem(sites=_grid(side, 2.0), dipoles=_unit(rng, n), omega=_maxwell_omega(rng, n, 0.1, T), cutoff=1.0, langevin=(T, damp, 4321))
    ctx.progress("LAMMPS langevin omega: friction of free spheres")
    traj = run_lammps(free, dt, int(round(20 * lag / dt)), every=int(round(lag / dt)))
    x, y = traj.omega[4:-1].ravel(), traj.omega[5:].ravel()
    fit = stats.linregress(x, y)
    rate, rate_error = -np.log(fit.slope) / lag, fit.stderr / fit.slope / lag
    checks.append(
        Check(
            name="LAMMPS langevin omega: friction is 10/(3 damp)",
            proves="LAMMPS's rotational Langevin damps omega at the rate 10/(3 damp) (its drag torque -(10/3) I omega/damp), the mapping used for the comparisons below",
            tolerance=Z_MAX,
            measured=float(abs(rate - 1.0 / damp * 10.0 / 3.0) / rate_error),
            references=refs,
            details=f"fitted rate {rate:.4f} +- {rate_error:.4f} per time unit, damp {damp:.4f}: 10/(3 damp) = {10 / (3 * damp):.4f}, 1/damp = {1 / damp:.4f}",
        )
    )
    checks.append(
        Check(
            name="LAMMPS langevin omega: friction is not 1/damp (trap reproduced)",
            proves="reading damp as the inverse friction, as for the translational thermostat, is wrong by 10/3 for omega: the fitted rate excludes 1/damp",
            tolerance=-Z_MAX,
            measured=float(-abs(rate - 1.0 / damp) / rate_error),
            references=refs,
            details=f"fitted rate {rate:.4f} +- {rate_error:.4f}, 1/damp = {1 / damp:.4f}",
        )
    )
    # 2. Independent dipoles in a uniform field: the exact distribution, and
    #    quatrot's sample of the same system (two-sample KS).
    ctx.progress("LAMMPS langevin omega: dipoles in a field")
    field_system = DipoleSystem(sites=_grid(side, 2.0), dipoles=_unit(rng, n), omega=_maxwell_omega(rng, n, 0.1, T), cutoff=1.0, field=(0.0, 0.0, FIELD), langevin=(T, damp, 8765))
    steps = int(round(20.0 / dt))
    traj = run_lammps(field_system, dt, steps, every=steps)
    mu = traj.dipoles[-1]
    c = mu[:, 2] / np.linalg.norm(mu, axis=1)
    kinetic = 0.5 * 0.1 * (traj.omega[-1] ** 2).sum(axis=1) / T
    p = {
        "cos theta ~ exp(x cos theta)": ref.ks_p(c, lambda v: ref.dipole_cos_cdf(v, X)),
        "<cos theta> = coth x - 1/x": ref.mean_p(c, ref.langevin_function(X), ref.dipole_cos_variance(X)),
        "omega ~ normal(0, T/I)": ref.ks_p((traj.omega[-1] / np.sqrt(T / 0.1)).ravel(), stats.norm.cdf),
        "K ~ Gamma(3/2, T)": ref.ks_p(kinetic, stats.gamma(1.5).cdf),
    }
    q_quatrot, _ = langevin_runs[("dlm", "dipole", "spherical")]
    p["quatrot dlm sample (two-sample KS)"] = float(stats.ks_2samp(c, axis(q_quatrot)[:, 2]).pvalue)
    checks.append(verdict("LAMMPS langevin omega + dipole/dlm, dipoles in a field: canonical", p, "LAMMPS's rotational Langevin with nve/sphere update dipole/dlm (friction mapped as 10/(3 damp)) samples the exact distribution of a dipole in a uniform field and Maxwell angular velocities, and the same distribution as quatrot", refs, n))
    checks += _lattice_checks(ctx, refs)
    return checks


def _block(series) -> tuple[float, float]:
    b = quatrot.block_average(np.asarray(series, float))
    return float(b["mean"]), float(b["error"])


def _lattice_checks(ctx: Context, refs: dict) -> list[Check]:
    """The 1000-dipole lattice (sc, spacing 1, periodic, cutoff 3.1, I = 0.1,
    |mu| = 1) at T = 1: LAMMPS Langevin against quatrot's three thermostats,
    potential and kinetic energy per rotor after 5 time units."""
    side = 6 if ctx.quick else 10
    n = side**3
    temperature, dt = 1.0, 0.002
    # quatrot's runs of the small quick lattice are cheap: long enough for the
    # blocking to converge; LAMMPS's are shorter there.
    t_quatrot = 60.0 if ctx.quick else 40.0
    t_lammps = 20.0 if ctx.quick else 40.0
    equilibrate = 5.0
    every = 10
    first = int(round(equilibrate / dt)) // every
    base = quatrot.builtin_scenes()["dipole_lattice_sc_langevin"]
    import tomllib

    lattice = tomllib.loads(base)
    lattice["rotors"]["cells"] = side
    lattice["run"] = {"dt": dt, "steps": int(round(t_quatrot / dt))}
    lattice["record"] = {"series": [{"name": "e", "every": every, "quantities": ["kinetic_energy", "potential_energy"]}]}
    estimates = {}
    spins = {}
    for name, thermostat in (
        ("quatrot langevin", {"kind": "langevin", "temperature": temperature, "friction": 1.0}),
        ("quatrot bussi", {"kind": "bussi", "temperature": temperature, "tau": 0.1}),
        ("quatrot nose_hoover", {"kind": "nose_hoover", "temperature": temperature, "tau": 0.2}),
    ):
        ctx.progress(f"lattice: {name}")
        s = copy.deepcopy(lattice)
        s["thermostat"] = thermostat
        result = quatrot.run(s)
        e = result["series"]["e"]
        estimates[name] = (_block(e["potential_energy"][first:] / n), _block(e["kinetic_energy"][first:] / n))
        # The spins about the dipoles (body axis 3) Bussi and Nose-Hoover
        # leave alone keep their initial energy.
        spins[name] = 0.5 * 0.1 * float((np.asarray(result["initial_omega_body"])[:, 2] ** 2).sum()) / n
    ctx.progress("lattice: LAMMPS langevin omega")
    sites = _grid(side, 1.0)
    rng = np.random.default_rng(ctx.seed + 1)
    system = DipoleSystem(sites=sites, dipoles=_unit(rng, n), omega=_maxwell_omega(rng, n, 0.1, temperature), cutoff=3.1, box=float(side), langevin=(temperature, _damp(1.0), 2468))
    steps = int(round(t_lammps / dt))
    traj = run_lammps(system, dt, steps, every=every)
    estimates["LAMMPS langevin"] = (_block(traj.potential[first:] / n), _block(traj.kinetic[first:] / n))
    ctx.progress("lattice: LAMMPS nvt/sphere (Nose-Hoover chain on the rotational temperature)")
    nvt = run_lammps(DipoleSystem(**{**system.__dict__, "langevin": None, "nvt": (temperature, 0.2)}), dt, steps, every=every)
    nvt_v = _block(nvt.potential[first:] / n)
    unit = nvt.dipoles[first:] / np.linalg.norm(nvt.dipoles[first:], axis=2)[..., None]
    along = (nvt.omega[first:] * unit).sum(axis=2)
    # Per sample: I |w_perp|^2 / 2 per degree of freedom (two per rotor), and
    # I w_par^2 for the spin about the dipole.
    perpendicular = _block(0.1 * ((nvt.omega[first:] ** 2).sum(axis=2) - along**2).mean(axis=1) / 2.0)
    spin = 0.1 * float((along**2).mean())
    checks = [
        Check(
            name="LAMMPS nvt/sphere dipole/dlm: the dipoles' coupled components run hot (trap reproduced)",
            proves="LAMMPS's Nose-Hoover chain on spheres carrying dipoles (rotational temperature, dof rotate) scales the spins about the dipoles, which the dynamics conserves, so they cannot equilibrate and the thermostat heats the coupled components: their temperature is far from T (measured in units of its block error)",
            tolerance=-Z_MAX,
            measured=float(-abs(perpendicular[0] / temperature - 1.0) / (perpendicular[1] / temperature)),
            references=refs,
            details=f"coupled components at {perpendicular[0]:.4f} +- {perpendicular[1]:.4f}, spins at {spin:.4f}, T = {temperature}; V/N {nvt_v[0]:.5f} +- {nvt_v[1]:.5f} against quatrot langevin's {estimates['quatrot langevin'][0][0]:.5f} +- {estimates['quatrot langevin'][0][1]:.5f}",
        ),
        Check(
            name="LAMMPS nvt/sphere dipole/dlm: <V>/N differs from the canonical one (trap reproduced)",
            proves="the hot coupled components leave LAMMPS's Nose-Hoover lattice less ordered than the canonical one that quatrot's three thermostats and LAMMPS's Langevin agree on",
            tolerance=-Z_MAX,
            measured=float(-abs(nvt_v[0] - estimates["quatrot langevin"][0][0]) / np.hypot(nvt_v[1], estimates["quatrot langevin"][0][1])),
            references=refs,
            details=f"LAMMPS nvt/sphere V/N {nvt_v[0]:.5f} +- {nvt_v[1]:.5f}; quatrot langevin {estimates['quatrot langevin'][0][0]:.5f} +- {estimates['quatrot langevin'][0][1]:.5f}",
        ),
    ]
    table = "; ".join(f"{k}: V/N {v[0][0]:.5f} +- {v[0][1]:.5f}, K/N {v[1][0]:.5f} +- {v[1][1]:.5f}" for k, v in estimates.items())
    reference = estimates["quatrot langevin"]
    for name, (v, k) in estimates.items():
        if name in ("quatrot bussi", "quatrot nose_hoover"):
            label, expected, spin = "<K - K_spin>/N = T", temperature, spins[name]
            proves = "the global thermostat holds the lattice's kinetic energy per rotor in the components perpendicular to the dipole at exactly T (2 degrees of freedom; the spins about the dipoles, conserved by the dynamics, keep their initial energy)"
        else:
            label, expected, spin = "<K>/N = 3T/2", 1.5 * temperature, 0.0
            proves = "the thermostat holds the interacting lattice's mean kinetic energy per rotor at exactly 3T/2 (within the block error)"
        checks.append(
            Check(
                name=f"lattice T = 1, {name}: {label}",
                proves=proves,
                tolerance=Z_MAX,
                measured=float(abs(k[0] - spin - expected) / k[1]),
                references=refs,
                details=table + (f"; initial spin energy per rotor {spin:.5f}" if spin else ""),
            )
        )
        if name != "quatrot langevin":
            z_v = abs(v[0] - reference[0][0]) / np.hypot(v[1], reference[0][1])
            checks.append(
                Check(
                    name=f"lattice T = 1, {name}: <V>/N = quatrot langevin's",
                    proves="two independent canonical samplers agree on the mean potential energy per rotor of the interacting lattice within their combined block errors",
                    tolerance=Z_MAX,
                    measured=float(z_v),
                    references=refs,
                    details=table,
                )
            )
    return checks
