//! Running one command under a [`Confinement`] (Unix).
//!
//! The program runs from an argument vector (no shell) in a folder of its
//! own, with stdin closed, stdout and stderr captured ([`crate::capture`]),
//! and only `PATH`, `HOME` (the folder) and `LANG` in its environment.
//! Where the kernel allows it ([`crate::probe`]) it runs in a box
//! ([`crate::jail`]): PID, mount, IPC, UTS and network namespaces and a
//! root holding only the system folders and what [`Share`] names (the
//! working folder as a tmpfs of its own, whose fullness the run reports,
//! [`Run::disk_full`]), so nothing it starts outlives the run. Without
//! one (`--unprotected`), in the forked child (`confine`): a process
//! group of its own, a network
//! namespace when one can be had, and Landlock and a seccomp filter
//! ([`crate::fence`]). Either way (`drop_to_user`): every descriptor
//! from 3 up that the grader inherited is close-on-exec; when
//! the grader is root, a uid of the student's own (leased,
//! [`crate::uids`]), because root ignores the process-count limit; the
//! resource limits (CPU seconds, address space, file size, processes, no
//! core files) and `PR_SET_NO_NEW_PRIVS`. Where control groups can be
//! made ([`crate::cgroup`]), the run's first process joins groups of its
//! own that bound the memory and the processes of the whole run. On the
//! wall-clock timeout, and again after the program ends, its whole
//! process group is killed (in a box, that kills the box's pid 1 and so
//! everything in it). The grader is the subreaper of everything the
//! program starts ([`become_subreaper`]), so a process that leaves the
//! group outside a box is still reparented to it, and [`reap_orphans`]
//! kills and reaps it. An interrupted grader kills every running group
//! ([`kill_running`]) before it exits.

use std::ffi::OsString;
use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::capture::{self, Captured};
use crate::cgroup::{join_group, ControlGroup};
use crate::child::{check, drop_to_user, network_namespaces};
use crate::confinement::{Confinement, Share};
use crate::reason::{reason, start_failure};
use crate::spawning::SPAWNING;

/// The process groups of the programs running now, for [`kill_running`].
static RUNNING: Mutex<Vec<libc::pid_t>> = Mutex::new(Vec::new());

/// Kill every program running now, with its group: what an interrupted
/// `grade` does before it exits.
pub fn kill_running() {
    let running = RUNNING
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    for &group in running.iter() {
        // SAFETY: `killpg` has no memory preconditions.
        unsafe { libc::killpg(group, libc::SIGKILL) };
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Ended {
    Exited(i32),
    Signalled(i32),
    /// Killed at the wall-clock timeout.
    TimedOut,
    /// The program could not be started.
    NotStarted(String),
}

/// What a run did.
#[derive(Debug)]
pub struct Run {
    pub ended: Ended,
    pub seconds: f64,
    pub stdout: Captured,
    pub stderr: Captured,
    /// The box's working folder had no byte or no inode left when the
    /// program ended ([`crate::Scratch`]).
    pub disk_full: bool,
}

impl Run {
    /// A run whose program never started, for `reason`, `start` being when
    /// the run began.
    fn not_started(reason: String, start: Instant) -> Run {
        Run {
            ended: Ended::NotStarted(reason),
            seconds: start.elapsed().as_secs_f64(),
            stdout: Captured::default(),
            stderr: Captured::default(),
            disk_full: false,
        }
    }
}

/// A pipe, both ends close-on-exec and non-blocking: the read end and
/// the write end.
fn report_pipe() -> io::Result<(OwnedFd, OwnedFd)> {
    let mut ends = [0; 2];
    // SAFETY: `pipe2` writes two descriptors into the array.
    check(unsafe { libc::pipe2(ends.as_mut_ptr(), libc::O_CLOEXEC | libc::O_NONBLOCK) })?;
    // SAFETY: two fresh descriptors no one else owns.
    Ok(unsafe { (OwnedFd::from_raw_fd(ends[0]), OwnedFd::from_raw_fd(ends[1])) })
}

/// Make this process the subreaper of its descendants, so a program's
/// orphans come back to it to be killed and reaped ([`reap_orphans`]).
pub fn become_subreaper() {
    #[cfg(target_os = "linux")]
    // SAFETY: PR_SET_CHILD_SUBREAPER takes one integer argument.
    unsafe {
        libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1);
    }
}

/// Run `argv` in `dir` under `confinement`; in a box, `share` says what
/// of the grader's file system the box holds besides the system folders.
pub fn run(argv: &[OsString], dir: &Path, share: &Share, confinement: Confinement) -> Run {
    let start = Instant::now();
    let limits = confinement.limits;
    let mut command = Command::new(&argv[0]);
    command
        .args(&argv[1..])
        .current_dir(dir)
        .env_clear()
        .env(
            "PATH",
            std::env::var_os("PATH").unwrap_or_else(|| "/usr/bin:/bin".into()),
        )
        .env("HOME", dir)
        .env(
            "LANG",
            std::env::var_os("LANG").unwrap_or_else(|| "C.UTF-8".into()),
        )
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // Without a box, no /tmp: a temporary folder of the run's own.
    let tmpdir = if confinement.boxed {
        None
    } else {
        let folder = crate::tmpdir::folder(dir);
        command.envs(crate::tmpdir::environment(&folder));
        match crate::tmpdir::path(&folder) {
            Ok(path) => Some(path),
            Err(error) => return Run::not_started(reason(&error), start),
        }
    };
    let mut plan = if confinement.boxed {
        match crate::jail::Plan::new(dir, share, &confinement) {
            Ok(plan) => Some(plan),
            Err(error) => {
                return Run::not_started(
                    format!("cannot prepare the box: {}", reason(&error)),
                    start,
                )
            }
        }
    } else {
        None
    };
    // Where the box's pid 1 says the working folder was full.
    let report = match plan.as_mut().filter(|plan| plan.has_scratch()) {
        Some(plan) => match report_pipe() {
            Ok((read, write)) => {
                plan.report_to(write.as_raw_fd());
                Some((read, write))
            }
            Err(error) => return Run::not_started(reason(&error), start),
        },
        None => None,
    };
    let fence = if confinement.boxed {
        None
    } else {
        match crate::fence::Fence::new(share, confinement.landlock, confinement.seccomp) {
            Ok(fence) => Some(fence),
            Err(error) => return Run::not_started(reason(&error), start),
        }
    };
    let group_of_run = if confinement.cgroup {
        ControlGroup::new(&limits)
    } else {
        None
    };
    let procs: Vec<std::ffi::CString> = group_of_run
        .as_ref()
        .map(ControlGroup::procs)
        .unwrap_or_default();
    // SAFETY: `getpid` has no preconditions.
    let grader = unsafe { libc::getpid() };
    // SAFETY: `confine` and `jail::enter` make only async-signal-safe
    // system calls, on data prepared before the fork.
    unsafe {
        command.pre_exec(move || {
            for path in &procs {
                join_group(path)?;
            }
            match &plan {
                Some(plan) => crate::jail::enter(plan, &confinement),
                None => confine(&confinement, fence.as_ref(), grader, tmpdir.as_ref()),
            }
        });
    }
    let spawned = {
        let _alone = SPAWNING
            .write()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        command.spawn()
    };
    let mut child = match spawned {
        Ok(child) => child,
        // The box's pid 1 could not fill the working folder's tmpfs.
        Err(error) if report.is_some() && error.raw_os_error() == Some(libc::ENOSPC) => {
            let full = format!(
                "the program's files do not fit the run's disk space ({} MiB, {} files): raise `--disk`",
                limits.disk >> 20,
                crate::scratch::INODES
            );
            return Run::not_started(full, start);
        }
        Err(error) => return Run::not_started(start_failure(&argv[0], &error), start),
    };
    let group = child.id() as libc::pid_t;
    let running = || {
        RUNNING
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    };
    running().push(group);
    let stdout = capture::spawn(child.stdout.take(), limits.output);
    let stderr = capture::spawn(child.stderr.take(), limits.output);
    let ended = loop {
        match child.try_wait() {
            Ok(Some(status)) => {
                break match (status.code(), status.signal()) {
                    (Some(code), _) => Ended::Exited(code),
                    (None, Some(signal)) => Ended::Signalled(signal),
                    (None, None) => Ended::Signalled(0),
                }
            }
            Ok(None) if start.elapsed() < limits.timeout => {
                std::thread::sleep(Duration::from_millis(5))
            }
            _ => {
                // SAFETY: `killpg` has no memory preconditions.
                unsafe { libc::killpg(group, libc::SIGKILL) };
                let _ = child.wait();
                break Ended::TimedOut;
            }
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    let disk_full = report.is_some_and(|(read, _)| {
        let mut byte = 0u8;
        // SAFETY: reading one byte into a byte.
        let got = unsafe { libc::read(read.as_raw_fd(), (&mut byte as *mut u8).cast(), 1) };
        got == 1 && byte == b'f'
    });
    kill_group(group);
    running().retain(|&g| g != group);
    drop(group_of_run);
    Run {
        ended,
        seconds,
        stdout: stdout.finish(),
        stderr: stderr.finish(),
        disk_full,
    }
}

/// In the forked child, before `exec`, without a box: a process group of
/// its own, a network namespace when one can be had, then
/// [`drop_to_user`], the run's temporary folder ([`crate::tmpdir`]), the
/// fence ([`super::fence`]), and last (a change of
/// uid forgets it) death with `grader` ([`crate::jail::die_with`]).
fn confine(
    confinement: &Confinement,
    fence: Option<&crate::fence::Fence>,
    grader: libc::pid_t,
    tmpdir: Option<&std::ffi::CString>,
) -> io::Result<()> {
    // SAFETY: plain system calls on this (single-threaded) child.
    unsafe {
        check(libc::setpgid(0, 0))?;
        if confinement.isolate_network {
            check(libc::unshare(network_namespaces(confinement.root())))?;
        }
        drop_to_user(confinement)?;
        if let Some(tmpdir) = tmpdir {
            crate::tmpdir::make(tmpdir)?;
        }
        if let Some(fence) = fence {
            fence.enter()?;
        }
        crate::child::die_with(grader)
    }
}

/// Kill every process of `group` (its leader already reaped), again until
/// none is left: a fork bomb may add members while the first signal is
/// delivered, and a killed member stays in the group until it is reaped.
fn kill_group(group: libc::pid_t) {
    for _ in 0..1000 {
        // SAFETY: `killpg` has no memory preconditions.
        if unsafe { libc::killpg(group, libc::SIGKILL) } == -1 {
            return;
        }
        reap_orphans(Some(group));
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Kill and reap the processes reparented to this one (orphans of
/// programs that ended): those of `group`, or, once no program runs, all
/// of them. A program's own leader is reaped by its `Child` before this.
/// Killing one reparents its children here, and a child may have a lower
/// pid than its parent (pids wrap around), which a pass over `/proc` in
/// order has gone by: so passes repeat until one finds no orphan.
pub fn reap_orphans(group: Option<libc::pid_t>) {
    for _ in 0..1000 {
        if reap_orphans_once(group) == 0 {
            return;
        }
    }
}

/// One pass of [`reap_orphans`] over `/proc`: how many it killed.
fn reap_orphans_once(group: Option<libc::pid_t>) -> usize {
    // SAFETY: `getpid` has no preconditions.
    let me = unsafe { libc::getpid() };
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return 0;
    };
    let mut killed = 0;
    for entry in entries.flatten() {
        let Some(pid) = entry
            .file_name()
            .to_str()
            .and_then(|n| n.parse::<i32>().ok())
        else {
            continue;
        };
        let Some((parent, process_group)) = parent_and_group(pid) else {
            continue;
        };
        if parent != me || group.is_some_and(|g| g != process_group) {
            continue;
        }
        // SAFETY: signalling and waiting for our own child.
        unsafe {
            libc::kill(pid, libc::SIGKILL);
            libc::waitpid(pid, std::ptr::null_mut(), 0);
        }
        killed += 1;
    }
    killed
}

/// The parent and process group of `pid`, from `/proc/PID/stat`.
fn parent_and_group(pid: i32) -> Option<(i32, i32)> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name may hold spaces and parentheses: fields follow the last `)`.
    let rest = &stat[stat.rfind(')')? + 2..];
    let mut fields = rest.split(' ').skip(1);
    let parent = fields.next()?.parse().ok()?;
    let group = fields.next()?.parse().ok()?;
    Some((parent, group))
}
