//! The one run loop of the crate, and what it feeds: observers that declare
//! their [`Needs`] and sample at intervals the loop owns, the scalar
//! [`Quantity`]s they record, the blow-up guard, checkpoints and the energy
//! history, and the [`Control`] that stops a run from another thread. Scene runs, the experiments, the Python bindings and the
//! benchmarks all run through [`run`].

mod control;
mod energy;
mod observer;
mod quantity;
mod run_loop;
mod stop;

pub use control::Control;
pub use energy::{EnergyHistory, EnergyReference};
pub use observer::{CheckpointSink, Checkpoints, Energies, Needs, Observer, Sample, Scheduled};
pub use quantity::Quantity;
pub use run_loop::{run, RunOptions, RunReport};
pub use stop::{BlowUpChecks, Stop};
