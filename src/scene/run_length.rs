//! The `[run]` section: the time step, the length of the run (in steps or
//! as a time rounded to whole steps) and its threads.

use super::error::SceneError;
use crate::checks::{at_least_one, num, positive};
use crate::parallel::ThreadCount;
use crate::units::{Units, MAX_REAL_DT_FS};
use serde::{Deserialize, Serialize};

/// Time step and length of the run.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRun {
    /// The time step (> 0).
    pub dt: f64,
    /// The number of steps (>= 1), or
    pub steps: Option<i64>,
    /// the run time (at least one step).
    pub time: Option<f64>,
    /// The threads of the run: 1 to 1024 (`MAX_THREADS`), or
    /// `"auto"` (the default); a count given to the run (`--threads`)
    /// overrides it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threads: Option<ThreadCount>,
}

/// The smallest time step: the Gear schemes keep `dt^5 / 120` times the
/// fifth derivative, which underflows to zero (and the run to NaN) for
/// steps much below `(2.2e-308)^(1/5)`, about 1e-61.
pub const MIN_DT: f64 = 1e-60;

/// Validates the section: the time step (in `units`; at most
/// [`MAX_REAL_DT_FS`] in real units) and the number of steps.
pub(super) fn run_length(raw: &RawRun, units: Units) -> Result<(f64, u64), SceneError> {
    let dt = positive(raw.dt).map_err(|e| e.at("run.dt"))?;
    if units == Units::Real && dt > MAX_REAL_DT_FS {
        return Err(SceneError::field(
            "run.dt",
            format!(
                "must be at most {MAX_REAL_DT_FS} fs in real units (rigid water is stable to about 4 fs), got {}",
                num(dt)
            ),
        ));
    }
    if dt < MIN_DT {
        return Err(SceneError::field(
            "run.dt",
            format!("must be >= {MIN_DT:e}, got {}", num(dt)),
        ));
    }
    let steps = match (raw.steps, raw.time) {
        (Some(_), Some(_)) => {
            return Err(SceneError::field(
                "run",
                "give either steps or time, not both",
            ))
        }
        (None, None) => return Err(SceneError::field("run", "give steps or time")),
        (Some(steps), None) => at_least_one(steps).map_err(|e| e.at("run.steps"))?,
        (None, Some(time)) => {
            let time = positive(time).map_err(|e| e.at("run.time"))?;
            let steps = (time / dt).round();
            if steps < 1.0 {
                return Err(SceneError::field(
                    "run.time",
                    format!(
                        "must be at least one step (dt = {}), got {}",
                        num(dt),
                        num(time)
                    ),
                ));
            }
            if steps > u64::MAX as f64 {
                return Err(SceneError::field(
                    "run.time",
                    format!(
                        "gives too many steps of dt = {}, got {}",
                        num(dt),
                        num(time)
                    ),
                ));
            }
            steps as u64
        }
    };
    Ok((dt, steps))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(dt: f64, steps: Option<i64>, time: Option<f64>) -> Result<(f64, u64), String> {
        run_length(
            &RawRun {
                dt,
                steps,
                time,
                threads: None,
            },
            Units::Reduced,
        )
        .map_err(|e| e.to_string())
    }

    /// A run time is rounded to whole steps; steps and time exclude each other.
    #[test]
    fn time_is_rounded_to_whole_steps() {
        assert_eq!(check(0.1, None, Some(1.04)), Ok((0.1, 10)));
        assert_eq!(check(0.1, Some(7), None), Ok((0.1, 7)));
        assert_eq!(
            check(0.1, Some(7), Some(1.0)),
            Err("run: give either steps or time, not both".to_string())
        );
        assert_eq!(
            check(0.1, None, Some(0.04)),
            Err("run.time: must be at least one step (dt = 0.1), got 0.04".to_string())
        );
        assert_eq!(
            check(0.0, Some(1), None),
            Err("run.dt: must be > 0, got 0".to_string())
        );
    }
}
