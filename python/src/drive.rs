//! A run on a thread of its own while the interpreter's thread waits without the GIL, reports
//! progress and answers Ctrl-C.

use pseudorigid::population::RunControl;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// Run `work` on a thread of its own while this (the interpreter's) thread waits without the
/// GIL; every `POLL` it calls `progress(done, total)` when the count moved and checks for
/// signals (Ctrl-C). A raised exception asks the run to stop after the particles in flight
/// (their records are checkpointed) and is re-raised once the run has stopped.
pub(crate) fn drive<T: Send>(
    py: Python<'_>,
    control: &RunControl,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    const POLL: Duration = Duration::from_millis(100);
    let finished = (Mutex::new(false), Condvar::new());
    std::thread::scope(|s| {
        let handle = s.spawn(|| {
            // Set the flag even if `work` panics, so the waiting thread wakes up.
            struct Done<'a>(&'a (Mutex<bool>, Condvar));
            impl Drop for Done<'_> {
                fn drop(&mut self) {
                    if let Ok(mut done) = self.0.0.lock() {
                        *done = true;
                    }
                    self.0.1.notify_all();
                }
            }
            let _done = Done(&finished);
            work()
        });
        let mut failure: Option<PyErr> = None;
        let mut last = None;
        let mut report = |failure: &mut Option<PyErr>| {
            let now = control.progress();
            if let Some(cb) = progress
                && failure.is_none()
                && last != Some(now)
            {
                last = Some(now);
                if let Err(e) = cb.call1(now) {
                    control.stop();
                    *failure = Some(e);
                }
            }
        };
        loop {
            let done = py.detach(|| {
                let (lock, cvar) = &finished;
                let guard = lock.lock().unwrap_or_else(|p| p.into_inner());
                let (guard, _) = cvar
                    .wait_timeout_while(guard, POLL, |done| !*done)
                    .unwrap_or_else(|p| p.into_inner());
                *guard
            });
            if done {
                break;
            }
            report(&mut failure);
            if failure.is_none()
                && let Err(e) = py.check_signals()
            {
                control.stop();
                failure = Some(e);
            }
        }
        let joined = py.detach(|| handle.join());
        match (failure, joined) {
            (Some(e), _) => Err(e),
            (None, Ok(value)) => {
                let mut failure = None;
                report(&mut failure);
                failure.map_or(Ok(value), Err)
            }
            (None, Err(_)) => Err(PyRuntimeError::new_err(
                "pseudorigid: the run panicked (a bug; please report it)",
            )),
        }
    })
}
