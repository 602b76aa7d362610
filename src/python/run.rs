//! `quatrot.run(scene)` and `quatrot.builtin_scenes()`: scenes from Python.
//! A scene arrives as TOML text, a built-in name, a path or a dict; the run
//! happens without the GIL; results come back as numpy arrays and a summary
//! dict. Scene errors raise `quatrot.SceneError` (a `ValueError`) naming the
//! field; a blow-up raises `quatrot.BlowUpError`, and Ctrl-C
//! `KeyboardInterrupt`, carrying the partial results in their `result`
//! attribute. A scene dict is converted with its nesting bounded and its
//! cycles refused.

use super::args::{integer, invalid, path_or, text_or, wrong_type};
use super::scene_dict::{field, load_scene, scene_error, SceneError};
use crate::run::{execute, Outputs, RunError, RunResult};
use crate::scene::{Overrides, Scene, BUILTINS};
use crate::simulation::{Control, Stop};
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyRuntimeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyInt};
use std::num::NonZeroUsize;
use std::sync::{mpsc, Arc};
use std::time::Duration;

create_exception!(
    quatrot,
    BlowUpError,
    PyRuntimeError,
    "A run blew up; `result` holds what it recorded."
);

/// A run's error: an invalid scene is a `SceneError`, a file that cannot
/// be read or written an `OSError`, anything else a `RuntimeError`.
impl From<RunError> for PyErr {
    fn from(e: RunError) -> PyErr {
        match e {
            RunError::Scene(e) => scene_error(&e),
            // Built from the scene: coincident sites, sizes of the sums.
            RunError::Potential(_) => SceneError::new_err(e.to_string()),
            RunError::Io { .. } => PyOSError::new_err(e.to_string()),
            other => PyRuntimeError::new_err(other.to_string()),
        }
    }
}

/// The result as a dict of numpy arrays and the summary.
fn result_dict<'py>(
    py: Python<'py>,
    scene: &Scene,
    result: RunResult,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let json = py.import("json")?;
    let summary_text = serde_json::to_string(&result.summary)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    out.set_item("summary", json.call_method1("loads", (summary_text,))?)?;
    let series = PyDict::new(py);
    for table in result.series {
        let columns = PyDict::new(py);
        let width = table.columns.len();
        for (c, name) in table.columns.iter().enumerate() {
            let column: Vec<f64> = table
                .values
                .iter()
                .skip(c)
                .step_by(width)
                .copied()
                .collect();
            columns.set_item(name, column.into_pyarray(py))?;
        }
        series.set_item(table.name, columns)?;
    }
    out.set_item("series", series)?;
    let n = scene.rotors.len();
    let trajectory = match result.trajectory {
        Some(t) => {
            let frames = t.steps.len();
            let d = PyDict::new(py);
            d.set_item("step", t.steps.into_pyarray(py))?;
            d.set_item("time", t.times.into_pyarray(py))?;
            d.set_item(
                "orientations",
                t.orientations.into_pyarray(py).reshape([frames, n, 4])?,
            )?;
            d.set_item(
                "omega_body",
                t.omega_body.into_pyarray(py).reshape([frames, n, 3])?,
            )?;
            d.into_any()
        }
        None => py.None().into_bound(py),
    };
    out.set_item("trajectory", trajectory)?;
    let sites: Vec<f64> = scene
        .rotors
        .iter()
        .flat_map(|r| [r.site.x, r.site.y, r.site.z])
        .collect();
    out.set_item("sites", sites.into_pyarray(py).reshape([n, 3])?)?;
    let q0: Vec<f64> = scene.initial.iter().flat_map(|s| s.orientation.0).collect();
    out.set_item("initial_orientations", q0.into_pyarray(py).reshape([n, 4])?)?;
    let w0: Vec<f64> = scene
        .initial
        .iter()
        .flat_map(|s| [s.omega_body.x, s.omega_body.y, s.omega_body.z])
        .collect();
    out.set_item("initial_omega_body", w0.into_pyarray(py).reshape([n, 3])?)?;
    Ok(out)
}

/// How often a run started from Python looks at its progress and at
/// Ctrl-C (Python's pending signals).
const POLL: Duration = Duration::from_millis(20);

/// Runs a scene: TOML text, a built-in name, a path or a dict.
///
/// The GIL is released while the run goes on. Ctrl-C stops it at the end of
/// the step in progress, with its output files flushed and closed (summary
/// status `"interrupted"`, a checkpoint written when the scene asks for
/// checkpoints), and raises `KeyboardInterrupt` whose `result` attribute
/// holds the dict of what the run recorded.
///
/// Parameters
/// ----------
/// scene : str, path or dict
///     The scene (docs: scene reference).
/// out_dir : str or path, optional
///     Folder for the CSV, DCD + PDB, checkpoint and summary files (none
///     written without it).
/// dt : float, optional
///     Overrides the scene's time step.
/// steps : int, optional
///     Overrides the scene's number of steps.
/// integrator : str, optional
///     Overrides the scene's integrator kind (`"gear_a"`, `"gear_b"`,
///     `"no_squish"`, `"dlm"`, `"richardson"`).
/// no_thermostat : bool, default False
///     Drops the scene's thermostat: the run keeps its energy from the
///     scene's start (`"gear_b"` and `"richardson"` take no thermostat).
/// restart : str or path, optional
///     A checkpoint file to continue from.
/// threads : int, optional
///     Runs on a pool of that many threads (1 to `MAX_THREADS`; default
///     the scene's `run.threads`, else the shared pool when
///     `RAYON_NUM_THREADS` is set, else one thread per
///     500 rotors or 250 sites of moving bodies, at least 1, at most the
///     cores; recorded in the summary's
///     `threads`). The periodic pair loop's last bits depend on it.
/// progress : bool, default False
///     A progress bar (tqdm if installed, else a line on stderr).
/// on_progress : callable, optional
///     `on_progress(step, total)`, called about every 20 ms and at the end;
///     an exception it raises stops the run and is raised.
///
/// Returns
/// -------
/// dict
///     `summary` (dict, as `summary.json`), `series` ({name: {column:
///     ndarray}}), `trajectory` (None, or `step`, `time`, `orientations`
///     (frames, n, 4), `omega_body` (frames, n, 3)), `sites` (n, 3),
///     `initial_orientations` (n, 4), `initial_omega_body` (n, 3). A
///     scene in real units (``units = "real"``) returns its series in them
///     (time in fs, temperatures in K, pressure in atm) and its summary
///     names them (``summary["units"]``).
///
/// Raises
/// ------
/// SceneError
///     An invalid scene; the message names the field.
/// BlowUpError
///     The run blew up; the message names the step and the rotor, or the
///     two bodies and their sites; its `result` holds what it recorded.
/// OSError
///     An output file that cannot be written.
///
/// Examples
/// --------
/// ```python
///
/// >>> result = quatrot.run("dipole_in_field", steps=100)
/// >>> result["summary"]["status"], result["summary"]["last_step"]
/// ('completed', 100)
/// >>> sorted(result["series"]["energies"])[:3]
/// ['energy_error', 'kinetic_energy', 'potential_energy']
///
/// ```
#[pyfunction]
#[pyo3(signature = (scene, *, out_dir=None, dt=None, steps=None, integrator=None, no_thermostat=false, restart=None, threads=None, progress=false, on_progress=None))]
#[allow(clippy::too_many_arguments)]
fn run<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    out_dir: Option<&Bound<'py, PyAny>>,
    dt: Option<f64>,
    steps: Option<&Bound<'py, PyAny>>,
    integrator: Option<&Bound<'py, PyAny>>,
    no_thermostat: bool,
    restart: Option<&Bound<'py, PyAny>>,
    threads: Option<&Bound<'py, PyAny>>,
    progress: bool,
    on_progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let threads = threads.map(thread_count).transpose()?;
    let path = |p: &Bound<'py, PyAny>, name| path_or(p, name, field);
    let out_dir = out_dir.map(|p| path(p, "out_dir")).transpose()?;
    if out_dir.as_ref().is_some_and(|d| d.as_os_str().is_empty()) {
        return Err(field(
            "out_dir",
            "must be a folder's path, got an empty one (use \".\" for the current directory)"
                .to_string(),
        ));
    }
    let restart = restart.map(|p| path(p, "restart")).transpose()?;
    let overrides = Overrides {
        dt,
        steps: steps.map(step_count).transpose()?,
        integrator: integrator
            .map(|i| text_or(i, "integrator", field))
            .transpose()?,
        no_thermostat,
    };
    let (raw, scene) = load_scene(scene, &overrides)?;
    let definition = raw.definition();
    let control = Arc::new(Control::new());
    let outputs = Outputs {
        dir: out_dir,
        keep: true,
        control: Some(Arc::clone(&control)),
        threads,
    };
    let mut reporters: Vec<Bound<'py, PyAny>> = on_progress.into_iter().cloned().collect();
    if progress {
        reporters.push(
            py.import("quatrot._progress")?
                .call_method1("bar", (scene.steps,))?,
        );
    }
    let go = || execute(&scene, definition, &outputs, restart.as_deref(), None);
    let (finished, stopped_by) = std::thread::scope(|s| {
        let (send, receive) = mpsc::channel();
        let _ = s.spawn(move || {
            let _ = send.send(go());
        });
        watch(py, receive, &control, scene.steps, &reporters)
    });
    for r in reporters
        .iter()
        .filter(|r| r.hasattr("close").unwrap_or(false))
    {
        let _ = r.call_method0("close")?;
    }
    let result =
        finished.ok_or_else(|| PyRuntimeError::new_err("the run ended without a result"))??;
    let message = result.summary.message.clone();
    let stop = result.stop.clone();
    let dict = result_dict(py, &scene, result)?;
    let err = match (stopped_by, stop) {
        (Some(err), _) => err,
        (None, Stop::BlewUp { .. }) => BlowUpError::new_err(message.unwrap_or_default()),
        (None, _) => return Ok(dict),
    };
    err.value(py).setattr("result", dict)?;
    Err(err)
}

/// Waits for the run sending its result on `receive` (`None` if it ended
/// without one), without the GIL but for a look every [`POLL`]: reports the step reached to `reporters` and,
/// on Ctrl-C (a pending `KeyboardInterrupt`) or an exception of a reporter,
/// asks the run to stop and keeps that exception to raise.
fn watch<T: Send>(
    py: Python<'_>,
    mut receive: mpsc::Receiver<T>,
    control: &Control,
    total: u64,
    reporters: &[Bound<'_, PyAny>],
) -> (Option<T>, Option<PyErr>) {
    let mut stopped_by: Option<PyErr> = None;
    let mut reported = None;
    loop {
        let (r, waited) = py.detach(move || {
            let waited = receive.recv_timeout(POLL);
            (receive, waited)
        });
        receive = r;
        let step = control.step();
        if reported != Some(step) && stopped_by.is_none() {
            reported = Some(step);
            if let Some(e) = reporters.iter().find_map(|r| r.call1((step, total)).err()) {
                control.request_stop();
                stopped_by = Some(e);
            }
        }
        match waited {
            Ok(finished) => return (Some(finished), stopped_by),
            Err(mpsc::RecvTimeoutError::Disconnected) => return (None, stopped_by),
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        if stopped_by.is_none() {
            if let Err(e) = py.check_signals() {
                control.request_stop();
                stopped_by = Some(e);
            }
        }
    }
}

/// The `threads` argument: an integer from 1 to
/// [`crate::parallel::MAX_THREADS`].
fn thread_count(threads: &Bound<'_, PyAny>) -> PyResult<NonZeroUsize> {
    let max = crate::parallel::MAX_THREADS;
    let n = integer(threads, "threads", 1, max as u64)?;
    NonZeroUsize::new(usize::try_from(n).unwrap_or(max))
        .ok_or_else(|| invalid("threads", format!("must be between 1 and {max}, got {n}")))
}

/// The `steps` argument: an integer the scene's `run.steps` can hold (the
/// scene checks its range).
fn step_count(steps: &Bound<'_, PyAny>) -> PyResult<i64> {
    if !steps.is_instance_of::<PyInt>() {
        return Err(wrong_type(steps, "steps", "an integer"));
    }
    steps.extract().map_err(|_| {
        field(
            "steps",
            format!("must be at most {}, got {steps}", i64::MAX),
        )
    })
}

/// The built-in scenes' TOML texts by name.
///
/// Returns
/// -------
/// dict of str to str
///
/// Examples
/// --------
/// ```python
///
/// >>> scenes = quatrot.builtin_scenes()
/// >>> "dipole_in_field" in scenes
/// True
/// >>> quatrot.run(scenes["free_spherical_top"], steps=10)["summary"]["status"]
/// 'completed'
///
/// ```
#[pyfunction]
fn builtin_scenes(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    for b in BUILTINS {
        d.set_item(b.name, b.toml)?;
    }
    Ok(d)
}

/// Adds `run`, `builtin_scenes`, `SceneError` and `BlowUpError` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(builtin_scenes, m)?)?;
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("BlowUpError", m.py().get_type::<BlowUpError>())?;
    m.add("MAX_THREADS", crate::parallel::MAX_THREADS)?;
    Ok(())
}
