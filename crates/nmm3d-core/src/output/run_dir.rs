//! The run directory: one run writes it at a time (a lock file naming the process), and a
//! fresh run starts from a clean one (the outputs of an earlier run are removed first, so no
//! old frame or table is mistaken for the new run's).

use std::io::{ErrorKind, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// The lock file, present while a run writes the directory; it holds the writer's process id.
pub const LOCK: &str = ".nmm3d.lock";

/// The files a run writes at the top of its directory (frames go to `frames/`).
pub const OUTPUTS: [&str; 8] = [
    "summary.json",
    "history.csv",
    "diagnostics.csv",
    "cuts.csv",
    "blocks.csv",
    "blocks.vtu",
    "result.pvd",
    "checkpoint.json",
];

/// A locked run directory; the lock goes when this is dropped.
#[derive(Debug)]
pub struct RunDir {
    lock: PathBuf,
}

impl Drop for RunDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.lock);
    }
}

/// Create and lock `out` for a run of the scenario `label`; with `fresh`, remove the outputs
/// of an earlier run first. A directory another live process is writing is refused (input
/// error naming `--out`); a lock left by a process that no longer runs is taken over.
pub fn open(out: &Path, label: &str, fresh: bool) -> Result<RunDir> {
    if out.as_os_str().is_empty() {
        return Err(Error::input(label, "--out", "the output directory must not be empty (use . for this one)"));
    }
    std::fs::create_dir_all(out.join("frames")).map_err(|e| Error::io(out, e))?;
    let lock = out.join(LOCK);
    for _ in 0..2 {
        match std::fs::OpenOptions::new().write(true).create_new(true).open(&lock) {
            Ok(mut f) => {
                let _ = write!(f, "{}", std::process::id());
                if fresh {
                    clear(out)?;
                }
                return Ok(RunDir { lock });
            }
            Err(e) if e.kind() == ErrorKind::AlreadyExists => {
                let holder = std::fs::read_to_string(&lock).ok().and_then(|s| s.trim().parse::<u32>().ok());
                if let Some(pid) = holder.filter(|&p| alive(p)) {
                    return Err(Error::input(
                        label,
                        "--out",
                        format!(
                            "{} is being written by another run (process {pid}); choose another directory, or remove {} if that process is gone",
                            out.display(),
                            lock.display()
                        ),
                    ));
                }
                let _ = std::fs::remove_file(&lock);
            }
            Err(e) => return Err(Error::io(&lock, e)),
        }
    }
    Err(Error::io(&lock, std::io::Error::new(ErrorKind::AlreadyExists, "the lock file keeps reappearing")))
}

/// Remove the outputs of an earlier run (only the files runs write).
fn clear(out: &Path) -> Result<()> {
    for name in OUTPUTS {
        remove_if_present(&out.join(name))?;
    }
    let frames = std::fs::read_dir(out.join("frames")).map_err(|e| Error::io(out.join("frames"), e))?;
    for entry in frames.flatten().filter(|e| e.file_type().is_ok_and(|t| t.is_file())) {
        let path = entry.path();
        if path.extension().is_some_and(|x| x == "vtu") {
            remove_if_present(&path)?;
        }
    }
    Ok(())
}

fn remove_if_present(path: &Path) -> Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != ErrorKind::NotFound => Err(Error::io(path, e)),
        _ => Ok(()),
    }
}

/// Whether process `pid` runs (Linux: `/proc/<pid>`; elsewhere every lock counts as live,
/// as does one of this very process — another run in one of its threads).
fn alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    if pid == std::process::id() || !proc.is_dir() {
        return true;
    }
    // A killed run its parent has not reaped yet (a zombie, state Z) writes no more: `stat` is
    // "pid (name) state …", the name in parentheses.
    match std::fs::read_to_string(proc.join(pid.to_string()).join("stat")) {
        Ok(stat) => {
            !matches!(stat.rsplit_once(')').and_then(|(_, rest)| rest.trim_start().chars().next()), Some('Z' | 'X'))
        }
        Err(_) => proc.join(pid.to_string()).exists(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("nmm3d_run_dir_{name}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_killed_process_not_yet_reaped_holds_no_lock() {
        if !Path::new("/proc").is_dir() {
            return;
        }
        let mut child = std::process::Command::new("sleep").arg("30").spawn().unwrap();
        assert!(alive(child.id()));
        child.kill().unwrap();
        // Dead but not waited for: a zombie until `wait`.
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(5);
        while alive(child.id()) && std::time::Instant::now() < deadline {
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        assert!(!alive(child.id()), "a zombie counted as a live run");
        child.wait().unwrap();
    }

    #[test]
    fn a_fresh_run_clears_old_outputs_and_keeps_other_files() {
        let d = dir("fresh");
        std::fs::create_dir_all(d.join("frames")).unwrap();
        for f in ["summary.json", "history.csv", "frames/blocks_00007.vtu", "notes.txt", "frames/readme.md"] {
            std::fs::write(d.join(f), "old").unwrap();
        }
        let held = open(&d, "<test>", true).unwrap();
        assert!(!d.join("summary.json").exists() && !d.join("history.csv").exists());
        assert!(!d.join("frames/blocks_00007.vtu").exists());
        assert!(d.join("notes.txt").exists() && d.join("frames/readme.md").exists(), "not ours: kept");
        drop(held);
        assert!(!d.join(LOCK).exists(), "the lock goes with the run");
        // A resumed run keeps what is there.
        std::fs::write(d.join("checkpoint.json"), "{}").unwrap();
        let _held = open(&d, "<test>", false).unwrap();
        assert!(d.join("checkpoint.json").exists());
    }

    #[test]
    fn a_directory_being_written_is_refused_and_a_stale_lock_taken_over() {
        let d = dir("lock");
        let first = open(&d, "<test>", true).unwrap();
        match open(&d, "<test>", true) {
            Err(Error::Scenario { problems, .. }) => {
                assert_eq!(problems[0].path, "--out");
                assert!(problems[0].reason.contains("being written by another run"), "{}", problems[0].reason);
            }
            other => panic!("expected refusal, got {other:?}"),
        }
        drop(first);
        // A lock left by a process that is gone (pid beyond the kernel's maximum).
        std::fs::write(d.join(LOCK), "4294967295").unwrap();
        if Path::new("/proc").is_dir() {
            assert!(open(&d, "<test>", true).is_ok(), "a stale lock is taken over");
        }
    }

    #[test]
    fn an_empty_directory_name_is_an_input_error() {
        assert!(matches!(open(Path::new(""), "<test>", true), Err(Error::Scenario { .. })));
    }
}
