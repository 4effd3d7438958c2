//! Typed errors of the method crate. `exit_code` is the single mapping to CLI exit codes;
//! the bindings map the same variants to Python exceptions in one place.

use std::path::PathBuf;

/// One problem in the input: where and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Key path, e.g. `material.rock.poisson` or `body[2].shape.box.max`.
    pub path: String,
    /// What is wrong.
    pub reason: String,
}

/// Everything that can stop nmm3d.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Invalid input: every problem found, with its key path.
    #[error("{}", format_problems(file, problems))]
    Scenario {
        /// The scenario file (or "<dict>" from Python).
        file: String,
        /// Problems found.
        problems: Vec<Problem>,
    },
    /// The linear system could not be factorised.
    #[error("linear solver failed at step {step}: {reason}{}", pivot.as_ref().map(Pivot::describe).unwrap_or_default())]
    Solver {
        /// Step number.
        step: u64,
        /// Solver message.
        reason: String,
        /// Where the factorisation met a non-positive pivot, when it did.
        pivot: Option<Pivot>,
    },
    /// The run diverged (NaN, runaway displacement, no acceptable step).
    #[error("run diverged at step {step} (t = {time:.6} s): {reason}")]
    Diverged {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// What was detected.
        reason: String,
    },
    /// A file could not be written or read.
    #[error("cannot access {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
}

fn format_problems(file: &str, problems: &[Problem]) -> String {
    let lines: Vec<String> = problems.iter().map(|p| format!("{file}: {}: {}", p.path, p.reason)).collect();
    lines.join("\n")
}

/// The equation at which a Cholesky factorisation met a non-positive pivot, and what it belongs to.
#[derive(Debug, Clone, PartialEq)]
pub struct Pivot {
    /// Equation (row of the system matrix, 3 per free cover).
    pub equation: usize,
    /// Physical cover of the equation.
    pub cover: usize,
    /// Block of the cover.
    pub block: usize,
    /// Body of the block.
    pub body: String,
    /// Position of the cover's node [m].
    pub position: [f64; 3],
}

impl Pivot {
    fn describe(&self) -> String {
        let [x, y, z] = self.position;
        format!(
            " (the pivot of equation {} — cover {} of block {} of body '{}', node at ({x:.4}, {y:.4}, {z:.4}) — is not positive: \
             that block may be free to move without inertia, or a penalty far too large)",
            self.equation, self.cover, self.block, self.body
        )
    }
}

impl Error {
    /// A single input problem.
    pub fn input(file: &str, path: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Scenario { file: file.to_string(), problems: vec![Problem { path: path.into(), reason: reason.into() }] }
    }

    /// CLI exit status of this error: [`exit::INPUT`] or [`exit::FAILED`].
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Scenario { .. } => exit::INPUT,
            _ => exit::FAILED,
        }
    }

    /// Wrap an I/O error with the file it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io { path: path.into(), source }
    }
}

/// The exit statuses of the command line, defined once (the Python CLI reads them from the
/// native module).
pub mod exit {
    /// Done (a study: found or out of range).
    pub const OK: i32 = 0;
    /// The run failed (divergence, an unsolvable system, an unwritable output, a defect).
    pub const FAILED: i32 = 1;
    /// Invalid input: the message names the file, key path and reason.
    pub const INPUT: i32 = 2;
    /// Interrupted (Ctrl-C), as shells report SIGINT: 128 + 2.
    pub const INTERRUPTED: i32 = 130;
}

/// Result alias.
pub type Result<T> = std::result::Result<T, Error>;
