//! Children that share their parent's memory until they end or exec
//! (`clone(CLONE_VM)`, as glibc's `posix_spawn` makes its child), and the
//! program's exec prepared before the fork ([`Exec`]).
//!
//! The box's keeper (C0) is a fork of the grader, which holds every
//! scene's probes: a fork copies the page tables of all that memory, and
//! the exec that follows tears the copy down again. So the box's pid 1
//! (C1) shares C0's memory instead of copying it, and the program (C2)
//! shares it until its exec. A child that shares memory runs on a stack
//! of its own (mapped here, with a guard below it) and writes nothing
//! its parent reads but through pipes; a parent that must not run beside
//! its child until the child execs waits for that (`CLONE_VFORK`). Each
//! child is still a process of its own: its descriptors, credentials,
//! limits and signal handlers are its own copies, so what it changes of
//! them (the program's uid, its limits) is its alone.

use std::convert::Infallible;
use std::ffi::{CString, OsString};
use std::io;
use std::os::unix::ffi::OsStrExt;

use crate::child::check;

/// The bytes below a child's stack that no access may reach, so an
/// overflow faults rather than writes into another mapping: 64 KiB, a
/// whole number of pages of every page size Linux uses.
const GUARD: usize = 64 << 10;

/// Start `main(argument)` in a child that shares this process's memory,
/// on a stack of `size` bytes of its own (reserved, not committed); the
/// child ends with `main`'s return as its status, and its parent gets
/// `SIGCHLD`. With `until_exec`, this process waits until the child
/// execs or ends (`CLONE_VFORK`). The stack stays mapped: the processes
/// that map one end with the run.
///
/// # Safety
/// Async-signal-safe. `main` may make only async-signal-safe system
/// calls, and may write nothing this process reads but its own stack;
/// what `argument` points to must outlive the child's reading of it.
pub(crate) unsafe fn child(
    main: extern "C" fn(*mut libc::c_void) -> libc::c_int,
    argument: *mut libc::c_void,
    size: usize,
    until_exec: bool,
) -> io::Result<libc::pid_t> {
    unsafe {
        let base = libc::mmap(
            std::ptr::null_mut(),
            GUARD + size,
            libc::PROT_READ | libc::PROT_WRITE,
            libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_NORESERVE | libc::MAP_STACK,
            -1,
            0,
        );
        if base == libc::MAP_FAILED {
            return Err(io::Error::last_os_error());
        }
        check(libc::mprotect(base, GUARD, libc::PROT_NONE))?;
        // Page-aligned, so aligned as every ABI wants a stack's top.
        let top = base.cast::<u8>().add(GUARD + size);
        let mut flags = libc::CLONE_VM | libc::SIGCHLD;
        if until_exec {
            flags |= libc::CLONE_VFORK;
        }
        let pid = libc::clone(main, top.cast(), flags, argument);
        check(pid)?;
        Ok(pid)
    }
}

/// Write the reason `error` (its errno) on `fd`, where C0 reads why the
/// program did not start, and end this process.
///
/// # Safety
/// Async-signal-safe.
pub(crate) unsafe fn fail(fd: libc::c_int, error: io::Error) -> ! {
    let errno = error.raw_os_error().unwrap_or(libc::EIO).to_ne_bytes();
    unsafe {
        libc::write(fd, errno.as_ptr().cast(), errno.len());
        libc::_exit(127)
    }
}

/// The errno that C1 or the program wrote on `fd` ([`fail`]), or `None`
/// when every write end closed unwritten: the program's exec closed the
/// last, or the processes holding them were killed (which the keeper's
/// wait for their status then tells).
///
/// # Safety
/// Async-signal-safe.
pub(crate) unsafe fn failure(fd: libc::c_int) -> Option<io::Error> {
    let mut errno = [0u8; 4];
    // Writes of 4 bytes on a pipe are whole; no handler can interrupt the
    // read ([`default_handlers`]).
    match unsafe { libc::read(fd, errno.as_mut_ptr().cast(), errno.len()) } {
        0 => None,
        4 => Some(io::Error::from_raw_os_error(i32::from_ne_bytes(errno))),
        _ => Some(io::Error::from_raw_os_error(libc::EIO)),
    }
}

/// Put back the default action of every signal that has a handler (those
/// ignored stay ignored, as an exec keeps them): a handler of the
/// grader's must not run in a process that shares its memory with the
/// box, nor be reachable by a signal the program sends its pid 1.
///
/// # Safety
/// Async-signal-safe.
pub(crate) unsafe fn default_handlers() {
    unsafe {
        let default: libc::sigaction = std::mem::zeroed();
        for signal in 1..=64 {
            let mut action: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(signal, std::ptr::null(), &mut action) == 0
                && action.sa_sigaction != libc::SIG_DFL
                && action.sa_sigaction != libc::SIG_IGN
            {
                libc::sigaction(signal, &default, std::ptr::null_mut());
            }
        }
    }
}

/// A program's exec, prepared before the fork: its arguments (the first
/// names it, looked up as `execvp` does on the grader's `PATH`, which
/// its environment carries) and its environment, as the null-ended
/// arrays of C strings `execvpe` takes.
pub(crate) struct Exec {
    /// The strings the arrays point into: their bytes stay where they are
    /// as the vector moves.
    _strings: Vec<CString>,
    argv: Vec<*const libc::c_char>,
    envp: Vec<*const libc::c_char>,
}

// SAFETY: the pointers point into `_strings`, owned and never changed.
unsafe impl Send for Exec {}
// SAFETY: as for `Send`; nothing writes through the pointers.
unsafe impl Sync for Exec {}

impl Exec {
    /// The exec of `argv` (not empty) with `environment`.
    pub(crate) fn new(argv: &[OsString], environment: &[(OsString, OsString)]) -> io::Result<Exec> {
        let c = |bytes: Vec<u8>| {
            CString::new(bytes).map_err(|_| {
                io::Error::new(
                    io::ErrorKind::InvalidInput,
                    "an argument or a variable holds a NUL byte",
                )
            })
        };
        if argv.is_empty() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "no program to run",
            ));
        }
        let arguments = argv
            .iter()
            .map(|argument| c(argument.as_bytes().to_vec()))
            .collect::<io::Result<Vec<_>>>()?;
        let variables = environment
            .iter()
            .map(|(name, value)| c([name.as_bytes(), b"=", value.as_bytes()].concat()))
            .collect::<io::Result<Vec<_>>>()?;
        let pointers = |strings: &[CString]| {
            strings
                .iter()
                .map(|string| string.as_ptr())
                .chain([std::ptr::null()])
                .collect()
        };
        let (argv, envp) = (pointers(&arguments), pointers(&variables));
        let mut strings = arguments;
        strings.extend(variables);
        Ok(Exec {
            _strings: strings,
            argv,
            envp,
        })
    }

    /// Exec the program: returns only why it could not.
    ///
    /// # Safety
    /// Async-signal-safe (glibc's `execvpe` builds each path it tries on
    /// the stack).
    pub(crate) unsafe fn run(&self) -> io::Result<Infallible> {
        unsafe {
            libc::execvpe(self.argv[0], self.argv.as_ptr(), self.envp.as_ptr());
        }
        Err(io::Error::last_os_error())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exec_holds_its_strings_behind_null_ended_arrays() {
        let argv = ["sh", "-c", ":"].map(OsString::from);
        let environment = [("HOME".into(), "/tmp".into()), ("LANG".into(), "C".into())];
        let exec = Exec::new(&argv, &environment).unwrap();
        let read = |array: &[*const libc::c_char]| -> Vec<String> {
            assert!(array.last().unwrap().is_null());
            array[..array.len() - 1]
                .iter()
                .map(|&p| {
                    // SAFETY: each pointer before the null one is a C
                    // string of `exec`'s.
                    unsafe { std::ffi::CStr::from_ptr(p) }
                        .to_str()
                        .unwrap()
                        .to_string()
                })
                .collect()
        };
        assert_eq!(read(&exec.argv), ["sh", "-c", ":"]);
        assert_eq!(read(&exec.envp), ["HOME=/tmp", "LANG=C"]);
    }

    #[test]
    fn an_exec_refuses_no_program_and_a_nul_byte() {
        assert!(Exec::new(&[], &[]).is_err());
        assert!(Exec::new(&["a\0b".into()], &[]).is_err());
        let variable = [("NAME".into(), "a\0b".into())];
        assert!(Exec::new(&["sh".into()], &variable).is_err());
    }
}
