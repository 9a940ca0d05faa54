//! The box a student's program runs in (Linux), after IOI's `isolate`:
//! namespaces and a root file system of our making.
//!
//! In the forked child ([`enter`], between fork and exec, so only
//! async-signal-safe system calls on data [`Plan::new`] prepared before
//! the fork), the process that `grade` started (the keeper's child, "C0")
//! puts back the default action of every signal the grader handles,
//! makes a process group of its own and unshares the mount, PID, network,
//! IPC and UTS namespaces; when the grader is not root, inside a user
//! namespace of its own that maps only the grader's uid and gid to
//! themselves (so the program has no capability once it runs). C0 dies
//! with the grader's thread that forked it (`PR_SET_PDEATHSIG`, checked
//! against a grader that died first), so a grader killed with SIGKILL
//! still takes the whole box with it (`die_with`). Its first
//! child ("C1"), which shares C0's memory rather than copying the
//! grader's page tables again (`sharing.rs`), is pid 1 of the new PID
//! namespace, dies with C0
//! (`PR_SET_PDEATHSIG`), and builds the root: a tmpfs holding read-only
//! binds of `/usr`, `/bin`, `/sbin`, `/lib*` and `/etc` (links stay
//! links), a minimal `/dev` (null, zero, full, random, urandom; a private
//! tmpfs `/dev/shm`), private tmpfs `/tmp` and `/var/tmp`, a fresh `/proc`
//! of the new PID namespace, and [`Share`]'s paths bound at their own
//! paths (a build's folder read-write, `nosuid` and `nodev`, a `--tracer`
//! program's file read-only); a scene's working folder is instead a tmpfs
//! of `--disk` MiB at its path, filled from the prepared folder
//! (`scratch.rs`). The grader's own executable is covered by `/dev/null`
//! if it lies under a bound system folder. It then pivots into that
//! root, detaches the old one, makes `/` read-only, in a user namespace allows
//! no user namespace to be made inside it (so the program cannot mount the
//! control groups it is held in), and starts the program ("C2"), which
//! shares that memory until its exec while C1 waits: it marks every
//! inherited descriptor close-on-exec, drops to the run's uid, takes the
//! limits and `PR_SET_NO_NEW_PRIVS`, and execs the prepared `Exec`
//! itself. C0 waits for that exec, and hands std's spawn the errno of a
//! step that failed, in C1 or in C2, when there is one.
//! C1 (not dumpable, holding no descriptor of the grader's but its own
//! pipes and the working folder's) reaps whatever is reparented to it
//! and looks at the tmpfs every 10 ms; when the program ends it kills
//! everything left in the box, copies the program's image out of the
//! tmpfs, tells the grader whether the tmpfs was full, then or when it
//! was looked at (a pipe of the run's, [`Plan::report_to`]) and exits,
//! handing the program's wait status to C0 through a pipe; C0 exits the
//! same way. When C1 exits, or is killed with C0's group at the
//! timeout, the kernel kills every process left in the namespace:
//! nothing the program started survives the run.
//! Everything else of the grader's file system (its executable, the
//! reference cache, the reports, home folders, other students' folders)
//! is simply absent, and the network namespace has only a loopback that
//! is down; abstract UNIX sockets are per network namespace, and socket
//! files of the host are not in the box.

use std::convert::Infallible;
use std::ffi::{CStr, CString, OsString};
use std::io;
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use crate::child::{check, die_with, drop_to_user, sh_runs_after};
use crate::confinement::{Confinement, Limits, Share, NOBODY};
use crate::scratch;
use crate::sharing::{self, Exec};

/// The system folders bound read-only (links among them stay links).
pub(crate) const SYSTEM: &[&str] = &[
    "/usr", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32", "/etc",
];

/// A flag of ours in [`Step::Bind`]'s flags (no mount flag uses this
/// bit): open the source in the child with `openat2(RESOLVE_NO_SYMLINKS)`
/// and bind from that descriptor, so a link planted anywhere on a shared
/// path is refused, not followed.
const NO_LINKS: libc::c_ulong = 1 << 40;

/// The devices bound into the box's `/dev`.
pub(crate) const DEVICES: &[&str] = &["null", "zero", "full", "random", "urandom"];

/// One step of building the box's root, in C1.
#[derive(Debug)]
enum Step {
    Mkdir(CString),
    /// A tmpfs with these options.
    Tmpfs(CString, CString),
    /// Bind `from` onto `to`, read-only with the source's locked flags.
    Bind {
        from: CString,
        to: CString,
        read_only: bool,
        flags: libc::c_ulong,
    },
    /// An empty file to bind a file onto.
    Touch(CString),
    Symlink(CString, CString),
    Proc(CString),
    /// The run's working folder `from` as a tmpfs at `to`, with these
    /// options, filled from it ([`crate::scratch`]).
    Scratch {
        from: CString,
        to: CString,
        options: CString,
    },
}

/// Everything the child needs, prepared before the fork.
#[derive(Debug)]
pub struct Plan {
    root: CString,
    steps: Vec<Step>,
    start: CString,
    uid_map: CString,
    gid_map: CString,
    /// The grader's command line in memory (`arg_start..arg_end` of
    /// `/proc/self/stat`), which C1, a fork of the grader, blanks: the
    /// box's `/proc/1/cmdline` names no report or cache.
    arguments: Option<(usize, usize)>,
    /// The grader's pid: C0 dies with it ([`enter`]).
    grader: libc::pid_t,
    /// The folder (relative to the working folder) and name of the file
    /// C1 copies out of the tmpfs, when there is one.
    keep: Option<(CString, CString)>,
    /// The descriptor C1 writes `f` to when the tmpfs was full; -1 for none.
    report: libc::c_int,
}

fn c(path: &Path) -> io::Result<CString> {
    CString::new(path.as_os_str().as_bytes())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "a path holds a NUL byte"))
}

/// The folder every box's root is mounted on (in the box's own mount
/// namespace, so many boxes share it): the grader's, empty, 0700.
fn staging() -> io::Result<&'static Path> {
    static STAGING: OnceLock<Option<PathBuf>> = OnceLock::new();
    STAGING
        .get_or_init(|| {
            let dir = tempfile::Builder::new()
                .prefix("raytracer-box-")
                .tempdir()
                .ok()?;
            // Kept for the grader's lifetime; [`remove_staging`] removes it.
            Some(dir.keep())
        })
        .as_deref()
        .ok_or_else(|| io::Error::other("cannot make the box's mount point"))
}

/// Remove the box's mount point when `last`: what `grade` does after
/// its last job.
pub fn remove_staging_if(last: bool) {
    if let (true, Ok(dir)) = (last, staging()) {
        let _ = std::fs::remove_dir(dir);
    }
}

/// The locked mount flags of the file system holding `path`, which a
/// read-only remount inside a user namespace must keep.
fn locked_flags(path: &Path) -> libc::c_ulong {
    let Ok(name) = c(path) else { return 0 };
    // SAFETY: `statvfs` writes into the zeroed struct we pass.
    let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
    if unsafe { libc::statvfs(name.as_ptr(), &mut st) } != 0 {
        return 0;
    }
    let mut flags = 0;
    for (st_flag, ms_flag) in [
        (libc::ST_NOSUID, libc::MS_NOSUID),
        (libc::ST_NODEV, libc::MS_NODEV),
        (libc::ST_NOEXEC, libc::MS_NOEXEC),
        (libc::ST_NOATIME, libc::MS_NOATIME),
        (libc::ST_NODIRATIME, libc::MS_NODIRATIME),
        (libc::ST_RELATIME, libc::MS_RELATIME),
    ] {
        if st.f_flag & st_flag != 0 {
            flags |= ms_flag;
        }
    }
    flags
}

impl Plan {
    /// The box for a program starting in `start`, holding `share`.
    pub fn new(start: &Path, share: &Share, confinement: &Confinement) -> io::Result<Plan> {
        let root = staging()?.to_path_buf();
        let mut steps = Steps {
            root: root.clone(),
            steps: Vec::new(),
        };
        let tmpfs_size = format!("size={}", confinement.limits.file_size.max(1 << 20) * 4);
        steps.push(Step::Tmpfs(
            c(&root)?,
            CString::new(format!("mode=0755,{tmpfs_size}")).unwrap_or_default(),
        ));
        steps.system()?;
        steps.devices()?;
        steps.temporary(&tmpfs_size)?;
        let keep = steps.shared(share, confinement.limits.disk)?;
        // SAFETY: `getuid`/`getgid` have no preconditions.
        let (uid, gid) = unsafe { (libc::getuid(), libc::getgid()) };
        Ok(Plan {
            root: c(&root)?,
            steps: steps.steps,
            start: c(start)?,
            uid_map: CString::new(format!("{uid} {uid} 1\n")).unwrap_or_default(),
            gid_map: CString::new(format!("{gid} {gid} 1\n")).unwrap_or_default(),
            arguments: arguments(),
            // SAFETY: `getpid` has no preconditions.
            grader: unsafe { libc::getpid() },
            keep,
            report: -1,
        })
    }

    /// Whether the box gives the run a tmpfs working folder, whose
    /// fullness C1 reports ([`Plan::report_to`]).
    pub fn has_scratch(&self) -> bool {
        self.keep.is_some()
    }

    /// Have C1 write `f` to the descriptor `fd` (the write end of a pipe,
    /// close-on-exec) when the run's tmpfs was full.
    pub fn report_to(&mut self, fd: libc::c_int) {
        self.report = fd;
    }
}

/// The steps of a plan being made, under the box's `root`.
struct Steps {
    root: PathBuf,
    steps: Vec<Step>,
}

impl Steps {
    fn push(&mut self, step: Step) {
        self.steps.push(step);
    }

    /// Where the host's `path` lies in the box's root.
    fn inside(&self, path: &Path) -> PathBuf {
        self.root.join(path.strip_prefix("/").unwrap_or(path))
    }

    /// The system folders, bound read-only (a link among them stays a
    /// link), and the grader's own executable covered by `/dev/null`
    /// when it lies in one.
    fn system(&mut self) -> io::Result<()> {
        let exe = std::env::current_exe().and_then(std::fs::canonicalize).ok();
        let mut masked = None;
        for dir in SYSTEM {
            let host = Path::new(dir);
            let Ok(meta) = host.symlink_metadata() else {
                continue;
            };
            if meta.file_type().is_symlink() {
                let target = std::fs::read_link(host)?;
                self.push(Step::Symlink(c(&target)?, c(&self.inside(host))?));
            } else if meta.is_dir() {
                self.push(Step::Mkdir(c(&self.inside(host))?));
                self.bind(host, &self.inside(host), true, locked_flags(host))?;
                if let Some(exe) = exe.as_ref().filter(|exe| exe.starts_with(host)) {
                    masked = Some(exe.clone());
                }
            }
        }
        if let Some(exe) = masked {
            self.bind(
                Path::new("/dev/null"),
                &self.inside(&exe),
                true,
                locked_flags(&exe),
            )?;
        }
        Ok(())
    }

    /// A bind of `from` onto `to`.
    fn bind(
        &mut self,
        from: &Path,
        to: &Path,
        read_only: bool,
        flags: libc::c_ulong,
    ) -> io::Result<()> {
        self.push(Step::Bind {
            from: c(from)?,
            to: c(to)?,
            read_only,
            flags,
        });
        Ok(())
    }

    /// A minimal `/dev`: a small tmpfs holding [`DEVICES`] bound from the
    /// host's, and the links to this process's descriptors.
    fn devices(&mut self) -> io::Result<()> {
        let dev = self.root.join("dev");
        self.push(Step::Mkdir(c(&dev)?));
        self.push(Step::Tmpfs(c(&dev)?, c(Path::new("mode=0755,size=64k"))?));
        for device in DEVICES {
            let to = dev.join(device);
            self.push(Step::Touch(c(&to)?));
            self.bind(&Path::new("/dev").join(device), &to, false, 0)?;
        }
        for (name, target) in [
            ("fd", "/proc/self/fd"),
            ("stdin", "/proc/self/fd/0"),
            ("stdout", "/proc/self/fd/1"),
            ("stderr", "/proc/self/fd/2"),
        ] {
            self.push(Step::Symlink(c(Path::new(target))?, c(&dev.join(name))?));
        }
        Ok(())
    }

    /// Private tmpfs `/dev/shm`, `/tmp` and `/var/tmp` of `size`, and a
    /// fresh `/proc`.
    fn temporary(&mut self, size: &str) -> io::Result<()> {
        let sticky = CString::new(format!("mode=1777,{size}")).unwrap_or_default();
        for tmp in ["dev/shm", "tmp", "var", "var/tmp"] {
            self.push(Step::Mkdir(c(&self.root.join(tmp))?));
            if tmp != "var" {
                self.push(Step::Tmpfs(c(&self.root.join(tmp))?, sticky.clone()));
            }
        }
        self.push(Step::Mkdir(c(&self.root.join("proc"))?));
        self.push(Step::Proc(c(&self.root.join("proc"))?));
        Ok(())
    }

    /// `share`'s paths at their own paths: bound, or for its working
    /// folder a tmpfs of `disk` bytes; the folder and name of the file to
    /// keep from that tmpfs, when there is one.
    fn shared(&mut self, share: &Share, disk: u64) -> io::Result<Option<(CString, CString)>> {
        let mut keep = None;
        for (paths, read_only) in [(&share.read_write, false), (&share.read_only, true)] {
            for path in paths {
                let to = self.mount_point(path)?;
                match share
                    .scratch
                    .as_ref()
                    .filter(|s| !read_only && s.folder == *path)
                {
                    Some(scratch) => keep = Some(self.scratch(path, &to, scratch, disk)?),
                    None => self.bind(path, &to, read_only, locked_flags(path) | NO_LINKS)?,
                }
            }
        }
        Ok(keep)
    }

    /// The folders down to `path` in the box, and `path` itself (a folder
    /// or an empty file, as on the host): where it is mounted.
    fn mount_point(&mut self, path: &Path) -> io::Result<PathBuf> {
        let meta = path.symlink_metadata()?;
        let to = self.inside(path);
        for ancestor in to.ancestors().collect::<Vec<_>>().into_iter().rev() {
            if ancestor.starts_with(&self.root) && ancestor != self.root && ancestor != to {
                self.push(Step::Mkdir(c(ancestor)?));
            }
        }
        self.push(if meta.is_dir() {
            Step::Mkdir(c(&to)?)
        } else {
            Step::Touch(c(&to)?)
        });
        Ok(to)
    }

    /// The working folder `path` as a tmpfs of `disk` bytes at `to`; the
    /// folder and name of `scratch`'s file to keep.
    fn scratch(
        &mut self,
        path: &Path,
        to: &Path,
        scratch: &crate::confinement::Scratch,
        disk: u64,
    ) -> io::Result<(CString, CString)> {
        let options = format!(
            "mode=0700,size={},nr_inodes={}",
            disk.max(1 << 20),
            scratch::INODES
        );
        self.push(Step::Scratch {
            from: c(path)?,
            to: c(to)?,
            options: CString::new(options).unwrap_or_default(),
        });
        let folder = scratch.keep.parent().filter(|p| !p.as_os_str().is_empty());
        let name = scratch.keep.file_name().unwrap_or_default();
        Ok((c(folder.unwrap_or(Path::new(".")))?, c(Path::new(name))?))
    }
}

/// Where this process's command line lies in its memory.
fn arguments() -> Option<(usize, usize)> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let fields: Vec<&str> = stat[stat.rfind(')')? + 2..].split(' ').collect();
    // Fields 48 and 49 of stat(5), counted from 3 after the command name.
    let start = fields.get(48 - 3)?.parse().ok()?;
    let end = fields.get(49 - 3)?.parse().ok()?;
    (start < end).then_some((start, end))
}

/// Write `bytes` to the file `path` (a `/proc` map).
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
unsafe fn write_file(path: &[u8], bytes: &[u8]) -> io::Result<()> {
    unsafe {
        let fd = libc::open(path.as_ptr().cast(), libc::O_WRONLY | libc::O_CLOEXEC);
        check(fd)?;
        let written = libc::write(fd, bytes.as_ptr().cast(), bytes.len());
        libc::close(fd);
        if written != bytes.len() as isize {
            return Err(io::Error::last_os_error());
        }
    }
    Ok(())
}

/// The stack of C1, which copies a folder tree into the tmpfs with a
/// frame of `PATH_MAX` bytes per level ([`scratch::DEPTH`]): reserved, only
/// the pages it reaches are ever committed.
const INIT_STACK: usize = 8 << 20;

/// The stack of the program's process until its exec.
const PROGRAM_STACK: usize = 1 << 20;

/// What C1 reads of C0's, in the memory they share: copied onto C1's own
/// stack as it starts.
#[derive(Clone, Copy)]
struct Init<'a> {
    plan: &'a Plan,
    exec: &'a Exec,
    confinement: &'a Confinement,
    /// The pipe on which C1 hands the program's wait status to C0.
    status: [libc::c_int; 2],
    /// The pipe on which C1 or the program says why the program did not
    /// start ([`sharing::fail`]); its last write end closes with the
    /// program's exec.
    started: [libc::c_int; 2],
}

/// What the program's process reads of C1's before its exec.
struct Program<'a> {
    exec: &'a Exec,
    confinement: &'a Confinement,
    /// C1's write end of [`Init::status`].
    status: libc::c_int,
    /// The prepared working folder and its tmpfs, open in C1.
    folders: Option<(libc::c_int, libc::c_int)>,
    started: libc::c_int,
}

/// In the child `grade` forked (C0), before exec: the box of the module
/// doc, then C0's wait for the program's status, which it ends with.
/// Returns only why the program could not start, which std's spawn then
/// reports to the grader.
///
/// # Safety
/// Async-signal-safe: called between fork and exec, on `plan` and `exec`
/// prepared before the fork.
pub(crate) unsafe fn enter(plan: &Plan, exec: &Exec, confinement: &Confinement) -> io::Error {
    match unsafe { keep(plan, exec, confinement) } {
        Err(error) => error,
    }
}

/// C0: unshare the namespaces, start C1 in them, and wait for the
/// program's exec, then its status ([`keeper`]).
///
/// # Safety
/// As [`enter`].
unsafe fn keep(plan: &Plan, exec: &Exec, confinement: &Confinement) -> io::Result<Infallible> {
    unsafe {
        sharing::default_handlers();
        check(libc::setpgid(0, 0))?;
        let mut flags = libc::CLONE_NEWNS
            | libc::CLONE_NEWPID
            | libc::CLONE_NEWNET
            | libc::CLONE_NEWIPC
            | libc::CLONE_NEWUTS;
        if !confinement.root() {
            flags |= libc::CLONE_NEWUSER;
        }
        check(libc::unshare(flags))?;
        if !confinement.root() {
            write_file(b"/proc/self/setgroups\0", b"deny")?;
            write_file(b"/proc/self/uid_map\0", plan.uid_map.as_bytes())?;
            write_file(b"/proc/self/gid_map\0", plan.gid_map.as_bytes())?;
        }
        die_with(plan.grader)?;
        let mut init = Init {
            plan,
            exec,
            confinement,
            status: pipe()?,
            started: pipe()?,
        };
        let pid = sharing::child(
            init_main,
            (&mut init as *mut Init).cast(),
            INIT_STACK,
            false,
        )?;
        libc::close(init.started[1]);
        if let Some(error) = sharing::failure(init.started[0]) {
            return Err(error);
        }
        keeper(pid, init.status[0], init.status[1])
    }
}

/// A pipe, both ends close-on-exec: its read end and its write end.
///
/// # Safety
/// Async-signal-safe.
unsafe fn pipe() -> io::Result<[libc::c_int; 2]> {
    let mut ends = [0; 2];
    check(unsafe { libc::pipe2(ends.as_mut_ptr(), libc::O_CLOEXEC) })?;
    Ok(ends)
}

/// C1, started by C0 on its [`Init`]: pid 1 of the new namespace.
extern "C" fn init_main(argument: *mut libc::c_void) -> libc::c_int {
    // SAFETY: C0 passed its `Init`, which it keeps until it reads from
    // `started`, which happens after this copy.
    let init = unsafe { *argument.cast::<Init>() };
    // SAFETY: only async-signal-safe calls on data prepared before the fork.
    unsafe {
        libc::close(init.status[0]);
        libc::close(init.started[0]);
        match init_box(&init) {
            Err(error) => sharing::fail(init.started[1], error),
        }
    }
}

/// C1: build the root, start the program in it, and reap until it ends
/// ([`reap_until_done`]).
///
/// # Safety
/// Async-signal-safe.
unsafe fn init_box(init: &Init) -> io::Result<Infallible> {
    let Init {
        plan, confinement, ..
    } = *init;
    unsafe {
        check(libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL, 0, 0, 0))?;
        if libc::getppid() != 0 {
            // C0 already died: nothing to run for.
            libc::_exit(1);
        }
        if let Some((start, end)) = plan.arguments {
            std::ptr::write_bytes(start as *mut u8, 0, end - start);
        }
        let folders = build_root(plan, confinement.user)?;
        if !confinement.root() {
            // No user namespace may be made inside the box's: in one, with
            // a cgroup namespace, the program could mount the control
            // groups it runs in, which a delegated grader's uid owns
            // (`sandbox::ControlGroup`), and raise its own limits.
            write_file(b"/proc/sys/user/max_user_namespaces\0", b"0")?;
        }
        // Not dumpable before the program exists: it could otherwise reach
        // the descriptors below through `/proc/1/fd`.
        libc::prctl(libc::PR_SET_DUMPABLE, 0, 0, 0, 0);
        let mut program = Program {
            exec: init.exec,
            confinement,
            status: init.status[1],
            folders,
            started: init.started[1],
        };
        let pid = sharing::child(
            program_main,
            (&mut program as *mut Program).cast(),
            PROGRAM_STACK,
            true,
        )?;
        // Nothing in the box may use the grader's descriptors through us.
        let (host, inside) = folders.unwrap_or((-1, -1));
        close_all_but(&[init.status[1], host, inside, plan.report]);
        reap_until_done(plan, confinement, pid, (host, inside), init.status[1])
    }
}

/// The program's process, started by C1 on its [`Program`]: drop to the
/// run's user and exec.
extern "C" fn program_main(argument: *mut libc::c_void) -> libc::c_int {
    // SAFETY: C1 waits, its `Program` untouched, until this process execs
    // or ends.
    let program = unsafe { &*argument.cast::<Program>() };
    // SAFETY: only async-signal-safe calls on data prepared before the fork.
    unsafe {
        libc::close(program.status);
        if let Some((host, inside)) = program.folders {
            libc::close(host);
            libc::close(inside);
        }
        let ran = libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL, 0, 0, 0);
        let error = match check(ran).and_then(|()| drop_to_user(program.confinement)) {
            Ok(()) => match program.exec.run() {
                Err(error) => error,
            },
            Err(error) => error,
        };
        sharing::fail(program.started, error)
    }
}

/// C1 once the program (`program`) runs: reap whatever is reparented to
/// it, and look at the tmpfs every 10 ms, until the program ends; then
/// kill everything left in the box, say whether the tmpfs was full (then
/// or when it was looked at), copy the program's image out of it (the
/// prepared folder and the tmpfs are `folders`, -1 for none), hand the
/// program's wait status to C0 on `write_end`, and exit.
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
unsafe fn reap_until_done(
    plan: &Plan,
    confinement: &Confinement,
    program: libc::pid_t,
    (host, inside): (libc::c_int, libc::c_int),
    write_end: libc::c_int,
) -> ! {
    unsafe {
        let mut status = 0;
        // Whether the tmpfs was seen full while the program ran: a file it
        // removed but held open fills it only until the program ends.
        let mut full = false;
        loop {
            let pid = libc::waitpid(-1, &mut status, libc::WNOHANG);
            if pid == program {
                break;
            }
            if pid == -1 && *libc::__errno_location() == libc::ECHILD {
                libc::_exit(1);
            }
            if pid == 0 {
                full = full || (inside >= 0 && scratch::full(inside));
                let pause = libc::timespec {
                    tv_sec: 0,
                    tv_nsec: 10_000_000,
                };
                libc::nanosleep(&pause, std::ptr::null_mut());
            }
        }
        // Nothing may change the folder while it is read.
        libc::kill(-1, libc::SIGKILL);
        while libc::waitpid(-1, std::ptr::null_mut(), 0) != -1
            || *libc::__errno_location() == libc::EINTR
        {}
        if let (Some((folder, name)), true) = (&plan.keep, inside >= 0) {
            if (full || scratch::full(inside)) && plan.report >= 0 {
                libc::write(plan.report, b"f".as_ptr().cast(), 1);
            }
            let _ = scratch::keep(
                inside,
                host,
                folder.as_ptr(),
                name.as_ptr(),
                confinement.user,
            );
        }
        let bytes = status.to_ne_bytes();
        libc::write(write_end, bytes.as_ptr().cast(), bytes.len());
        libc::_exit(0)
    }
}

/// Close every descriptor from 3 on but those of `keep` (-1 for none).
unsafe fn close_all_but(keep: &[libc::c_int]) {
    let mut kept = [-1; 4];
    let count = keep.len().min(kept.len());
    kept[..count].copy_from_slice(&keep[..count]);
    kept.sort_unstable();
    let mut first = 3;
    for &fd in kept.iter().filter(|&&fd| fd >= 3) {
        unsafe {
            if fd > first {
                libc::syscall(libc::SYS_close_range, first as u32, (fd - 1) as u32, 0u32);
            }
        }
        first = first.max(fd + 1);
    }
    unsafe {
        libc::syscall(libc::SYS_close_range, first as u32, u32::MAX, 0u32);
    }
}

/// C0 once the program runs: wait for its status and end as it did.
unsafe fn keeper(init: libc::pid_t, read_end: libc::c_int, write_end: libc::c_int) -> ! {
    unsafe {
        libc::close(write_end);
        close_all_but(&[read_end]);
        let mut bytes = [0u8; 4];
        let mut got = 0;
        while got < 4 {
            let n = libc::read(read_end, bytes[got..].as_mut_ptr().cast(), 4 - got);
            if n > 0 {
                got += n as usize;
            } else if n == 0 || *libc::__errno_location() != libc::EINTR {
                break;
            }
        }
        let mut init_status = 0;
        while libc::waitpid(init, &mut init_status, 0) == -1
            && *libc::__errno_location() == libc::EINTR
        {}
        let status = if got == 4 {
            i32::from_ne_bytes(bytes)
        } else {
            init_status
        };
        if libc::WIFSIGNALED(status) {
            let signal = libc::WTERMSIG(status);
            libc::signal(signal, libc::SIG_DFL);
            libc::kill(libc::getpid(), signal);
            libc::_exit(128 + signal);
        }
        libc::_exit(if libc::WIFEXITED(status) {
            libc::WEXITSTATUS(status)
        } else {
            1
        })
    }
}

/// Open `path` with `flags` (`O_PATH`: as a place), refusing a link
/// anywhere on it.
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
unsafe fn open_no_links(path: &CStr, flags: libc::c_int) -> io::Result<libc::c_int> {
    unsafe {
        let mut how: libc::open_how = std::mem::zeroed();
        how.flags = (flags | libc::O_NOFOLLOW | libc::O_CLOEXEC) as u64;
        how.resolve = libc::RESOLVE_NO_SYMLINKS | libc::RESOLVE_NO_MAGICLINKS;
        let fd = libc::syscall(
            libc::SYS_openat2,
            libc::AT_FDCWD,
            path.as_ptr(),
            &how as *const libc::open_how,
            std::mem::size_of::<libc::open_how>(),
        );
        if fd < 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(fd as libc::c_int)
    }
}

/// `/proc/self/fd/FD` written into `buffer` without allocating.
fn fd_path(fd: libc::c_int, buffer: &mut [u8; 32]) -> *const libc::c_char {
    let prefix = b"/proc/self/fd/";
    buffer[..prefix.len()].copy_from_slice(prefix);
    let mut digits = [0u8; 12];
    let mut n = fd.max(0) as u32;
    let mut count = 0;
    loop {
        digits[count] = b'0' + (n % 10) as u8;
        count += 1;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    for i in 0..count {
        buffer[prefix.len() + i] = digits[count - 1 - i];
    }
    buffer[prefix.len() + count] = 0;
    buffer.as_ptr().cast()
}

/// C1: build the box's root from the plan, pivot into it, and go to the
/// program's folder; the prepared working folder and its tmpfs, open,
/// when there is one (`owner` is the run's user when the grader is root).
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
unsafe fn build_root(
    plan: &Plan,
    owner: Option<u32>,
) -> io::Result<Option<(libc::c_int, libc::c_int)>> {
    let mut folders = None;
    unsafe {
        remount(c"/", libc::MS_REC | libc::MS_PRIVATE)?;
        for step in &plan.steps {
            if let Some(opened) = take(step, owner)? {
                folders = Some(opened);
            }
        }
        pivot(plan)?;
    }
    Ok(folders)
}

/// `mount` of nothing on `target` with `flags`: a change of an existing
/// mount's flags or propagation.
///
/// # Safety
/// Async-signal-safe.
unsafe fn remount(target: &CStr, flags: libc::c_ulong) -> io::Result<()> {
    let null = std::ptr::null::<libc::c_char>();
    // SAFETY: C strings and a null data pointer.
    check(unsafe { libc::mount(null, target.as_ptr(), null, flags, std::ptr::null()) })
}

/// A `tmpfs` (`nosuid`, `nodev`) on `path` with `options`.
///
/// # Safety
/// Async-signal-safe.
unsafe fn tmpfs(path: &CStr, options: &CStr) -> io::Result<()> {
    // SAFETY: C strings.
    check(unsafe {
        libc::mount(
            c"tmpfs".as_ptr(),
            path.as_ptr(),
            c"tmpfs".as_ptr(),
            libc::MS_NOSUID | libc::MS_NODEV,
            options.as_ptr().cast(),
        )
    })
}

/// Take one step of the plan; the prepared working folder and its
/// tmpfs, open, after [`Step::Scratch`].
///
/// # Safety
/// Async-signal-safe.
unsafe fn take(step: &Step, owner: Option<u32>) -> io::Result<Option<(libc::c_int, libc::c_int)>> {
    unsafe {
        match step {
            Step::Mkdir(path) => {
                if libc::mkdir(path.as_ptr(), 0o755) == -1
                    && *libc::__errno_location() != libc::EEXIST
                {
                    return Err(io::Error::last_os_error());
                }
            }
            Step::Tmpfs(path, options) => tmpfs(path, options)?,
            Step::Bind {
                from,
                to,
                read_only,
                flags,
            } => bind(from, to, *read_only, *flags)?,
            Step::Scratch { from, to, options } => {
                return scratch_from(from, to, options, owner).map(Some)
            }
            Step::Touch(path) => {
                let fd = libc::open(
                    path.as_ptr(),
                    libc::O_CREAT | libc::O_WRONLY | libc::O_CLOEXEC,
                    0o644,
                );
                check(fd)?;
                libc::close(fd);
            }
            Step::Symlink(target, link) => check(libc::symlink(target.as_ptr(), link.as_ptr()))?,
            Step::Proc(path) => check(libc::mount(
                c"proc".as_ptr(),
                path.as_ptr(),
                c"proc".as_ptr(),
                libc::MS_NOSUID | libc::MS_NODEV | libc::MS_NOEXEC,
                std::ptr::null(),
            ))?,
        }
    }
    Ok(None)
}

/// Bind `from` onto `to` ([`Step::Bind`]): through a descriptor opened
/// without following a link when `flags` asks for it ([`NO_LINKS`]); a
/// read-only bind, and a shared folder (a build's), remounted to run no
/// set-user-ID file and open no device.
///
/// # Safety
/// Async-signal-safe.
unsafe fn bind(from: &CStr, to: &CStr, read_only: bool, flags: libc::c_ulong) -> io::Result<()> {
    let no_links = flags & NO_LINKS != 0;
    let flags = flags & !NO_LINKS;
    let null = std::ptr::null::<libc::c_char>();
    let mut through = [0u8; 32];
    let mut fd = -1;
    unsafe {
        let source = if no_links {
            fd = open_no_links(from, libc::O_PATH)?;
            fd_path(fd, &mut through)
        } else {
            from.as_ptr()
        };
        let bound = libc::mount(
            source,
            to.as_ptr(),
            null,
            libc::MS_BIND | libc::MS_REC,
            std::ptr::null(),
        );
        if fd >= 0 {
            libc::close(fd);
        }
        check(bound)?;
        let remount_flags = if read_only {
            Some(libc::MS_RDONLY)
        } else {
            no_links.then_some(0)
        };
        if let Some(read_only) = remount_flags {
            let hardened = libc::MS_REMOUNT | libc::MS_BIND | libc::MS_NOSUID | libc::MS_NODEV;
            remount(to, hardened | read_only | flags)?;
        }
    }
    Ok(())
}

/// The working folder `from` as a tmpfs at `to` with `options`, given to
/// `owner` and filled from `from` ([`crate::scratch`]); both open.
///
/// # Safety
/// Async-signal-safe.
unsafe fn scratch_from(
    from: &CStr,
    to: &CStr,
    options: &CStr,
    owner: Option<u32>,
) -> io::Result<(libc::c_int, libc::c_int)> {
    unsafe {
        let host = open_no_links(from, libc::O_RDONLY | libc::O_DIRECTORY)?;
        tmpfs(to, options)?;
        let inside = libc::open(
            to.as_ptr(),
            libc::O_RDONLY | libc::O_DIRECTORY | libc::O_NOFOLLOW | libc::O_CLOEXEC,
        );
        check(inside)?;
        let mut stat: libc::stat = std::mem::zeroed();
        check(libc::fstat(host, &mut stat))?;
        scratch::give(inside, stat.st_mode, owner)?;
        scratch::fill(host, inside, owner, scratch::DEPTH)?;
        Ok((host, inside))
    }
}

/// Pivot into the plan's root, detach the old one, make `/` read-only,
/// and go to the program's folder.
///
/// # Safety
/// Async-signal-safe.
unsafe fn pivot(plan: &Plan) -> io::Result<()> {
    unsafe {
        check(libc::chdir(plan.root.as_ptr()))?;
        check(libc::syscall(libc::SYS_pivot_root, c".".as_ptr(), c".".as_ptr()) as libc::c_int)?;
        check(libc::umount2(c".".as_ptr(), libc::MNT_DETACH))?;
        check(libc::chdir(c"/".as_ptr()))?;
        remount(
            c"/",
            libc::MS_REMOUNT | libc::MS_BIND | libc::MS_RDONLY | libc::MS_NOSUID | libc::MS_NODEV,
        )?;
        check(libc::chdir(plan.start.as_ptr()))?;
        libc::sethostname(c"box".as_ptr(), 3);
    }
    Ok(())
}

/// Whether a box can be had here: run `sh -c :` in one.
pub fn available(root: bool) -> bool {
    let confinement = Confinement {
        limits: Limits {
            timeout: std::time::Duration::from_secs(10),
            cpu_seconds: 10,
            address_space: 1 << 32,
            file_size: 1 << 20,
            processes: 64,
            output: 1024,
            disk: 1 << 20,
        },
        isolate_network: true,
        user: root.then_some(NOBODY),
        boxed: true,
        cgroup: false,
        landlock: false,
        seccomp: false,
    };
    let Ok(plan) = Plan::new(Path::new("/"), &Share::default(), &confinement) else {
        return false;
    };
    let sh: Vec<OsString> = ["sh", "-c", ":"].map(OsString::from).to_vec();
    let Ok(exec) = Exec::new(&sh, &[]) else {
        return false;
    };
    // SAFETY: `enter` makes only async-signal-safe calls on the plan.
    unsafe { sh_runs_after(move || Err(enter(&plan, &exec, &confinement))) }
}
