//! One evaluation of a body system: energies by term, forces on sites and
//! bodies, torques, the molecular virial and the pressure.
//!
//! Site forces `F_s` sum into the body force `F = sum_s F_s` and the
//! space-frame torque `tau = sum_s (d_s x F_s + mu_s x E_s - 2
//! vec(Theta_s W_s))` (`d_s` the site's offset from the centre, `E_s` the
//! field and `W_s = dV/dTheta_s` the conjugate at the site, `vec(M)_c =
//! eps_abc M_ab`, as for rotors). The
//! molecular virial is `W = sum_pairs R_IJ f_ij^T = W_sites - sum_s d_s F_s^T`
//! (`R_IJ` the centre separation of the pair's minimum image), and the
//! pressure `P = (2 K_trans + tr W) / (3 V) + P_tail`.

use super::electrostatics::SiteResponse;
use super::pair_pass::PairTerms;
use super::system::BodySystem;
use nalgebra::{Matrix3, Vector3};

/// What an evaluation computes: everything, or the forces and torques only
/// (what a step needs: its energies and virial are read only at the steps
/// a run records or checks, and a run asks for them there).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scope {
    /// Energies by term, forces, torques and the virial.
    #[default]
    Full,
    /// Forces and torques, the same bits as [`Scope::Full`]'s, the energies
    /// and the virial NaN (the short-range pass skips their sums, the mesh
    /// sum and the exclusions of charges their virial; the direct Ewald sum
    /// runs as in full), and no count of overlapping pairs.
    Forces,
}

/// The state of a body system's interactions at one configuration.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Evaluation {
    /// Lennard-Jones energy of the site pairs within the cutoff.
    pub lennard_jones: f64,
    /// The tail correction of the plain truncation (periodic only).
    pub lennard_jones_tail: f64,
    /// Electrostatic energy.
    pub electrostatic: f64,
    /// The force on each site (bodies in order, their sites in order).
    pub site_force: Vec<Vector3<f64>>,
    /// The force on each body.
    pub force: Vec<Vector3<f64>>,
    /// The torque on each body about its centre, space frame.
    pub torque: Vec<Vector3<f64>>,
    /// The molecular virial `sum_pairs R_IJ f_ij^T`.
    pub virial: Matrix3<f64>,
    /// The tail correction to the pressure (periodic, plain truncation).
    pub pressure_tail: f64,
    /// How many Lennard-Jones site pairs may overlap: closer than a part
    /// in 1e9 over [`super::OVERLAP_FRACTION`] of their sigma (none
    /// farther does; [`BodySystem::closest_pair`] finds the closest).
    /// `None` for [`Scope::Forces`].
    pub overlaps: Option<usize>,
}

impl Evaluation {
    /// The potential energy: every term, the tail included.
    pub fn potential_energy(&self) -> f64 {
        self.lennard_jones + self.lennard_jones_tail + self.electrostatic
    }
}

impl BodySystem {
    /// Evaluates the interactions at the bodies' positions and
    /// orientations, first rebuilding the neighbour list (after wrapping
    /// the centres into a periodic box) if a site has moved more than half
    /// the skin or the space has changed.
    pub fn evaluate(&mut self, out: &mut Evaluation) {
        self.evaluate_in(out, Scope::Full);
    }

    /// [`BodySystem::evaluate`] in `scope`.
    pub fn evaluate_in(&mut self, out: &mut Evaluation, scope: Scope) {
        let mut positions = std::mem::take(&mut self.scratch.multipoles.positions);
        self.site_positions(&mut positions);
        if self.neighbours.is_stale(&positions, &self.space) {
            let space = self.space;
            for body in &mut self.bodies {
                space.wrap(&mut body.position, &mut body.image);
            }
            self.site_positions(&mut positions);
            self.neighbours
                .build(&positions, &self.site_body, &self.space);
        }
        self.scratch.multipoles.positions = positions;
        let n = self.sites();
        (out.lennard_jones, out.lennard_jones_tail, out.pressure_tail) = (0.0, 0.0, 0.0);
        out.electrostatic = 0.0;
        if self.electrostatics.is_some() {
            self.space_multipoles();
        }
        // Lennard-Jones and a cutoff sum of charges and dipoles: one pass.
        let cutoff_sum = self.electrostatics.as_ref().and_then(|e| e.cutoff_pairs());
        let terms = PairTerms {
            lennard_jones: self.lennard_jones.as_ref().map(|t| (t, &self.lj_kind[..])),
            electrostatics: cutoff_sum.map(|(c, t)| (c, t, &self.scratch.multipoles)),
        };
        let response = &mut self.scratch.response;
        if self.electrostatics.is_some() && response.potential.len() != n {
            *response = SiteResponse::zeros(n);
        }
        let sums = self.scratch.pairs.run(
            &terms,
            &self.neighbours,
            &self.scratch.multipoles.positions,
            scope,
        );
        let mut virial = sums.virial;
        out.lennard_jones = sums.lennard_jones;
        out.overlaps = (scope == Scope::Full).then_some(sums.overlaps as usize);
        if cutoff_sum.is_some() {
            sums.fill(response);
            out.electrostatic = response.energy;
        }
        self.scratch.pairs.swap_forces(&mut out.site_force);
        if let (Some(term), Some(volume)) = (&self.lennard_jones, self.space.volume()) {
            (out.lennard_jones_tail, out.pressure_tail) = term.tail(&self.lj_counts, volume);
        }
        if let (Some(method), None) = (&mut self.electrostatics, cutoff_sum) {
            method.evaluate(
                &self.scratch.multipoles,
                &self.space,
                &self.neighbours,
                response,
                scope,
            );
            out.electrostatic = response.energy;
            virial += response.virial;
            add(&mut out.site_force, &response.force);
        }
        self.body_sums(out, virial);
        if scope == Scope::Forces {
            out.lennard_jones = f64::NAN;
            out.lennard_jones_tail = f64::NAN;
            out.electrostatic = f64::NAN;
            out.pressure_tail = f64::NAN;
            out.virial = Matrix3::repeat(f64::NAN);
        }
    }

    /// The pressure of an evaluation `e` of the current state, `None` in
    /// open space.
    pub fn pressure(&self, e: &Evaluation) -> Option<f64> {
        let volume = self.space.volume()?;
        let kinetic = 2.0 * self.translational_kinetic_energy();
        Some((kinetic + e.virial.trace()) / (3.0 * volume) + e.pressure_tail)
    }

    /// Each site's position (and its offset into the scratch).
    fn site_positions(&mut self, positions: &mut Vec<Vector3<f64>>) {
        let offsets = &mut self.scratch.offsets;
        positions.clear();
        offsets.clear();
        for body in &self.bodies {
            let rotation = body.orientation.body_to_space_matrix();
            for site in &self.types[body.kind].sites {
                let offset = rotation * site.position;
                offsets.push(offset);
                positions.push(body.position + offset);
            }
        }
    }

    /// Charges, space-frame dipoles `A^T mu_b` and quadrupoles `A^T
    /// Theta_b A` (eq 7's `A`, body to space as its transpose) of every site.
    fn space_multipoles(&mut self) {
        let m = &mut self.scratch.multipoles;
        m.charges.clear();
        m.dipoles.clear();
        m.quadrupoles.clear();
        for body in &self.bodies {
            let rotation = body.orientation.body_to_space_matrix();
            for site in &self.types[body.kind].sites {
                m.charges.push(site.charge);
                m.dipoles
                    .push(site.dipole.map_or(Vector3::zeros(), |mu| rotation * mu));
                m.quadrupoles
                    .push(site.quadrupole.map_or(Matrix3::zeros(), |theta| {
                        rotation * theta * rotation.transpose()
                    }));
            }
        }
    }

    /// Body forces, torques and the molecular virial from the site forces.
    fn body_sums(&self, out: &mut Evaluation, site_virial: Matrix3<f64>) {
        let nbodies = self.bodies.len();
        out.force.clear();
        out.force.resize(nbodies, Vector3::zeros());
        out.torque.clear();
        out.torque.resize(nbodies, Vector3::zeros());
        let response = self.electrostatics.as_ref().map(|_| &self.scratch.response);
        let (dipoles, quadrupoles) = (
            &self.scratch.multipoles.dipoles,
            &self.scratch.multipoles.quadrupoles,
        );
        let mut virial = site_virial;
        for (s, (&b, f)) in self.site_body.iter().zip(&out.site_force).enumerate() {
            let (b, d) = (b as usize, self.scratch.offsets[s]);
            out.force[b] += f;
            out.torque[b] += d.cross(f);
            if let Some(response) = response {
                out.torque[b] += dipoles[s].cross(&response.field[s]);
                let m = quadrupoles[s] * response.quadrupole_conjugate[s];
                out.torque[b] -= Vector3::new(m.m23 - m.m32, m.m31 - m.m13, m.m12 - m.m21) * 2.0;
            }
            virial -= d * f.transpose();
        }
        out.virial = virial;
    }
}

/// `total[i] += part[i]` for every site.
fn add(total: &mut [Vector3<f64>], part: &[Vector3<f64>]) {
    for (t, p) in total.iter_mut().zip(part) {
        *t += p;
    }
}
