//! A process whose pid wrapped around below its parent's does not
//! outlive the run without a box.
//!
//! Without a box, the grader kills and reaps what a program left behind
//! by passes over `/proc`, which lists pids in increasing order
//! (`raytracer_box::run::reap_orphans`). Killing an orphan hands its
//! children to the grader; a child whose pid is lower than its parent's
//! (the kernel's pids wrapped around between the two forks) is then
//! behind the pass, and only another pass finds it. The test makes that
//! order for certain: as root, in a PID namespace of its own (so no other
//! process of the machine takes a pid meanwhile) whose first process
//! plays the grader, it sets the namespace's last pid
//! (`/proc/sys/kernel/ns_last_pid`) before each fork, so the orphan gets
//! pid 1001 and its child pid 11. Its own binary, so that the grader's
//! reaping meets no other test's processes.

use std::io;

/// How the grader of the namespace ended: the exit codes of [`grader`].
const REAPED: i32 = 0;
const NOT_ARRANGED: i32 = 2;
const SURVIVED: i32 = 3;

#[test]
fn a_child_whose_pid_wrapped_below_its_parents_is_reaped() {
    // SAFETY: `geteuid` has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        let ci = std::env::var("CI").unwrap_or_default();
        assert!(
            matches!(ci.trim(), "" | "0") || ci.eq_ignore_ascii_case("false"),
            "CI runs as root, and must run this test"
        );
        use std::io::Write;
        let _ = writeln!(
            io::stderr(),
            "SKIPPED the pid wrap-around: setting ns_last_pid needs root"
        );
        return;
    }
    // SAFETY: the child makes system calls and the grader's reaping, and
    // leaves with `_exit`; this test binary runs no other test.
    let child = unsafe { libc::fork() };
    assert!(child >= 0, "{}", io::Error::last_os_error());
    if child == 0 {
        // SAFETY: as above.
        unsafe { libc::_exit(in_a_pid_namespace()) };
    }
    let mut status = 0;
    // SAFETY: waiting for our own child.
    assert_eq!(unsafe { libc::waitpid(child, &mut status, 0) }, child);
    assert!(libc::WIFEXITED(status), "the namespace's grader was killed");
    match libc::WEXITSTATUS(status) {
        REAPED => {}
        NOT_ARRANGED => panic!("the pids could not be arranged (the child below its parent)"),
        SURVIVED => panic!("the child whose pid wrapped below its parent's survived the reaping"),
        code => panic!("the namespace's grader failed: exit {code}"),
    }
}

/// In the forked child: a PID and mount namespace whose first process is
/// the [`grader`]; its exit code.
unsafe fn in_a_pid_namespace() -> i32 {
    unsafe {
        if libc::unshare(libc::CLONE_NEWPID | libc::CLONE_NEWNS) != 0 {
            return 10;
        }
        let first = libc::fork();
        if first == 0 {
            libc::_exit(grader());
        }
        let mut status = 0;
        if first < 0 || libc::waitpid(first, &mut status, 0) != first || !libc::WIFEXITED(status) {
            return 11;
        }
        libc::WEXITSTATUS(status)
    }
}

/// Pid 1 of the namespace, with its own `/proc`: a program (M) starts an
/// orphan-to-be (A, pid 1001) which starts a child (B, pid 11) and
/// sleeps, and ends; A is then this process's child, holding B. The
/// grader reaps its orphans once, as after a run; B must be gone.
unsafe fn grader() -> i32 {
    unsafe {
        let null = std::ptr::null::<libc::c_char>();
        let private = libc::MS_REC | libc::MS_PRIVATE;
        if libc::mount(null, c"/".as_ptr(), null, private, std::ptr::null()) != 0
            || libc::mount(
                c"proc".as_ptr(),
                c"/proc".as_ptr(),
                c"proc".as_ptr(),
                0,
                std::ptr::null(),
            ) != 0
        {
            return 12;
        }
        let mut pids = [0; 2];
        if libc::pipe(pids.as_mut_ptr()) != 0 {
            return 13;
        }
        let [read_end, write_end] = pids;
        let program = libc::fork();
        if program == 0 {
            libc::_exit(program_and_orphan(write_end));
        }
        let mut status = 0;
        libc::waitpid(program, &mut status, 0);
        let mut bytes = [0u8; 8];
        if libc::read(read_end, bytes.as_mut_ptr().cast(), 8) != 8 {
            return 14;
        }
        let orphan = i32::from_ne_bytes(bytes[..4].try_into().unwrap());
        let child = i32::from_ne_bytes(bytes[4..].try_into().unwrap());
        if !(child < orphan && parent(orphan) == Some(1) && parent(child) == Some(orphan)) {
            return NOT_ARRANGED;
        }
        raytracer_box::run::reap_orphans(None);
        if libc::kill(child, 0) == 0 {
            libc::kill(child, libc::SIGKILL);
            return SURVIVED;
        }
        REAPED
    }
}

/// The program M: start A at pid 1001, which starts B at pid 11, writes
/// both pids on `pipe` and sleeps; end once B is there.
unsafe fn program_and_orphan(pipe: libc::c_int) -> i32 {
    unsafe {
        if !last_pid(1000) {
            return 15;
        }
        let orphan = libc::fork();
        if orphan == 0 {
            if !last_pid(10) {
                libc::_exit(16);
            }
            let child = libc::fork();
            if child == 0 {
                loop {
                    libc::pause();
                }
            }
            let mut bytes = [0u8; 8];
            bytes[..4].copy_from_slice(&libc::getpid().to_ne_bytes());
            bytes[4..].copy_from_slice(&child.to_ne_bytes());
            libc::write(pipe, bytes.as_ptr().cast(), 8);
            loop {
                libc::pause();
            }
        }
        // Wait until A has written, without reading what it wrote.
        let mut written: libc::c_int = 0;
        while written == 0 {
            libc::ioctl(pipe, libc::FIONREAD, &mut written);
            libc::usleep(10_000);
        }
        0
    }
}

/// Make the namespace's next pid `pid + 1`.
fn last_pid(pid: i32) -> bool {
    std::fs::write("/proc/sys/kernel/ns_last_pid", pid.to_string()).is_ok()
}

/// The parent of `pid`, from `/proc/PID/stat`.
fn parent(pid: i32) -> Option<i32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    stat[stat.rfind(')')? + 2..].split(' ').nth(1)?.parse().ok()
}
