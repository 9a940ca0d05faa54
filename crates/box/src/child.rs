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

/// Drop to the run's user and set the limits: the last steps in the
/// child, box or not.
///
/// # Safety
/// Only async-signal-safe system calls: called between fork and exec.
pub(crate) unsafe fn drop_to_user(confinement: &Confinement) -> io::Result<()> {
    let limits = confinement.limits;
    unsafe {
        if let Some(id) = confinement.user {
            check(libc::setgroups(0, std::ptr::null()))?;
            check(libc::setgid(id))?;
            check(libc::setuid(id))?;
        }
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
