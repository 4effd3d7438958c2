//! Thin PyO3 layer over `nmm3d-core`: scenarios cross as JSON text, results as files and a
//! JSON summary. Every call converts, releases the GIL while computing, converts back.

mod errors;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;

use nmm3d_core::error::exit;
use nmm3d_core::simulation::{self, RunOptions, StopRequest};
use nmm3d_core::{input, scenario};
use pyo3::prelude::*;

/// The Rust side allocates many small geometry buffers (clipping, covers) and large solver
/// workspaces; mimalloc serves both with fewer page faults than the system allocator.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Parse, override and validate a TOML scenario file; returns the canonical scenario as JSON.
#[pyfunction]
#[pyo3(signature = (path, overrides = Vec::new()))]
fn load_file(py: Python<'_>, path: PathBuf, overrides: Vec<String>) -> PyResult<String> {
    py.detach(|| errors::guard("loading the scenario", || input::load_file(&path, &overrides).map(|s| canonical(&s))))
}

/// Validate a scenario given as JSON text (`label` names it in messages); returns it canonical.
#[pyfunction]
#[pyo3(signature = (text, label, overrides = Vec::new()))]
fn load_json(py: Python<'_>, text: String, label: String, overrides: Vec<String>) -> PyResult<String> {
    py.detach(|| {
        errors::guard("loading the scenario", || input::from_json_str(&text, &label, &overrides).map(|s| canonical(&s)))
    })
}

/// Run a scenario (JSON text) writing outputs to `out`; returns the summary as JSON text.
/// Ctrl-C (a pending Python signal, e.g. `KeyboardInterrupt`) stops the run after the current
/// step with status "interrupted"; the signal is consumed. `resume`: continue the run whose
/// `checkpoint.json` is in `out`.
#[pyfunction]
#[pyo3(signature = (text, label, out, progress = false, resume = false))]
fn run_json(
    py: Python<'_>,
    text: String,
    label: String,
    out: PathBuf,
    progress: bool,
    resume: bool,
) -> PyResult<String> {
    let requested = Arc::new(AtomicBool::new(false));
    let stop = StopRequest(Arc::new({
        let requested = Arc::clone(&requested);
        move || requested.load(Relaxed)
    }));
    let outcome = py.detach(|| {
        watching_signals(&requested, || {
            errors::guard("running", || {
                let s = input::from_json_str(&text, &label, &[])?;
                simulation::run(s, &label, &RunOptions { out, progress, stop: Some(stop), resume })
            })
        })
    })?;
    Ok(serde_json::to_string(&outcome.summary).expect("the summary serialises"))
}

/// How often the calling thread looks for a Python signal while a run computes [ms].
const SIGNAL_POLL_MS: u64 = 20;

/// `f` on a thread of its own while this one — Python's main thread, the only one Python hands
/// its signals to — looks for a pending signal every [`SIGNAL_POLL_MS`] and sets `requested`
/// when there is one (the signal is consumed). The run steps on a pool of its own
/// (`simulation::run`), so it cannot look itself.
fn watching_signals<T: Send>(requested: &AtomicBool, f: impl FnOnce() -> T + Send) -> T {
    std::thread::scope(|scope| {
        let run = scope.spawn(f);
        while !run.is_finished() {
            std::thread::sleep(std::time::Duration::from_millis(SIGNAL_POLL_MS));
            if !requested.load(Relaxed) && Python::attach(|py| py.check_signals().is_err()) {
                requested.store(true, Relaxed);
            }
        }
        // `f` is guarded (`errors::guard`): it returns, it does not unwind.
        run.join().unwrap_or_else(|payload| std::panic::resume_unwind(payload))
    })
}

/// Build the blocks of a scenario (JSON text); with `out`, write `blocks.csv` and `blocks.vtu`
/// there and return the report, else return the block table. JSON text either way.
#[pyfunction]
#[pyo3(signature = (text, label, out = None))]
fn blocks_json(py: Python<'_>, text: String, label: String, out: Option<PathBuf>) -> PyResult<String> {
    let v = py.detach(|| {
        errors::guard("cutting the blocks", || {
            let s = input::from_json_str(&text, &label, &[])?;
            match out {
                Some(dir) => nmm3d_core::blocks::report(&s, &label, &dir),
                None => Ok(nmm3d_core::blocks::table(&s)),
            }
        })
    })?;
    Ok(v.to_string())
}

/// A panic inside the binding boundary, for the tests of [`errors::guard`] (no input of nmm3d's
/// is known to panic; every one found became an input error or a fix).
#[pyfunction]
fn _panic_for_test() -> PyResult<()> {
    errors::guard("testing the panic guard", || -> nmm3d_core::Result<()> { panic!("a deliberate panic") })
}

/// Build what a run of the scenario (JSON text) builds before its first step, for every stage:
/// the error a run would end with, or each stage's blocks and MEs as JSON.
#[pyfunction]
fn check_json(py: Python<'_>, text: String, label: String) -> PyResult<String> {
    let v = py.detach(|| {
        errors::guard("checking the model", || {
            let s = input::from_json_str(&text, &label, &[])?;
            simulation::check(s, &label)
        })
    })?;
    Ok(v.to_string())
}

/// Cut the rock mass and build its covers (no element matrices); counts and seconds as JSON.
#[pyfunction]
fn cover_report_json(py: Python<'_>, text: String, label: String) -> PyResult<String> {
    let v = py.detach(|| {
        errors::guard("building the covers", || {
            input::from_json_str(&text, &label, &[]).map(|s| nmm3d_core::blocks::cover_report(&s))
        })
    })?;
    Ok(v.to_string())
}

/// The surfaces of the cut blocks (faces, their joints and touching areas) as JSON, for the
/// key-block analysis.
#[pyfunction]
fn block_surfaces_json(py: Python<'_>, text: String, label: String) -> PyResult<String> {
    let v = py.detach(|| {
        errors::guard("reading the block surfaces", || {
            input::from_json_str(&text, &label, &[]).map(|s| nmm3d_core::blocks::surfaces(&s))
        })
    })?;
    Ok(v.to_string())
}

/// The canonical scenario as JSON text (the values were validated, so it serialises).
fn canonical(s: &scenario::Scenario) -> String {
    serde_json::to_string(s).expect("a validated scenario serialises")
}

/// The native module `nmm3d._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(load_file, m)?)?;
    m.add_function(wrap_pyfunction!(load_json, m)?)?;
    m.add_function(wrap_pyfunction!(run_json, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_json, m)?)?;
    m.add_function(wrap_pyfunction!(check_json, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    m.add_function(wrap_pyfunction!(cover_report_json, m)?)?;
    m.add_function(wrap_pyfunction!(block_surfaces_json, m)?)?;
    m.add("NmmError", m.py().get_type::<errors::NmmError>())?;
    m.add("ScenarioError", m.py().get_type::<errors::ScenarioError>())?;
    m.add("RunError", m.py().get_type::<errors::RunError>())?;
    m.add("OutputError", m.py().get_type::<errors::OutputError>())?;
    m.add("InternalError", m.py().get_type::<errors::InternalError>())?;
    for (name, code) in
        [("OK", exit::OK), ("FAILED", exit::FAILED), ("INPUT", exit::INPUT), ("INTERRUPTED", exit::INTERRUPTED)]
    {
        m.add(format!("EXIT_{name}").as_str(), code)?;
    }
    for (ty, code) in [
        (m.py().get_type::<errors::NmmError>(), exit::FAILED),
        (m.py().get_type::<errors::ScenarioError>(), exit::INPUT),
        (m.py().get_type::<errors::RunError>(), exit::FAILED),
        (m.py().get_type::<errors::OutputError>(), exit::FAILED),
        (m.py().get_type::<errors::InternalError>(), exit::FAILED),
    ] {
        ty.setattr("exit_code", code)?;
    }
    errors::keep_panics_quiet();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
