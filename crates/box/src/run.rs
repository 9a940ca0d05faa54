//! Running one command under a [`Confinement`] (Unix).
//!
//! The program runs from an argument vector (no shell) in a folder of its
//! own, with stdin closed, stdout and stderr captured ([`crate::capture`]),
//! and only `PATH`, `HOME` (the folder, or [`Share::home`]) and `LANG` in
//! its environment.
//! Where the kernel allows it ([`crate::probe`]) it runs in a box
//! ([`crate::jail`]): PID, mount, IPC, UTS and network namespaces and a
//! root holding only the system folders and what [`Share`] names (the
//! working folder as a tmpfs of its own, whose fullness the run reports,
//! [`Run::disk_full`]), so nothing it starts outlives the run. Without
//! one (`--unprotected`), in the forked child (`confine`): a process
//! group of its own, a network namespace when one can be had, and
//! Landlock and a seccomp filter ([`crate::fence`]). Either way
//! (`drop_to_user`): every descriptor from 3 up that the grader
//! inherited is close-on-exec; when the grader is root, a uid of the
//! student's own (leased, [`crate::uids`]), because root ignores the
//! process-count limit; the resource limits (CPU seconds, address space,
//! file size, processes, no core files) and `PR_SET_NO_NEW_PRIVS`. Where
//! control groups can be made ([`crate::cgroup`]), the run's first
//! process joins groups of its own that bound the memory and the
//! processes of the whole run. The folders it writes that no tmpfs
//! bounds (a build's; without a box, all of them) are held to the same
//! bytes and files by walks while it runs ([`crate::quota`]), and a run
//! whose files do not fit does not start. At the wall-clock timeout, or
//! when those folders pass their bound, the program's whole process tree
//! is killed (`kill_tree`; in a box, that kills the box's pid 1 and so
//! everything in it), and its process group again after it ends. The
//! grader is the subreaper of everything the program starts
//! ([`become_subreaper`]), so a process that leaves the group outside a
//! box is still reparented to it, and [`reap_orphans`] kills and reaps
//! it. An interrupted grader kills every running group ([`kill_running`])
//! before it exits.

use std::ffi::{CString, OsStr, OsString};
use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::capture::{self, Captured};
use crate::cgroup::{join_group, ControlGroup};
use crate::child::{check, drop_to_user, network_namespaces};
use crate::confinement::{Confinement, Limits, Share};
use crate::procs::{descendants, parent_and_group, processes};
use crate::quota::{Bound, Quota};
use crate::reason::{reason, start_failure};
use crate::sharing::Exec;
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
    /// The box's working folder had no byte or no inode left while the
    /// program ran or when it ended ([`crate::Scratch`]), or the folders
    /// no tmpfs bounds passed their quota ([`crate::quota`]).
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
    let mut setup = match Setup::new(argv, dir, share, confinement) {
        Ok(setup) => setup,
        Err(reason) => return Run::not_started(reason, start),
    };
    let mut child = match setup.spawn(&argv[0]) {
        Ok(child) => child,
        Err(reason) => return Run::not_started(reason, start),
    };
    let group = child.id() as libc::pid_t;
    if let Some(quota) = setup.quota.as_mut() {
        quota.watch(group);
    }
    let running = || {
        RUNNING
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    };
    running().push(group);
    let stdout = capture::spawn(child.stdout.take(), limits.output);
    let stderr = capture::spawn(child.stderr.take(), limits.output);
    let (ended, over) = wait(&mut child, start, &limits, setup.quota.as_mut());
    let seconds = start.elapsed().as_secs_f64();
    let box_full = setup.report.is_some_and(|(read, _)| reported_full(&read));
    kill_group(group);
    running().retain(|&g| g != group);
    drop(setup.group);
    // What the program left past the bound as it ended counts too, as a
    // tmpfs with no room left would.
    let left_over = || setup.quota.as_ref().is_some_and(Quota::over);
    Run {
        ended,
        seconds,
        stdout: stdout.finish(),
        stderr: stderr.finish(),
        disk_full: box_full || over || left_over(),
    }
}

/// What one run needs, made before the fork: the command (with what its
/// child does before exec), the pipe on which a box's pid 1 says its
/// tmpfs was full, the run's control groups, and the quota of the folders
/// no tmpfs bounds ([`crate::quota`]).
struct Setup {
    command: Command,
    report: Option<(OwnedFd, OwnedFd)>,
    group: Option<ControlGroup>,
    quota: Option<Quota>,
    limits: Limits,
}

impl Setup {
    /// The setup of a run of `argv` in `dir`, or why it cannot start.
    fn new(
        argv: &[OsString],
        dir: &Path,
        share: &Share,
        confinement: Confinement,
    ) -> Result<Setup, String> {
        let home = share.home.as_deref().unwrap_or(dir);
        let mut command = command(argv, dir, home);
        let limits = confinement.limits;
        let quota = quota(share, &confinement);
        if quota.as_ref().is_some_and(Quota::over) {
            return Err(does_not_fit(&limits));
        }
        let group = confinement
            .cgroup
            .then(|| ControlGroup::new(&limits))
            .flatten();
        let procs: Vec<CString> = group.as_ref().map(ControlGroup::procs).unwrap_or_default();
        let report = if confinement.boxed {
            let (plan, report) = boxed(dir, share, &confinement)?;
            let exec = Exec::new(argv, &environment(home)).map_err(|error| reason(&error))?;
            // SAFETY: `jail::enter` makes only async-signal-safe system
            // calls, on data prepared before the fork.
            unsafe {
                command.pre_exec(move || {
                    join_groups(&procs)?;
                    Err(crate::jail::enter(&plan, &exec, &confinement))
                });
            }
            report
        } else {
            let (fence, tmpdir) = fenced(&mut command, dir, share, &confinement)?;
            // SAFETY: `getpid` has no preconditions.
            let grader = unsafe { libc::getpid() };
            // SAFETY: `confine` makes only async-signal-safe system calls,
            // on data prepared before the fork.
            unsafe {
                command.pre_exec(move || {
                    join_groups(&procs)?;
                    confine(&confinement, &fence, grader, &tmpdir)
                });
            }
            None
        };
        Ok(Setup {
            command,
            report,
            group,
            quota,
            limits,
        })
    }

    /// Start the program (named `program` in a reason), or say why not.
    fn spawn(&mut self, program: &OsStr) -> Result<Child, String> {
        let spawned = {
            let _alone = SPAWNING
                .write()
                .unwrap_or_else(|poisoned| poisoned.into_inner());
            self.command.spawn()
        };
        spawned.map_err(|error| {
            // The box's pid 1 could not fill the working folder's tmpfs.
            if self.report.is_some() && error.raw_os_error() == Some(libc::ENOSPC) {
                does_not_fit(&self.limits)
            } else {
                start_failure(program, &error)
            }
        })
    }
}

/// The command of `argv` in `dir`: no environment but [`environment`],
/// stdin closed, stdout and stderr piped.
fn command(argv: &[OsString], dir: &Path, home: &Path) -> Command {
    let mut command = Command::new(&argv[0]);
    command
        .args(&argv[1..])
        .current_dir(dir)
        .env_clear()
        .envs(environment(home))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    command
}

/// A program's whole environment: the grader's `PATH` and `LANG` (or
/// defaults), and `HOME` at `home`.
fn environment(home: &Path) -> [(OsString, OsString); 3] {
    let grader =
        |name: &str, default: &str| std::env::var_os(name).unwrap_or_else(|| default.into());
    [
        ("PATH".into(), grader("PATH", "/usr/bin:/bin")),
        ("HOME".into(), home.into()),
        ("LANG".into(), grader("LANG", "C.UTF-8")),
    ]
}

/// The quota of the folders the run may write that no tmpfs bounds:
/// every one of `share`'s read-write folders, but the working folder a
/// box gives as a tmpfs.
fn quota(share: &Share, confinement: &Confinement) -> Option<Quota> {
    let tmpfs = share
        .scratch
        .as_ref()
        .filter(|_| confinement.boxed)
        .map(|scratch| &scratch.folder);
    let folders = share
        .read_write
        .iter()
        .filter(|folder| Some(*folder) != tmpfs)
        .cloned()
        .collect();
    let bound = Bound {
        bytes: confinement.limits.disk,
        inodes: crate::scratch::INODES,
    };
    Quota::new(folders, bound)
}

/// Why a run whose files do not fit its disk space cannot start.
fn does_not_fit(limits: &Limits) -> String {
    format!(
        "the program's files do not fit the run's disk space ({} MiB, {} files): raise `--disk`",
        limits.disk >> 20,
        crate::scratch::INODES
    )
}

/// The box's plan for a run in `dir`, and when the box gives the run a
/// tmpfs, the pipe on which its pid 1 says the tmpfs was full.
fn boxed(
    dir: &Path,
    share: &Share,
    confinement: &Confinement,
) -> Result<(crate::jail::Plan, Option<(OwnedFd, OwnedFd)>), String> {
    let mut plan = crate::jail::Plan::new(dir, share, confinement)
        .map_err(|error| format!("cannot prepare the box: {}", reason(&error)))?;
    if !plan.has_scratch() {
        return Ok((plan, None));
    }
    let (read, write) = report_pipe().map_err(|error| reason(&error))?;
    plan.report_to(write.as_raw_fd());
    Ok((plan, Some((read, write))))
}

/// Without a box: the fence of a run in `dir`, and its temporary folder
/// (no `/tmp` there), named in `command`'s environment.
fn fenced(
    command: &mut Command,
    dir: &Path,
    share: &Share,
    confinement: &Confinement,
) -> Result<(crate::fence::Fence, CString), String> {
    let folder = crate::tmpdir::folder(dir);
    command.envs(crate::tmpdir::environment(&folder));
    let tmpdir = crate::tmpdir::path(&folder).map_err(|error| reason(&error))?;
    let fence = crate::fence::Fence::new(share, confinement.landlock, confinement.seccomp)
        .map_err(|error| reason(&error))?;
    Ok((fence, tmpdir))
}

/// In the forked child: join the run's control groups.
fn join_groups(procs: &[CString]) -> io::Result<()> {
    for path in procs {
        join_group(path)?;
    }
    Ok(())
}

/// Wait for the program until it ends, its time is up, or its folders
/// pass their quota (then its whole process tree is killed): how it
/// ended, and whether it passed the quota.
fn wait(
    child: &mut Child,
    start: Instant,
    limits: &Limits,
    mut quota: Option<&mut Quota>,
) -> (Ended, bool) {
    let group = child.id() as libc::pid_t;
    loop {
        match child.try_wait() {
            Ok(Some(status)) => return (ended(status), false),
            Ok(None) if start.elapsed() < limits.timeout => {
                if quota.as_mut().is_some_and(|quota| quota.due()) {
                    kill_tree(group);
                    let ended = child.wait().map_or(Ended::Signalled(libc::SIGKILL), ended);
                    return (ended, true);
                }
                std::thread::sleep(Duration::from_millis(5))
            }
            _ => {
                kill_tree(group);
                let _ = child.wait();
                return (Ended::TimedOut, false);
            }
        }
    }
}

/// How a program that ended with `status` ended.
fn ended(status: ExitStatus) -> Ended {
    match (status.code(), status.signal()) {
        (Some(code), _) => Ended::Exited(code),
        (None, Some(signal)) => Ended::Signalled(signal),
        (None, None) => Ended::Signalled(0),
    }
}

/// Whether the box's pid 1 wrote on the pipe whose read end is `read`
/// that its tmpfs was full.
fn reported_full(read: &OwnedFd) -> bool {
    let mut byte = 0u8;
    // SAFETY: reading one byte into a byte.
    let got = unsafe { libc::read(read.as_raw_fd(), (&mut byte as *mut u8).cast(), 1) };
    got == 1 && byte == b'f'
}

/// Kill the whole process tree of the program whose first process is
/// `leader` (its own group's leader): every process descended from it,
/// those that left its group (`setsid`) too, and its group. Each process
/// found is stopped first, and the tree looked for again until no new one
/// is found, so none can fork a child the kill misses (a child of a
/// killed process would be reparented to the grader, out of the tree).
fn kill_tree(leader: libc::pid_t) {
    let mut stopped = Vec::new();
    for _ in 0..100 {
        let found: Vec<libc::pid_t> = descendants(leader)
            .into_iter()
            .filter(|pid| !stopped.contains(pid))
            .collect();
        if found.is_empty() {
            break;
        }
        for &pid in &found {
            // SAFETY: `kill` has no memory preconditions.
            unsafe { libc::kill(pid, libc::SIGSTOP) };
        }
        stopped.extend(found);
    }
    for &pid in &stopped {
        // SAFETY: `kill` has no memory preconditions.
        unsafe { libc::kill(pid, libc::SIGKILL) };
    }
    // SAFETY: `killpg` has no memory preconditions.
    unsafe { libc::killpg(leader, libc::SIGKILL) };
}

/// In the forked child, before `exec`, without a box: a process group of
/// its own, a network namespace when one can be had, then
/// [`drop_to_user`], the run's temporary folder ([`crate::tmpdir`]), the
/// fence ([`super::fence`]), and last (a change of
/// uid forgets it) death with `grader` ([`crate::jail::die_with`]).
fn confine(
    confinement: &Confinement,
    fence: &crate::fence::Fence,
    grader: libc::pid_t,
    tmpdir: &CString,
) -> io::Result<()> {
    // SAFETY: plain system calls on this (single-threaded) child.
    unsafe {
        check(libc::setpgid(0, 0))?;
        if confinement.isolate_network {
            check(libc::unshare(network_namespaces(confinement.root())))?;
        }
        drop_to_user(confinement)?;
        crate::tmpdir::make(tmpdir)?;
        fence.enter()?;
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
    let mut killed = 0;
    for pid in processes() {
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
