//! The steps taken in a forked child between fork and exec, box or not,
//! and the probe that tries such steps once on `sh -c :`. Only
//! async-signal-safe system calls, on data prepared before the fork.

use std::io;
use std::os::unix::process::CommandExt;
use std::process::{Command, Stdio};

use crate::confinement::Confinement;

/// A failed system call's error.
pub(crate) fn check(result: libc::c_int) -> io::Result<()> {
    if result == -1 {
        Err(io::Error::last_os_error())
    } else {
        Ok(())
    }
}

/// Whether `sh -c :` runs and exits 0 with `setup` done in the child
/// before exec: how a confinement is tried once before any student runs
/// under it.
///
/// # Safety
///
/// `setup` runs between fork and exec, so it may make only
/// async-signal-safe calls.
pub unsafe fn sh_runs_after(setup: impl FnMut() -> io::Result<()> + Send + Sync + 'static) -> bool {
    let mut probe = Command::new("sh");
    probe
        .args(["-c", ":"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    // SAFETY: the caller promises `setup` is async-signal-safe.
    unsafe {
        probe.pre_exec(setup);
    }
    probe.status().is_ok_and(|s| s.success())
}

/// Join a new, empty session keyring, the run's own: without it a
/// program inherits the grader's session keyring, where one run could
/// leave a key for the next to read. Where the kernel or a seccomp filter
/// refuses the keyring calls (Docker's default profile does), no program
/// can reach a keyring either, and nothing is needed.
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
unsafe fn fresh_session_keyring() -> io::Result<()> {
    const KEYCTL_JOIN_SESSION_KEYRING: libc::c_long = 1;
    // SAFETY: a plain system call; a null name asks for an anonymous keyring.
    let joined = unsafe {
        libc::syscall(
            libc::SYS_keyctl,
            KEYCTL_JOIN_SESSION_KEYRING,
            std::ptr::null::<libc::c_char>(),
        )
    };
    if joined == -1 {
        let error = io::Error::last_os_error();
        if !matches!(
            error.raw_os_error(),
            Some(libc::EPERM | libc::ENOSYS | libc::EACCES)
        ) {
            return Err(error);
        }
    }
    Ok(())
}

/// Mark every inherited descriptor from 3 up close-on-exec, drop to the
/// run's user (in a session keyring of the run's own) and set the limits: the last steps in the child, box or
/// not.
///
/// # Safety
/// Only async-signal-safe system calls: called between fork and exec.
pub(crate) unsafe fn drop_to_user(confinement: &Confinement) -> io::Result<()> {
    let limits = confinement.limits;
    unsafe {
        close_on_exec_from(3);
        if let Some(id) = confinement.user {
            // The system calls, not glibc's wrappers, which would have
            // every thread glibc believes this process has change its
            // credentials too: the box's program runs here in memory it
            // shares with its parent (`sharing.rs`), whose threads are not
            // its own.
            let set = |call: libc::c_long, a: libc::c_long, b: libc::c_long| {
                check(libc::syscall(call, a, b) as libc::c_int)
            };
            set(libc::SYS_setgroups, 0, 0)?;
            set(libc::SYS_setgid, libc::c_long::from(id), 0)?;
            set(libc::SYS_setuid, libc::c_long::from(id), 0)?;
        }
        fresh_session_keyring()?;
        let limit = |resource, value: u64| {
            let rlimit = libc::rlimit {
                rlim_cur: value as libc::rlim_t,
                rlim_max: value as libc::rlim_t,
            };
            check(libc::setrlimit(resource, &rlimit))
        };
        // The soft CPU limit sends SIGXCPU; the hard one a second later, SIGKILL.
        check(libc::setrlimit(
            libc::RLIMIT_CPU,
            &libc::rlimit {
                rlim_cur: limits.cpu_seconds as libc::rlim_t,
                rlim_max: (limits.cpu_seconds + 1) as libc::rlim_t,
            },
        ))?;
        limit(libc::RLIMIT_AS, limits.address_space)?;
        limit(libc::RLIMIT_FSIZE, limits.file_size)?;
        limit(libc::RLIMIT_NPROC, limits.processes)?;
        limit(libc::RLIMIT_CORE, 0)?;
        check(libc::prctl(libc::PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0))?;
    }
    Ok(())
}

/// Mark every descriptor from `first` up close-on-exec: whatever the
/// process that started `grade` left open without the flag (a root-only
/// file, a log) must not reach the program. Marked rather than closed, so
/// std's own pipe that reports a failed `exec` stays open until then.
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
pub(crate) unsafe fn close_on_exec_from(first: libc::c_int) {
    unsafe {
        let marked = libc::syscall(
            libc::SYS_close_range,
            first as libc::c_uint,
            libc::c_uint::MAX,
            libc::CLOSE_RANGE_CLOEXEC,
        );
        if marked == 0 {
            return;
        }
        // A kernel before 5.11: mark each descriptor below the limit.
        let mut limit: libc::rlimit = std::mem::zeroed();
        let highest = if libc::getrlimit(libc::RLIMIT_NOFILE, &mut limit) == 0 {
            limit.rlim_cur.min(1 << 20) as libc::c_int
        } else {
            1 << 16
        };
        for fd in first..highest {
            libc::fcntl(fd, libc::F_SETFD, libc::FD_CLOEXEC);
        }
    }
}

/// The namespaces to unshare: the network's, inside a user namespace of
/// its own unless the caller is root.
pub(crate) fn network_namespaces(root: bool) -> libc::c_int {
    if root {
        libc::CLONE_NEWNET
    } else {
        libc::CLONE_NEWUSER | libc::CLONE_NEWNET
    }
}

/// Be killed when the thread that forked this process ends (the grader's
/// thread waiting for the run, and so the grader, killed or not), and
/// refuse to start if `grader` is no longer this process's parent: it
/// died before the request was made.
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
pub(crate) unsafe fn die_with(grader: libc::pid_t) -> io::Result<()> {
    unsafe {
        check(libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL, 0, 0, 0))?;
        if libc::getppid() != grader {
            return Err(io::Error::from_raw_os_error(libc::ESRCH));
        }
    }
    Ok(())
}
