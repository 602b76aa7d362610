//! The run loop's stop request (`simulation::Control`, Ctrl-C in Python):
//! a run stops at the end of the step in progress, its observers sampled up
//! to there and finished, the stop reported with the step.

use nalgebra::Vector3;
use quatrot::integrators::{IntegratorSpec, NoSquishOptions, RotorState};
use quatrot::potential::Free;
use quatrot::quaternion::Quat;
use quatrot::rotor::Inertia;
use quatrot::simulation::{self, Control, Needs, Observer, RunOptions, Sample, Scheduled, Stop};
use std::convert::Infallible;
use std::sync::Arc;

/// Records the steps it samples and asks for a stop at `stop_at`.
struct StopAt {
    control: Arc<Control>,
    stop_at: u64,
    steps: Vec<u64>,
    finished: bool,
}

impl Observer for StopAt {
    type Error = Infallible;

    fn needs(&self) -> Needs {
        Needs::default()
    }

    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), Infallible> {
        self.steps.push(sample.step);
        if sample.step == self.stop_at {
            self.control.request_stop();
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), Infallible> {
        self.finished = true;
        Ok(())
    }
}

/// A free top run to `end_step`, sampled every `every` steps, asked to stop
/// at `stop_at`: the stop, the steps sampled, whether the observer was
/// finished and the step the control last saw.
fn run(every: u64, stop_at: u64, end_step: u64) -> (Stop, u64, Vec<u64>, bool, u64) {
    let inertia = [Inertia::Spherical(1.0)];
    let initial = [RotorState {
        orientation: Quat::IDENTITY,
        omega_body: Vector3::new(0.1, 0.2, 0.3),
    }];
    let mut integrator = IntegratorSpec::NoSquish(NoSquishOptions::default()).build();
    integrator
        .setup(&inertia, &Free, &initial, 0.01)
        .expect("valid setup");
    let control = Arc::new(Control::new());
    let mut observer = StopAt {
        control: Arc::clone(&control),
        stop_at,
        steps: Vec::new(),
        finished: false,
    };
    let options = RunOptions {
        start_step: 0,
        end_step,
        checks: None,
        reference: None,
        control: Some(Arc::clone(&control)),
    };
    let mut observers = [Scheduled {
        every,
        at_end: false,
        observer: &mut observer,
    }];
    let Ok(report) = simulation::run(
        integrator.as_mut(),
        &Free,
        &inertia,
        &mut observers,
        None,
        &options,
    );
    (
        report.stop,
        report.last_step,
        observer.steps,
        observer.finished,
        control.step(),
    )
}

#[test]
fn a_stop_requested_at_a_sample_ends_the_run_there_after_its_samples() {
    let (stop, last, steps, finished, seen) = run(10, 20, 1000);
    assert_eq!(stop, Stop::Interrupted { step: 20 });
    assert_eq!(last, 20);
    assert_eq!(steps, vec![0, 10, 20]);
    assert!(finished);
    assert_eq!(seen, 20);
    assert_eq!(stop.message().as_deref(), Some("interrupted at step 20"));
}

#[test]
fn a_stop_requested_at_the_start_steps_no_further() {
    let (stop, last, steps, finished, _) = run(10, 0, 1000);
    assert_eq!(stop, Stop::Interrupted { step: 0 });
    assert_eq!((last, steps, finished), (0, vec![0], true));
}

#[test]
fn without_a_stop_the_run_completes_with_the_control_at_the_last_step() {
    let (stop, last, steps, _, seen) = run(250, u64::MAX, 1000);
    assert_eq!(stop, Stop::Completed);
    assert_eq!((last, seen), (1000, 1000));
    assert_eq!(steps, vec![0, 250, 500, 750, 1000]);
}
