//! The one place where nmm3d errors become Python exceptions.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::PyErr;

create_exception!(nmm3d, NmmError, PyException, "Base class of nmm3d errors.");
create_exception!(nmm3d, ScenarioError, NmmError, "Invalid scenario: the message names the file, key path and reason (CLI exit 2).");
create_exception!(nmm3d, RunError, NmmError, "The run failed: divergence or an unsolvable system (CLI exit 1).");
create_exception!(nmm3d, OutputError, NmmError, "An output file could not be written (CLI exit 1).");

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
