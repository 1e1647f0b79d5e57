//! Runs a cook off the Python thread with the GIL released, and turns Ctrl-C (KeyboardInterrupt) into the cook's cancellation.

use std::sync::mpsc::{channel, RecvTimeoutError};
use std::time::Duration;

use geode_op::CancelToken;
use pyo3::exceptions::PyRuntimeError;
use pyo3::panic::PanicException;
use pyo3::prelude::*;

/// How often a waiting cook looks for Python's signals: a Ctrl-C is seen
/// within this, and the cook then stops at its next cancellation check.
const SIGNAL_POLL: Duration = Duration::from_millis(40);

/// Runs `work` on a thread of its own while this one waits without the
/// GIL (other Python threads run, and cook too). Every `SIGNAL_POLL` the
/// waiting thread takes the GIL back to run Python's signal handlers; when
/// one raises (KeyboardInterrupt), the cook is cancelled, waited for, and
/// the exception returned.
pub fn run_interruptibly<R: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce(CancelToken) -> R + Send + 'static,
) -> PyResult<R> {
    let cancel = CancelToken::new();
    let (tx, rx) = channel();
    // Waited on without the GIL, from this thread only.
    let rx = std::sync::Mutex::new(rx);
    let wait = |d: Option<Duration>| {
        let rx = rx.lock().unwrap_or_else(|p| p.into_inner());
        match d {
            Some(d) => rx.recv_timeout(d),
            None => rx.recv().map_err(|_| RecvTimeoutError::Disconnected),
        }
    };
    let token = cancel.clone();
    std::thread::Builder::new()
        .name("geode-cook".into())
        .spawn(move || {
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(token)));
            let _ = tx.send(r);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start a cook thread: {e}")))?;
    loop {
        match py.detach(|| wait(Some(SIGNAL_POLL))) {
            Ok(Ok(r)) => return Ok(r),
            Ok(Err(panic)) => return Err(panic_error(panic)),
            Err(RecvTimeoutError::Timeout) => {
                if let Err(interrupt) = py.check_signals() {
                    cancel.cancel();
                    // Nothing the cook was making outlives the exception.
                    let _ = py.detach(|| wait(None));
                    return Err(interrupt);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "the cook thread ended without a result",
                ))
            }
        }
    }
}

fn panic_error(panic: Box<dyn std::any::Any + Send>) -> PyErr {
    let text = panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a cook panicked".into());
    PanicException::new_err(format!("geode bug, please report: {text}"))
}
