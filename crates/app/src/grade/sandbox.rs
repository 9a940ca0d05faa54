//! Running one student command under limits (Unix).
//!
//! The program runs from an argument vector (no shell) in a folder of its
//! own, with stdin closed, stdout and stderr captured ([`super::capture`]),
//! and only `PATH`, `HOME` (the folder) and `LANG` in its environment.
//! Where the kernel allows it (probed once, [`super::jail::available`]) it
//! runs in a box ([`super::jail`]): PID, mount, IPC, UTS and network
//! namespaces and a root holding only the system folders and what
//! [`Share`] names, so nothing it starts outlives the run. Without one
//! (`--unprotected`), in the forked child ([`confine`]): a process group
//! of its own, a network namespace when one can be had, and Landlock and
//! a seccomp filter ([`super::fence`]). Either way
//! ([`drop_to_user`]): when the grader is root, a uid of the
//! student's own (leased, [`super::uids`]; [`Confinement::with_user`]),
//! because root ignores the process-count limit; the resource limits (CPU
//! seconds, address space, file size, processes, no core files) and
//! `PR_SET_NO_NEW_PRIVS`. Where control groups can be made
//! ([`ControlGroup`]: as root, or in a box under a group delegated to the
//! grader), the run's first process joins groups of its own that bound
//! the memory and the processes of the whole run. On the wall-clock
//! timeout, and again after the program ends, its whole process group is
//! killed (in a box, that kills the box's pid 1 and so everything in
//! it). `grade` is the subreaper of everything the program starts, so a
//! process that leaves the group outside a box is still reparented to
//! `grade`, and [`reap_orphans`] kills and reaps it. An interrupted `grade` kills every running group
//! ([`kill_running`]) before it exits.

use std::ffi::OsString;
use std::io;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use super::capture::{self, Captured};

/// The limits one run is held to.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    pub timeout: Duration,
    pub cpu_seconds: u64,
    pub address_space: u64,
    pub file_size: u64,
    pub processes: u64,
    /// Bytes of stdout, and of stderr, kept.
    pub output: usize,
}

/// Held for writing while a program is started, and for reading while
/// the grader has a file open for writing that a program may run (a
/// student's copied program): a fork made then would inherit the open
/// descriptor, and a program run from that file meanwhile would fail with
/// `text file busy` (`ETXTBSY`) until the fork's child execs.
pub static SPAWNING: std::sync::RwLock<()> = std::sync::RwLock::new(());

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

/// The uid and gid a root grader runs programs as.
pub const NOBODY: u32 = 65_534;

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
        }
    }
}

/// How the child is confined, decided once per grading.
#[derive(Clone, Copy, Debug)]
pub struct Confinement {
    pub limits: Limits,
    /// Unshare the network namespace (the kernel allows it).
    pub isolate_network: bool,
    /// Switch to this uid and gid (the grader is root).
    pub user: Option<u32>,
    /// Run in a box ([`super::jail`]): PID, mount, IPC, UTS and network
    /// namespaces and a root of our making; inside a user namespace of
    /// its own when the grader is not root.
    pub boxed: bool,
    /// Hold each run in control groups of its own (cgroup v1 `memory` and
    /// `pids`; as root, or in a box under a delegated group,
    /// [`ControlGroup`]): `--memory` for the whole run, `--max-processes`
    /// for the run's processes alone.
    pub cgroup: bool,
    /// Without a box: Landlock ([`super::fence`]) where the kernel has it.
    pub landlock: bool,
    /// Without a box: the seccomp filter ([`super::fence`]).
    pub seccomp: bool,
}

impl Confinement {
    /// The confinement for this process: a box when one can be had, else
    /// a network namespace when one can be had; `nobody` when root until
    /// [`Confinement::with_user`] gives each student its own uid.
    pub fn new(limits: Limits) -> Confinement {
        // SAFETY: `geteuid` has no preconditions.
        let root = unsafe { libc::geteuid() } == 0;
        let boxed = super::jail::available(root);
        let (landlock, seccomp) = if boxed {
            (false, false)
        } else {
            super::fence::available()
        };
        Confinement {
            limits,
            isolate_network: boxed || network_isolation(root),
            user: root.then_some(NOBODY),
            boxed,
            cgroup: (root || boxed) && ControlGroup::available(),
            landlock,
            seccomp,
        }
    }

    /// The confinement of one tracer graded: the uid of `lease` (root's
    /// grader leases one per student, [`super::uids::Lease`]).
    pub fn with_user(self, lease: Option<&super::uids::Lease>) -> Confinement {
        Confinement {
            user: lease.map(super::uids::Lease::uid).or(self.user),
            ..self
        }
    }

    /// The names of the mechanisms that confine each run.
    pub fn mechanisms(&self) -> Vec<String> {
        let mut names = Vec::new();
        if self.boxed {
            names.extend(["pid_namespace", "mount_namespace", "ipc_namespace"]);
            if !self.root() {
                names.push("user_namespace");
            }
        }
        if self.isolate_network {
            names.push("network_namespace");
        }
        if self.root() {
            names.push("uid");
        }
        if self.cgroup {
            names.push("cgroup");
        }
        if self.landlock {
            names.push("landlock");
        }
        if self.seccomp {
            names.push("seccomp");
        }
        names.extend(["rlimits", "no_new_privs"]);
        names.into_iter().map(String::from).collect()
    }

    /// Whether the grader runs as root (and so switches uids).
    pub fn root(&self) -> bool {
        self.user.is_some()
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
    let plan = if confinement.boxed {
        match super::jail::Plan::new(dir, share, &confinement) {
            Ok(plan) => Some(plan),
            Err(error) => {
                return Run::not_started(
                    format!(
                        "cannot prepare the box: {}",
                        raytracer_scene::diagnostic::io_reason(&error)
                    ),
                    start,
                )
            }
        }
    } else {
        None
    };
    let fence = if confinement.boxed {
        None
    } else {
        match super::fence::Fence::new(share, confinement.landlock, confinement.seccomp) {
            Ok(fence) => Some(fence),
            Err(error) => {
                return Run::not_started(raytracer_scene::diagnostic::io_reason(&error), start)
            }
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
                Some(plan) => super::jail::enter(plan, &confinement),
                None => confine(&confinement, fence.as_ref(), grader),
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
        Err(error) => {
            return Run::not_started(super::workdir::start_failure(&argv[0], &error), start)
        }
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
    kill_group(group);
    running().retain(|&g| g != group);
    drop(group_of_run);
    Run {
        ended,
        seconds,
        stdout: stdout.finish(),
        stderr: stderr.finish(),
    }
}

/// What of the grader's file system a box holds: folders bound
/// read-write (the run's working folder) and files bound read-only (a
/// `--tracer` program named by its path), each at its own path.
#[derive(Clone, Debug, Default)]
pub struct Share {
    pub read_write: Vec<std::path::PathBuf>,
    pub read_only: Vec<std::path::PathBuf>,
}

/// Drop to the run's user and set the limits: the last steps in the
/// child, box or not.
///
/// # Safety
/// Only async-signal-safe system calls: called between fork and exec.
pub(super) unsafe fn drop_to_user(confinement: &Confinement) -> io::Result<()> {
    let check = |result: libc::c_int| {
        if result == -1 {
            Err(io::Error::last_os_error())
        } else {
            Ok(())
        }
    };
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

/// In the forked child, before `exec`, without a box: a process group of
/// its own, a network namespace when one can be had, then
/// [`drop_to_user`], the fence ([`super::fence`]), and last (a change of
/// uid forgets it) death with `grader` ([`super::jail::die_with`]).
fn confine(
    confinement: &Confinement,
    fence: Option<&super::fence::Fence>,
    grader: libc::pid_t,
) -> io::Result<()> {
    let check = |result: libc::c_int| {
        if result == -1 {
            Err(io::Error::last_os_error())
        } else {
            Ok(())
        }
    };
    // SAFETY: plain system calls on this (single-threaded) child.
    unsafe {
        check(libc::setpgid(0, 0))?;
        if confinement.isolate_network {
            check(libc::unshare(namespaces(confinement.root())))?;
        }
        drop_to_user(confinement)?;
        if let Some(fence) = fence {
            fence.enter()?;
        }
        super::jail::die_with(grader)
    }
}

/// The namespaces to unshare: the network's, inside a user namespace of
/// its own unless the caller is root.
fn namespaces(root: bool) -> libc::c_int {
    if root {
        libc::CLONE_NEWNET
    } else {
        libc::CLONE_NEWUSER | libc::CLONE_NEWNET
    }
}

/// Whether a child can be given a network namespace of its own: start one
/// (this program, printing its version) that unshares it.
fn network_isolation(root: bool) -> bool {
    let Ok(exe) = std::env::current_exe() else {
        return false;
    };
    let mut probe = Command::new(exe);
    probe
        .arg("--version")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    let flags = namespaces(root);
    // SAFETY: `unshare` is a plain system call.
    unsafe {
        probe.pre_exec(move || {
            if libc::unshare(flags) == -1 {
                Err(io::Error::last_os_error())
            } else {
                Ok(())
            }
        });
    }
    probe.status().is_ok_and(|s| s.success())
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
pub fn reap_orphans(group: Option<libc::pid_t>) {
    // SAFETY: `getpid` has no preconditions.
    let me = unsafe { libc::getpid() };
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return;
    };
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
    }
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

/// The cgroup v1 hierarchies a run is held in, and the file of each that
/// takes its limit.
const CONTROLLERS: [(&str, &str); 2] = [("memory", "memory.limit_in_bytes"), ("pids", "pids.max")];

/// A run's control groups (cgroup v1 `memory` and `pids`), removed when
/// dropped, once the run's processes are gone. A root grader makes them
/// at the top of each hierarchy. An ordinary user's grader makes them in
/// its own group of each hierarchy (`/proc/self/cgroup`) when that group
/// is delegated to it (its folder writable by the grader's uid): then the
/// run's groups are the grader's uid's, which is also the program's, so
/// they are used only in a box, which holds no `/sys` and lets no user
/// namespace be made in it to mount one ([`super::jail`]).
pub struct ControlGroup {
    folders: Vec<std::path::PathBuf>,
}

impl ControlGroup {
    /// Whether this grader can make control groups: cgroup v1's `memory`
    /// and `pids` hierarchies mounted, and writable where
    /// [`ControlGroup::parent`] says.
    fn available() -> bool {
        let limits = Limits {
            timeout: Duration::from_secs(1),
            cpu_seconds: 1,
            address_space: 1 << 30,
            file_size: 1 << 20,
            processes: 8,
            output: 0,
        };
        for (controller, _) in CONTROLLERS {
            if let Some(parent) = ControlGroup::parent(controller) {
                ControlGroup::sweep(&parent);
            }
        }
        ControlGroup::new(&limits).is_some()
    }

    /// Remove the groups in `parent` that graders which died left (one
    /// killed with SIGKILL removes nothing): named for a pid no process
    /// has, unchanged for a minute (so never one a grader of another PID
    /// namespace is making), and empty (the kernel removes no group that
    /// holds a process or a group).
    fn sweep(parent: &Path) {
        let Ok(entries) = std::fs::read_dir(parent) else {
            return;
        };
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(pid) = name
                .to_str()
                .and_then(|n| n.strip_prefix("raytracer-grade-"))
                .and_then(|rest| rest.split('-').next())
                .and_then(|pid| pid.parse::<libc::pid_t>().ok())
            else {
                continue;
            };
            // SAFETY: `kill` with signal 0 sends nothing.
            let dead = unsafe { libc::kill(pid, 0) } == -1
                && io::Error::last_os_error().raw_os_error() == Some(libc::ESRCH);
            let old = entry
                .metadata()
                .and_then(|m| m.modified())
                .is_ok_and(|t| t.elapsed().is_ok_and(|age| age > Duration::from_secs(60)));
            if dead && old {
                let _ = std::fs::remove_dir(entry.path());
            }
        }
    }

    /// A run's groups with `limits`' memory and processes, or `None`.
    fn new(limits: &Limits) -> Option<ControlGroup> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static RUNS: AtomicU64 = AtomicU64::new(0);
        let name = format!(
            "raytracer-grade-{}-{}",
            std::process::id(),
            RUNS.fetch_add(1, Ordering::Relaxed)
        );
        let mut group = ControlGroup {
            folders: Vec::new(),
        };
        for (controller, file) in CONTROLLERS {
            let folder = ControlGroup::parent(controller)?.join(&name);
            std::fs::create_dir(&folder).ok()?;
            group.folders.push(folder.clone());
            let value = match controller {
                "memory" => limits.address_space,
                _ => limits.processes,
            };
            std::fs::write(folder.join(file), value.to_string()).ok()?;
        }
        Some(group)
    }

    /// The folder a run's group of `controller`'s hierarchy is made in:
    /// the hierarchy's root as root, else this process's own group.
    fn parent(controller: &str) -> Option<std::path::PathBuf> {
        let hierarchy = Path::new("/sys/fs/cgroup").join(controller);
        // SAFETY: `geteuid` has no preconditions.
        if unsafe { libc::geteuid() } == 0 {
            return Some(hierarchy);
        }
        let groups = std::fs::read_to_string("/proc/self/cgroup").ok()?;
        groups.lines().find_map(|line| {
            let mut fields = line.splitn(3, ':');
            let (_, controllers, path) = (fields.next()?, fields.next()?, fields.next()?);
            controllers
                .split(',')
                .any(|c| c == controller)
                .then(|| hierarchy.join(path.trim_start_matches('/')))
        })
    }

    /// The `cgroup.procs` file of each group.
    fn procs(&self) -> Vec<std::ffi::CString> {
        use std::os::unix::ffi::OsStrExt;
        self.folders
            .iter()
            .filter_map(|f| {
                std::ffi::CString::new(f.join("cgroup.procs").as_os_str().as_bytes()).ok()
            })
            .collect()
    }
}

impl Drop for ControlGroup {
    fn drop(&mut self) {
        for folder in &self.folders {
            // A killed process leaves its group a moment after it is reaped.
            for _ in 0..200 {
                if std::fs::remove_dir(folder).is_ok() || !folder.exists() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(5));
            }
        }
    }
}

/// Move this process into the group whose `cgroup.procs` is `path`.
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
fn join_group(path: &std::ffi::CStr) -> io::Result<()> {
    // SAFETY: a NUL-terminated path; plain system calls.
    unsafe {
        let fd = libc::open(path.as_ptr(), libc::O_WRONLY | libc::O_CLOEXEC);
        if fd == -1 {
            return Err(io::Error::last_os_error());
        }
        let written = libc::write(fd, b"0".as_ptr().cast(), 1);
        libc::close(fd);
        if written != 1 {
            return Err(io::Error::last_os_error());
        }
    }
    Ok(())
}
