//! The one place where nmm3d errors — and panics — become Python exceptions.

use std::panic::{self, AssertUnwindSafe};
use std::sync::Mutex;

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::PyErr;

create_exception!(nmm3d, NmmError, PyException, "Base class of nmm3d errors.");
create_exception!(
    nmm3d,
    ScenarioError,
    NmmError,
    "Invalid scenario: the message names the file, key path and reason (CLI exit 2)."
);
create_exception!(nmm3d, RunError, NmmError, "The run failed: divergence or an unsolvable system (CLI exit 1).");
create_exception!(nmm3d, OutputError, NmmError, "An output file could not be written (CLI exit 1).");
create_exception!(
    nmm3d,
    InternalError,
    NmmError,
    "A defect of nmm3d (a Rust panic), with the phase it stopped in (CLI exit 1)."
);

/// Map a core error to its Python exception.
pub fn to_py(e: nmm3d_core::Error) -> PyErr {
    use nmm3d_core::Error as E;
    let msg = e.to_string();
    match e {
        E::Scenario { .. } => ScenarioError::new_err(msg),
        E::Io { .. } => OutputError::new_err(msg),
        E::Solver { .. } | E::Diverged { .. } => RunError::new_err(msg),
    }
}

/// Where and why the last panic happened, kept by the hook instead of printed.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Replace the default panic hook (which prints to stderr) by one that keeps the message and
/// location for [`guard`]; called once when the module loads.
pub fn keep_panics_quiet() {
    panic::set_hook(Box::new(|info| {
        let at = info.location().map(|l| format!(" at {}:{}", l.file(), l.line())).unwrap_or_default();
        if let Ok(mut last) = LAST_PANIC.lock() {
            *last = Some(format!("{}{at}", payload_text(info.payload())));
        }
    }));
}

fn payload_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Run `f`, turning a core error into its exception and a panic into an [`InternalError`]
/// naming the `phase` (so `except nmm3d.NmmError` catches everything nmm3d raises).
pub fn guard<T>(phase: &str, f: impl FnOnce() -> nmm3d_core::Result<T>) -> Result<T, PyErr> {
    match panic::catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result.map_err(to_py),
        Err(payload) => {
            let kept = LAST_PANIC.lock().ok().and_then(|mut last| last.take());
            let why = kept.unwrap_or_else(|| payload_text(payload.as_ref()));
            Err(InternalError::new_err(format!(
                "internal error while {phase}: {why} (a defect of nmm3d: please report it with the scenario)"
            )))
        }
    }
}
