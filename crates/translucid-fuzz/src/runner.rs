//! The parent side of a case: runs the child on a file under a wall-clock timeout and an
//! address-space cap, and turns its exit status and stderr into an outcome.

use crate::child::{EXIT_CAUGHT_PANIC, EXIT_ERROR, EXIT_OK, EXIT_WRONG_FRAME};
use std::io::Read;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug)]
pub struct Limits {
    pub timeout: Duration,
    /// RLIMIT_AS of the child, in bytes.
    pub memory: u64,
    /// Whether the child renders what loads with every method and checks the frames.
    pub render: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Kind {
    /// An uncaught panic (exit code 101).
    Panic,
    /// A panic the library caught and turned into an error.
    CaughtPanic,
    /// A signal or an unexpected exit code.
    Crash,
    Timeout,
    /// An allocation failed under the cap, or the kernel killed the child.
    Memory,
    /// A frame with a NaN or infinite pixel, or exact's off the reference.
    WrongFrame,
}

impl Kind {
    pub const ALL: [Kind; 6] = [
        Kind::Panic,
        Kind::CaughtPanic,
        Kind::Crash,
        Kind::Timeout,
        Kind::Memory,
        Kind::WrongFrame,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Kind::Panic => "panic",
            Kind::CaughtPanic => "caught-panic",
            Kind::Crash => "crash",
            Kind::Timeout => "timeout",
            Kind::Memory => "memory",
            Kind::WrongFrame => "wrong-frame",
        }
    }
}

#[derive(Clone, Debug)]
pub struct Finding {
    pub kind: Kind,
    /// How the child ended: "exit code 101", "signal 11 (SIGSEGV)", "killed at the 10 s
    /// timeout".
    pub status: String,
    pub stderr: String,
    pub seconds: f64,
}

#[derive(Clone, Debug)]
pub enum Outcome {
    Loaded,
    CleanError,
    Finding(Finding),
}

/// Stderr kept from a child: its head holds a panic's message, its tail the end of a
/// backtrace; a child printing megabytes cannot make the parent hold them.
const STDERR_HEAD: usize = 12 << 10;
const STDERR_TAIL: usize = 4 << 10;

pub fn run(exe: &Path, file: &Path, limits: Limits) -> std::io::Result<Outcome> {
    let mut command = Command::new(exe);
    command
        .arg("run-one")
        .arg(file)
        .args(limits.render.then_some("--render"))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .env("RUST_BACKTRACE", "1");
    let memory = limits.memory;
    // SAFETY: the hook runs in the forked child before exec, where only async-signal-safe
    // calls are allowed: it calls setrlimit(2), a plain system call, on stack values, and
    // neither allocates nor takes locks.
    unsafe {
        command.pre_exec(move || {
            let cap = libc::rlimit {
                rlim_cur: memory,
                rlim_max: memory,
            };
            if libc::setrlimit(libc::RLIMIT_AS, &cap) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            // A crash is a finding, not a core file.
            let none = libc::rlimit {
                rlim_cur: 0,
                rlim_max: 0,
            };
            libc::setrlimit(libc::RLIMIT_CORE, &none);
            Ok(())
        });
    }
    let start = Instant::now();
    let mut child = command.spawn()?;
    let mut pipe = child.stderr.take();
    let reader = std::thread::spawn(move || {
        let mut head = Vec::new();
        let mut tail = Vec::new();
        let mut buf = [0u8; 8192];
        while let Some(n) = pipe.as_mut().and_then(|p| p.read(&mut buf).ok()) {
            if n == 0 {
                break;
            }
            let room = STDERR_HEAD.saturating_sub(head.len()).min(n);
            head.extend_from_slice(&buf[..room]);
            tail.extend_from_slice(&buf[room..n]);
            if tail.len() > 2 * STDERR_TAIL {
                tail.drain(..tail.len() - STDERR_TAIL);
            }
        }
        let cut = tail.len().saturating_sub(STDERR_TAIL);
        let mut text = String::from_utf8_lossy(&head).into_owned();
        if cut > 0 {
            text.push_str("\n[...]\n");
        }
        text.push_str(&String::from_utf8_lossy(&tail[cut..]));
        text
    });
    // Polling keeps this simple and costs nothing next to a process start.
    let mut nap = Duration::from_millis(1);
    let (status, timed_out) = loop {
        if let Some(status) = child.try_wait()? {
            break (status, false);
        }
        if start.elapsed() >= limits.timeout {
            // SIGKILL: a hung child must not get to ignore it.
            let _ = child.kill();
            break (child.wait()?, true);
        }
        std::thread::sleep(nap);
        nap = (nap * 2).min(Duration::from_millis(20));
    };
    let seconds = start.elapsed().as_secs_f64();
    let stderr = reader.join().unwrap_or_default();
    Ok(classify(status, timed_out, stderr, seconds, limits))
}

fn classify(
    status: std::process::ExitStatus,
    timed_out: bool,
    stderr: String,
    seconds: f64,
    limits: Limits,
) -> Outcome {
    let finding = |kind, status: String| {
        Outcome::Finding(Finding {
            kind,
            status,
            stderr: stderr.clone(),
            seconds,
        })
    };
    if timed_out {
        return finding(
            Kind::Timeout,
            format!("killed at the {} s timeout", limits.timeout.as_secs_f64()),
        );
    }
    let out_of_memory =
        stderr.contains("memory allocation of") || stderr.contains("fuzz: allocation of");
    match (status.code(), status.signal()) {
        (Some(c), _) if c == i32::from(EXIT_OK) => Outcome::Loaded,
        (Some(c), _) if c == i32::from(EXIT_ERROR) => Outcome::CleanError,
        (Some(c), _) if c == i32::from(EXIT_CAUGHT_PANIC) => finding(
            Kind::CaughtPanic,
            format!("exit code {c} (panic caught by load)"),
        ),
        (Some(c), _) if c == i32::from(EXIT_WRONG_FRAME) => {
            finding(Kind::WrongFrame, format!("exit code {c} (wrong frame)"))
        }
        (Some(101), _) => finding(Kind::Panic, "exit code 101 (panic)".into()),
        (Some(c), _) => finding(Kind::Crash, format!("exit code {c}")),
        (None, Some(signal)) => {
            let name = signal_name(signal);
            let status = format!("signal {signal} ({name})");
            if out_of_memory || signal == libc::SIGKILL {
                // SIGKILL we did not send: the kernel's OOM killer.
                finding(Kind::Memory, status)
            } else {
                finding(Kind::Crash, status)
            }
        }
        (None, None) => finding(Kind::Crash, "no exit status".into()),
    }
}

fn signal_name(signal: i32) -> &'static str {
    match signal {
        libc::SIGABRT => "SIGABRT",
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGBUS => "SIGBUS",
        libc::SIGILL => "SIGILL",
        libc::SIGFPE => "SIGFPE",
        libc::SIGKILL => "SIGKILL",
        libc::SIGTRAP => "SIGTRAP",
        libc::SIGSYS => "SIGSYS",
        libc::SIGPIPE => "SIGPIPE",
        _ => "other",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::process::ExitStatus;

    const LIMITS: Limits = Limits {
        timeout: Duration::from_secs(10),
        memory: 1 << 32,
        render: false,
    };

    fn kind_of(status: ExitStatus, timed_out: bool, stderr: &str) -> Option<Kind> {
        match classify(status, timed_out, stderr.into(), 0.1, LIMITS) {
            Outcome::Finding(f) => Some(f.kind),
            _ => None,
        }
    }

    /// A wait status as the kernel reports it: exit code in the second byte, or the signal.
    fn exited(code: i32) -> ExitStatus {
        ExitStatus::from_raw(code << 8)
    }

    #[test]
    fn exit_statuses_are_classified() {
        assert!(matches!(
            classify(exited(0), false, String::new(), 0.1, LIMITS),
            Outcome::Loaded
        ));
        assert!(matches!(
            classify(exited(2), false, String::new(), 0.1, LIMITS),
            Outcome::CleanError
        ));
        assert_eq!(kind_of(exited(3), false, ""), Some(Kind::CaughtPanic));
        assert_eq!(kind_of(exited(4), false, ""), Some(Kind::WrongFrame));
        assert_eq!(kind_of(exited(101), false, ""), Some(Kind::Panic));
        assert_eq!(kind_of(exited(1), false, ""), Some(Kind::Crash));
        assert_eq!(
            kind_of(ExitStatus::from_raw(libc::SIGSEGV), false, ""),
            Some(Kind::Crash)
        );
        assert_eq!(
            kind_of(
                ExitStatus::from_raw(libc::SIGABRT),
                false,
                "memory allocation of 8589934592 bytes failed"
            ),
            Some(Kind::Memory)
        );
        assert_eq!(
            kind_of(ExitStatus::from_raw(libc::SIGKILL), false, ""),
            Some(Kind::Memory)
        );
        assert_eq!(
            kind_of(ExitStatus::from_raw(libc::SIGKILL), true, ""),
            Some(Kind::Timeout)
        );
    }
}
