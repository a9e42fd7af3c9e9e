//! Calls into the NetCDF and HDF5 C libraries (through the `netcdf` crate)
//! that cannot end floe without its one-line message, whatever the file:
//!
//! - the `netcdf` crate unwraps some of the C library's errors (a name or
//!   attribute that a damaged file cannot give back): the panic is caught
//!   and becomes an error naming the file, and the panic message is not
//!   printed;
//! - HDF5 1.10 crashes (SIGSEGV in its global heap) or loops for ever on
//!   some damaged NetCDF-4 files (`tests/cli/fuzz.rs` finds both with a few
//!   changed bytes): while a guarded call runs, a fatal signal (SIGSEGV,
//!   SIGBUS, SIGFPE, SIGILL, SIGABRT) prints the call's message and ends
//!   the process with its exit code, and a watchdog does the same when the
//!   call has spent [`CPU_LIMIT_S`] of processor time (a healthy file's
//!   metadata or slice takes milliseconds; a wait on a slow disk spends no
//!   processor time, so is never cut short). The environment variable
//!   `FLOE_NETCDF_CPU_LIMIT_S` sets another limit (the fuzz test's cases
//!   use 2 s).
//!
//! Outside guarded calls the signals keep their previous handlers (Rust's
//! stack-overflow report, the default core dump). Guarded calls are
//! serialised (the C library is not thread-safe anyway; the `netcdf` crate
//! holds a global lock around each call) and may nest on one thread.
#![allow(unsafe_code)]

use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, Once, OnceLock};

/// Processor time a guarded call may spend before it counts as a hang, s,
/// unless `FLOE_NETCDF_CPU_LIMIT_S` gives another: far above the
/// milliseconds of a healthy call, and of a deflated slice of a 10^4 x
/// 10^4 grid (a few seconds).
pub const CPU_LIMIT_S: f64 = 60.0;

/// The limit in use, and the end of the watchdog's message (made before
/// any call is watched: nothing is allocated when it fires).
fn cpu_limit() -> &'static (f64, Vec<u8>) {
    static LIMIT: OnceLock<(f64, Vec<u8>)> = OnceLock::new();
    LIMIT.get_or_init(|| {
        let limit = std::env::var("FLOE_NETCDF_CPU_LIMIT_S")
            .ok()
            .and_then(|v| v.trim().parse::<f64>().ok())
            .filter(|s| s.is_finite() && *s > 0.0)
            .unwrap_or(CPU_LIMIT_S);
        let tail = format!(
            " did not finish reading it within {limit} s of processor time: the file is damaged\n"
        );
        (limit, tail.into_bytes())
    })
}

/// What a guarded call prints if the library crashes or hangs in it:
/// `head` (`error: <where>: <file>: the NetCDF library`), then
/// ` crashed (SIGSEGV) reading it: the file is damaged` or ` did not
/// finish ...`; and the exit code.
#[derive(Debug, Clone)]
pub struct CrashReport {
    /// The message up to the library's name.
    pub head: String,
    /// The process's exit code.
    pub exit_code: i32,
}

/// Runs `f`, a call into the `netcdf` crate. A panic in it comes back as
/// `Err` with its message; a crash or a hang prints `report` and ends the
/// process (see the module docs).
pub fn guarded<R>(report: &CrashReport, f: impl FnOnce() -> R) -> Result<R, String> {
    let _active = Active::enter(report);
    QUIET_PANICS.with(|q| q.set(q.get() + 1));
    let out = catch_unwind(AssertUnwindSafe(f));
    QUIET_PANICS.with(|q| q.set(q.get() - 1));
    out.map_err(|payload| {
        payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "a panic without a message".to_string())
    })
}

thread_local! {
    /// Guarded calls running on this thread (they nest).
    static DEPTH: Cell<usize> = const { Cell::new(0) };
    /// While above zero, panics on this thread are not printed.
    static QUIET_PANICS: Cell<usize> = const { Cell::new(0) };
}

/// One guarded call at a time across threads.
static CALLS: Mutex<()> = Mutex::new(());

/// Longest message head kept, bytes.
const HEAD_CAPACITY: usize = 2048;

/// The running call's message head and exit code, for the signal handler
/// and the watchdog. Static, not on the heap: the crash being reported may
/// be a heap overrun that wrote over the heap's contents.
static HEAD: [AtomicU8; HEAD_CAPACITY] = [const { AtomicU8::new(0) }; HEAD_CAPACITY];
static HEAD_LEN: AtomicUsize = AtomicUsize::new(0);
static EXIT_CODE: AtomicUsize = AtomicUsize::new(2);
/// Whether a guarded call is running.
static ACTIVE: AtomicBool = AtomicBool::new(false);

/// The watchdog's view of the running call: its thread's processor clock
/// and the clock's reading when it began.
#[derive(Clone, Copy)]
struct Watched {
    #[cfg(target_os = "linux")]
    clock: libc::clockid_t,
    #[cfg(target_os = "linux")]
    start_cpu_s: f64,
}

static WATCHED: Mutex<Option<Watched>> = Mutex::new(None);

/// The outermost guarded call on this thread: holds [`CALLS`] and
/// publishes its message until dropped.
struct Active {
    _calls: Option<MutexGuard<'static, ()>>,
}

impl Active {
    fn enter(report: &CrashReport) -> Active {
        install();
        let depth = DEPTH.with(|d| {
            d.set(d.get() + 1);
            d.get()
        });
        if depth > 1 {
            return Active { _calls: None };
        }
        let calls = CALLS.lock().unwrap_or_else(|p| p.into_inner());
        let head = report.head.as_bytes();
        let len = head.len().min(HEAD_CAPACITY);
        for (slot, &b) in HEAD.iter().zip(&head[..len]) {
            slot.store(b, Ordering::Relaxed);
        }
        HEAD_LEN.store(len, Ordering::SeqCst);
        EXIT_CODE.store(report.exit_code as usize, Ordering::SeqCst);
        *lock_watched() = Some(Watched {
            #[cfg(target_os = "linux")]
            clock: thread_clock(),
            #[cfg(target_os = "linux")]
            start_cpu_s: cpu_seconds(thread_clock()),
        });
        ACTIVE.store(true, Ordering::SeqCst);
        Active {
            _calls: Some(calls),
        }
    }
}

impl Drop for Active {
    fn drop(&mut self) {
        DEPTH.with(|d| d.set(d.get() - 1));
        if self._calls.is_some() {
            ACTIVE.store(false, Ordering::SeqCst);
            *lock_watched() = None;
        }
    }
}

/// Writes the running call's head, `tail` and ends the process with its
/// exit code (as a signal handler may).
fn report_and_exit(middle: &[&[u8]]) -> ! {
    let len = HEAD_LEN.load(Ordering::SeqCst).min(HEAD_CAPACITY);
    let mut chunk = [0u8; 256];
    let mut at = 0;
    while at < len {
        let n = (len - at).min(chunk.len());
        for (k, c) in chunk[..n].iter_mut().enumerate() {
            *c = HEAD[at + k].load(Ordering::Relaxed);
        }
        write_stderr(&chunk[..n]);
        at += n;
    }
    for part in middle {
        write_stderr(part);
    }
    exit_now(EXIT_CODE.load(Ordering::SeqCst) as i32)
}

fn lock_watched() -> MutexGuard<'static, Option<Watched>> {
    WATCHED.lock().unwrap_or_else(|p| p.into_inner())
}

/// The panic hook that keeps guarded panics quiet, the signal handlers and
/// the watchdog, once.
fn install() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if QUIET_PANICS.with(|q| q.get()) == 0 {
                previous(info);
            }
        }));
        #[cfg(unix)]
        install_signal_handlers();
        #[cfg(target_os = "linux")]
        {
            cpu_limit();
            let _ = std::thread::Builder::new()
                .name("netcdf-watchdog".into())
                .spawn(watchdog);
        }
    });
}

/// Writes `bytes` to standard error, as a signal handler may.
fn write_stderr(bytes: &[u8]) {
    let mut rest = bytes;
    while !rest.is_empty() {
        // SAFETY: write(2) reads `rest.len()` bytes from a valid slice; it
        // is async-signal-safe.
        let n = unsafe { libc::write(2, rest.as_ptr().cast(), rest.len()) };
        if n <= 0 {
            return;
        }
        rest = &rest[n as usize..];
    }
}

/// Ends the process at once (no exit handlers: the HDF5 library's would
/// touch the state that just failed).
fn exit_now(code: i32) -> ! {
    // SAFETY: _exit takes no pointers and is async-signal-safe.
    unsafe { libc::_exit(code) }
}

#[cfg(unix)]
const SIGNALS: [(libc::c_int, &str); 5] = [
    (libc::SIGSEGV, "SIGSEGV"),
    (libc::SIGBUS, "SIGBUS"),
    (libc::SIGFPE, "SIGFPE"),
    (libc::SIGILL, "SIGILL"),
    (libc::SIGABRT, "SIGABRT"),
];

/// The handlers the signals had before ours.
#[cfg(unix)]
static PREVIOUS: OnceLock<Vec<libc::sigaction>> = OnceLock::new();

#[cfg(unix)]
fn install_signal_handlers() {
    let mut previous = Vec::with_capacity(SIGNALS.len());
    for (signal, _) in SIGNALS {
        // SAFETY: a zeroed sigaction is a valid "default" value; sigaction
        // reads `action` and writes the old action into `old`, both valid.
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_fatal_signal as *const () as libc::sighandler_t;
            action.sa_flags = libc::SA_SIGINFO | libc::SA_ONSTACK;
            libc::sigemptyset(&mut action.sa_mask);
            let mut old: libc::sigaction = std::mem::zeroed();
            libc::sigaction(signal, &action, &mut old);
            previous.push(old);
        }
    }
    let _ = PREVIOUS.set(previous);
}

#[cfg(unix)]
extern "C" fn on_fatal_signal(
    signal: libc::c_int,
    _info: *mut libc::siginfo_t,
    _context: *mut libc::c_void,
) {
    let name = SIGNALS
        .iter()
        .find(|(s, _)| *s == signal)
        .map_or("a signal", |(_, n)| n);
    if ACTIVE.load(Ordering::SeqCst) {
        report_and_exit(&[
            b" crashed (",
            name.as_bytes(),
            b") reading it: the file is damaged\n",
        ]);
    }
    // Not a guarded call: the previous handler takes the signal, which is
    // raised again when this handler returns (a fault re-executes) or now.
    if let (Some(previous), Some(k)) = (
        PREVIOUS.get(),
        SIGNALS.iter().position(|(s, _)| *s == signal),
    ) {
        // SAFETY: restores an action sigaction gave back; raise is
        // async-signal-safe.
        unsafe {
            libc::sigaction(signal, &previous[k], std::ptr::null_mut());
            if signal == libc::SIGABRT {
                libc::raise(signal);
            }
        }
    }
}

#[cfg(target_os = "linux")]
fn thread_clock() -> libc::clockid_t {
    let mut clock: libc::clockid_t = libc::CLOCK_THREAD_CPUTIME_ID;
    // SAFETY: pthread_self is always valid; the clock id is written into a
    // valid location.
    unsafe {
        libc::pthread_getcpuclockid(libc::pthread_self(), &mut clock);
    }
    clock
}

#[cfg(target_os = "linux")]
fn cpu_seconds(clock: libc::clockid_t) -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: writes into a valid timespec.
    if unsafe { libc::clock_gettime(clock, &mut t) } != 0 {
        return 0.0;
    }
    t.tv_sec as f64 + 1e-9 * t.tv_nsec as f64
}

/// Every tenth of a second: a guarded call past the processor-time limit
/// ([`CPU_LIMIT_S`]) ends the process with its message.
#[cfg(target_os = "linux")]
fn watchdog() {
    let (limit, tail) = cpu_limit();
    loop {
        std::thread::sleep(std::time::Duration::from_millis(100));
        let watched = lock_watched();
        let Some(w) = *watched else {
            continue;
        };
        let spent = cpu_seconds(w.clock) - w.start_cpu_s;
        if spent > *limit {
            // `watched` is held: the call cannot end meanwhile.
            report_and_exit(&[tail]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panics_come_back_as_errors_and_calls_nest() {
        let report = CrashReport {
            head: "error: test".into(),
            exit_code: 2,
        };
        let inner = guarded(&report, || guarded(&report, || 7));
        assert_eq!(inner, Ok(Ok(7)));
        let e = guarded(&report, || -> u8 { panic!("Netcdf(-101)") }).unwrap_err();
        assert!(e.contains("Netcdf(-101)"), "{e}");
        assert!(!ACTIVE.load(Ordering::SeqCst));
    }
}
