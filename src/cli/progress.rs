//! A progress bar (indicatif) fed as an observer that needs nothing.

use crate::run::RunError;
use crate::simulation::{Needs, Observer, Sample};
use indicatif::{ProgressBar, ProgressStyle};

/// Shows the step on a terminal progress bar.
pub struct ProgressBarObserver {
    bar: ProgressBar,
}

impl ProgressBarObserver {
    /// A bar for a run of `steps` steps.
    pub fn new(steps: u64) -> Self {
        let bar = ProgressBar::new(steps);
        if let Ok(style) =
            ProgressStyle::with_template("{bar:40} {pos}/{len} steps  {per_sec}  eta {eta}")
        {
            bar.set_style(style);
        }
        ProgressBarObserver { bar }
    }
}

impl Observer for ProgressBarObserver {
    type Error = RunError;

    fn needs(&self) -> Needs {
        Needs::default()
    }

    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), RunError> {
        self.bar.set_position(sample.step);
        Ok(())
    }

    fn finish(&mut self) -> Result<(), RunError> {
        self.bar.finish_and_clear();
        Ok(())
    }
}
