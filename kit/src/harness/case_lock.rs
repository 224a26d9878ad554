//! Cases whose verdict rests on a measured time (`Case::timed_verdict`) run with nothing beside
//! them: not in their own run (`check --jobs N`), nor in any other fragkit process on the machine
//! (a matrix's configurations run in parallel, two CI jobs on one runner). Every case run holds
//! one lock file while it runs: other cases share it, a timed case holds it alone. A turnstile in
//! front of it keeps a timed case from waiting for ever behind a stream of sharing cases: a timed
//! case holds the turnstile while it waits, and a case passes the turnstile before it shares.
//!
//! The files are `fragkit-cases.lock` and `fragkit-cases.turnstile` in the temporary folder, or
//! `$FRAGKIT_CASE_LOCK.lock` and `.turnstile` (processes that should not see each other, or a
//! folder all users can write).

use std::fs::{File, OpenOptions, TryLockError};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::case::Case;

/// The environment variable that names the lock files' common stem.
pub const CASE_LOCK: &str = "FRAGKIT_CASE_LOCK";

/// A case run's hold on the lock; released when dropped (or when its process dies).
pub struct CaseLock {
    _held: Vec<File>,
}

fn stem() -> PathBuf {
    std::env::var_os(CASE_LOCK).map_or_else(|| std::env::temp_dir().join("fragkit-cases"), PathBuf::from)
}

fn open(stem: &Path, extension: &str) -> Result<(File, PathBuf)> {
    let path = stem.with_extension(extension);
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(&path)
        .with_context(|| format!("opening the case lock {} (set {CASE_LOCK} to move it)", path.display()))?;
    Ok((file, path))
}

/// Takes a lock at once, or tells `waiting` and then blocks for it.
fn take(
    file: &File,
    path: &Path,
    alone: bool,
    waiting: &mut dyn FnMut(bool) -> Result<()>,
    waited: &mut bool,
) -> Result<()> {
    let tried = if alone { file.try_lock() } else { file.try_lock_shared() };
    match tried {
        Ok(()) => Ok(()),
        Err(TryLockError::WouldBlock) => {
            if !*waited {
                waiting(true)?;
                *waited = true;
            }
            let locked = if alone { file.lock() } else { file.lock_shared() };
            locked.with_context(|| format!("waiting for the case lock {}", path.display()))
        }
        Err(TryLockError::Error(e)) => Err(e).with_context(|| format!("locking {}", path.display())),
    }
}

/// The lock `case` runs under: alone where its verdict is timed, shared otherwise. `waiting` is
/// told `true` before the call blocks (a timed case runs elsewhere, or this one waits for the
/// others to end) and `false` once the lock is held, so that a supervisor does not count the
/// wait against the case's time.
pub fn lock_for(case: &Case, waiting: impl FnMut(bool) -> Result<()>) -> Result<CaseLock> {
    lock_at(&stem(), case, waiting)
}

/// [`lock_for`] with the lock files at `stem`.
fn lock_at(stem: &Path, case: &Case, mut waiting: impl FnMut(bool) -> Result<()>) -> Result<CaseLock> {
    let (turnstile, turnstile_path) = open(stem, "turnstile")?;
    let (lock, lock_path) = open(stem, "lock")?;
    let mut waited = false;
    take(&turnstile, &turnstile_path, true, &mut waiting, &mut waited)?;
    let held = if case.timed_verdict {
        take(&lock, &lock_path, true, &mut waiting, &mut waited)?;
        vec![turnstile, lock]
    } else {
        take(&lock, &lock_path, false, &mut waiting, &mut waited)?;
        turnstile.unlock().with_context(|| format!("passing the turnstile {}", turnstile_path.display()))?;
        vec![lock]
    };
    if waited {
        waiting(false)?;
    }
    Ok(CaseLock { _held: held })
}

#[cfg(test)]
mod tests {
    use std::sync::mpsc;
    use std::time::Duration;

    use super::*;

    /// The lock files' stem: `fragkit-cases` in the temporary folder, unless the variable names
    /// one (as the fleet's parallel jobs may set it).
    #[test]
    fn the_lock_files_lie_in_the_temporary_folder_unless_the_variable_moves_them() {
        let expected = match std::env::var_os(CASE_LOCK) {
            Some(named) => PathBuf::from(named),
            None => std::env::temp_dir().join("fragkit-cases"),
        };
        assert_eq!(stem(), expected);
    }

    /// Shared holders run together; a timed case waits for them, and a case that comes after it
    /// waits behind it.
    #[test]
    fn a_timed_case_runs_alone_and_cases_behind_it_wait() {
        let stem = std::env::temp_dir().join(format!("fragkit-case-lock-test-{}", std::process::id()));
        let plain = Case::passing("kit.plain");
        let timed = Case { timed_verdict: true, ..Case::passing("kit.timed") };
        let first = lock_at(&stem, &plain, |_| panic!("the first shared case waited")).unwrap();
        let second = lock_at(&stem, &plain, |_| panic!("a second shared case waited")).unwrap();

        let (told, heard) = mpsc::channel();
        let stem_of_waiter = stem.clone();
        let waiter = std::thread::spawn(move || {
            let stem = stem_of_waiter;
            let timed = Case { timed_verdict: true, ..Case::passing("kit.timed") };
            let lock = lock_at(&stem, &timed, |waiting| {
                told.send(if waiting { "waiting" } else { "running" }).unwrap();
                Ok(())
            })
            .unwrap();
            std::thread::sleep(Duration::from_millis(100));
            drop(lock);
        });
        assert_eq!(heard.recv().unwrap(), "waiting");
        std::thread::sleep(Duration::from_millis(50));
        assert!(heard.try_recv().is_err(), "the timed case ran beside two shared ones");
        drop((first, second));
        assert_eq!(heard.recv_timeout(Duration::from_secs(5)).unwrap(), "running");
        // The timed case holds the turnstile: a shared case now waits for it.
        let mut waited = false;
        let after = lock_at(&stem, &plain, |waiting| {
            waited |= waiting;
            Ok(())
        })
        .unwrap();
        assert!(waited, "a case ran beside the timed one");
        waiter.join().unwrap();
        drop(after);
        let alone = lock_at(&stem, &timed, |_| panic!("a timed case waited with nothing running")).unwrap();
        drop(alone);
        for extension in ["lock", "turnstile"] {
            std::fs::remove_file(stem.with_extension(extension)).ok();
        }
    }
}
