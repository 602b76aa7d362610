//! `quatrot.run(scene)` and `quatrot.builtin_scenes()`: scenes from Python.
//! A scene arrives as TOML text, a built-in name, a path or a dict; the run
//! happens without the GIL; results come back as numpy arrays and a summary
//! dict. Scene errors raise `quatrot.SceneError` (a `ValueError`) naming the
//! field; a blow-up raises `quatrot.BlowUpError` and Ctrl-C
//! `KeyboardInterrupt`, each carrying the partial results in its `result`
//! attribute.

use crate::run::{execute, Outputs, RunError, RunResult};
use crate::scene::raw::RawScene;
use crate::scene::{load, load_table, load_text, Overrides, Scene, BUILTINS};
use crate::simulation::Control;
use crate::simulation::Stop;
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

/// How often a running `quatrot.run` checks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

create_exception!(
    quatrot,
    SceneError,
    PyValueError,
    "A scene is invalid; the message names the field."
);
create_exception!(
    quatrot,
    BlowUpError,
    PyRuntimeError,
    "A run blew up; `result` holds what it recorded."
);

fn scene_error(e: &crate::scene::SceneError) -> PyErr {
    SceneError::new_err(e.to_string())
}

fn run_error(e: RunError) -> PyErr {
    match e {
        RunError::Scene(e) => scene_error(&e),
        RunError::Io { .. } => PyOSError::new_err(e.to_string()),
        other => PyRuntimeError::new_err(other.to_string()),
    }
}

/// Converts a Python value of a scene dict to TOML, naming the path on error.
fn to_toml(value: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    let here = |p: &str| {
        if p.is_empty() {
            "(top level)".to_string()
        } else {
            p.to_string()
        }
    };
    if value.is_none() {
        return Err(SceneError::new_err(format!(
            "{}: None is not allowed (leave the key out)",
            here(path)
        )));
    }
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if let Ok(i) = value.cast::<PyInt>() {
        return i.extract::<i64>().map(toml::Value::Integer).map_err(|_| {
            SceneError::new_err(format!("{}: integer out of range, got {i}", here(path)))
        });
    }
    if let Ok(f) = value.cast::<PyFloat>() {
        return Ok(toml::Value::Float(f.value()));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(toml::Value::String(s.to_str()?.to_string()));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key = k.cast::<PyString>().map_err(|_| {
                SceneError::new_err(format!("{}: keys must be strings, got {k}", here(path)))
            })?;
            let key = key.to_str()?.to_string();
            let sub = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            let _ = table.insert(key, to_toml(&v, &sub)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value
            .try_iter()?
            .enumerate()
            .map(|(k, item)| to_toml(&item?, &format!("{path}[{k}]")))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if value.hasattr("tolist")? {
        // numpy arrays and scalars.
        return to_toml(&value.call_method0("tolist")?, path);
    }
    Err(SceneError::new_err(format!(
        "{}: unsupported value of type {}",
        here(path),
        value.get_type().name()?
    )))
}

/// TOML text if it has a newline or `=`, otherwise a built-in name or a path.
fn load_scene(scene: &Bound<'_, PyAny>, overrides: &Overrides) -> PyResult<(RawScene, Scene)> {
    if let Ok(d) = scene.cast::<PyDict>() {
        let toml::Value::Table(table) = to_toml(d.as_any(), "")? else {
            return Err(SceneError::new_err("(top level): expected a table"));
        };
        return load_table(table, overrides).map_err(|e| scene_error(&e));
    }
    if let Ok(s) = scene.cast::<PyString>() {
        let text = s.to_str()?;
        let loaded = if text.contains('\n') || text.contains('=') {
            load_text(text, overrides)
        } else {
            load(text, overrides)
        };
        return loaded.map_err(|e| scene_error(&e));
    }
    let path: PathBuf = scene.extract().map_err(|_| {
        SceneError::new_err("scene: expected TOML text, a built-in name, a path or a dict")
    })?;
    let name = path.to_string_lossy().to_string();
    let name = if name.contains(['/', '\\']) || name.ends_with(".toml") {
        name
    } else {
        format!("./{name}")
    };
    load(&name, overrides).map_err(|e| scene_error(&e))
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

/// run(scene, *, out_dir=None, dt=None, steps=None, integrator=None, restart=None)
///
/// Runs a scene given as TOML text, a built-in name, a path or a dict.
/// `out_dir` (optional) receives the CSV, DCD + PDB, checkpoint and summary
/// files; `dt`, `steps` and `integrator` override the scene's; `restart` is a
/// checkpoint file to continue from. Returns a dict with `summary` (dict),
/// `series` ({name: {column: ndarray}}), `trajectory` (None, or `step`,
/// `time`, `orientations` (frames, n, 4), `omega_body` (frames, n, 3)),
/// `sites` (n, 3), `initial_orientations` (n, 4), `initial_omega_body` (n, 3).
/// The GIL is released while the run goes on. Ctrl-C (a signal whose
/// handler raises) stops the run at the end of the step in progress, with
/// its files flushed and closed (a checkpoint written when the scene asks
/// for checkpoints), and raises `KeyboardInterrupt` with the partial result
/// dict in its `result` attribute (`summary["status"]` is `"interrupted"`).
#[pyfunction]
#[pyo3(signature = (scene, *, out_dir=None, dt=None, steps=None, integrator=None, restart=None))]
fn run<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    out_dir: Option<PathBuf>,
    dt: Option<f64>,
    steps: Option<i64>,
    integrator: Option<String>,
    restart: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let overrides = Overrides {
        dt,
        steps,
        integrator,
    };
    let (raw, scene) = load_scene(scene, &overrides)?;
    let definition = raw.definition();
    let control = Arc::new(Control::new());
    let outputs = Outputs {
        dir: out_dir,
        keep: true,
        control: Some(Arc::clone(&control)),
    };
    // The run goes on in its own thread, without the GIL; this thread checks
    // for signals (Ctrl-C) between short waits and passes a stop request on.
    let (result, interrupt) = std::thread::scope(|scope| {
        let run = scope.spawn(|| execute(&scene, definition, &outputs, restart.as_deref(), None));
        let mut interrupt = None;
        while !run.is_finished() {
            py.detach(|| std::thread::sleep(SIGNAL_POLL));
            if interrupt.is_none() {
                if let Err(e) = py.check_signals() {
                    control.request_stop();
                    interrupt = Some(e);
                }
            }
        }
        (run.join(), interrupt)
    });
    let result = result
        .map_err(|_| PyRuntimeError::new_err("the run panicked"))?
        .map_err(run_error)?;
    let message = result.stop.message();
    let blew_up = matches!(result.stop, Stop::BlewUp { .. });
    let dict = result_dict(py, &scene, result)?;
    if let Some(err) = interrupt {
        err.value(py).setattr("result", dict)?;
        return Err(err);
    }
    if blew_up {
        let err = BlowUpError::new_err(message.unwrap_or_default());
        err.value(py).setattr("result", dict)?;
        return Err(err);
    }
    Ok(dict)
}

/// builtin_scenes() -> dict[str, str]: the built-in scenes' TOML texts by name.
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
    Ok(())
}
