//! Copying a folder that a student's program may write, without ever
//! following a link in it.
//!
//! The grader copies a student's folder (for the build) and the built
//! folder (into each scene's working folder), as root when it grades as
//! root. A path walked by name could be swapped for a link between the
//! check and the use, and root would then read whatever the link names
//! into a folder the student can read. So the walk holds each folder open
//! and reaches every entry relative to it (`openat` with `O_NOFOLLOW`):
//! a folder is entered only when it is one, a file is read only when it
//! is one, and a link is copied as a link (its target unread, so the
//! student's program meets it with its own rights). Anything else (a
//! FIFO, a socket, a device) is left out. The copy is bounded in bytes,
//! entries and depth ([`MAX_DEPTH`]), so a folder cannot fill the disk
//! the grader writes to nor make the walk recurse without end. A copied
//! file keeps its permissions but never its set-user-ID, set-group-ID or
//! sticky bit: the grader's copy of a student's file is no one's way to
//! another uid.

use std::ffi::{CStr, CString, OsStr};
use std::fs::File;
use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::PermissionsExt;
use std::path::Path;

/// The most a copied folder may hold.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    pub bytes: u64,
    pub entries: u64,
}

/// A student's folder: generous for sources and a build's output, and far
/// below what would trouble the grader's disk.
pub const STUDENT_FOLDER: Budget = Budget {
    bytes: 256 << 20,
    entries: 20_000,
};

/// How deep a copied folder may nest: far beyond a program's sources and
/// build, and few enough frames for any thread's stack.
pub const MAX_DEPTH: u32 = 64;

/// Copy the contents of the folder `from` into the existing folder `to`
/// (entries already there with the same names are replaced), within
/// `budget`.
pub fn copy_folder(from: &Path, to: &Path, budget: Budget) -> io::Result<()> {
    let source = open_at(libc::AT_FDCWD, from.as_os_str(), libc::O_DIRECTORY)?;
    let mut walk = Walk {
        budget,
        left: budget,
    };
    walk.copy_entries(&source, to, MAX_DEPTH)
}

/// A copy under way: the budget it started with and what is left of it.
struct Walk {
    budget: Budget,
    left: Budget,
}

/// Open `name` relative to the descriptor `dir` (`AT_FDCWD`: the working
/// folder), never following a link at its last component.
pub(crate) fn open_at(dir: libc::c_int, name: &OsStr, flags: libc::c_int) -> io::Result<OwnedFd> {
    let name =
        CString::new(name.as_bytes()).map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))?;
    // SAFETY: `name` is a valid C string; the descriptor returned is owned
    // by the `OwnedFd` below.
    let fd = unsafe {
        libc::openat(
            dir,
            name.as_ptr(),
            flags | libc::O_RDONLY | libc::O_NOFOLLOW | libc::O_CLOEXEC,
        )
    };
    if fd < 0 {
        return Err(io::Error::last_os_error());
    }
    // SAFETY: `fd` is a fresh descriptor no one else owns.
    Ok(unsafe { OwnedFd::from_raw_fd(fd) })
}

/// `name` in `dir` opened for reading when it is, as opened, a regular
/// file; `None` when it is anything else. A program running meanwhile may
/// have swapped the file it was for a FIFO (which would block an open
/// without `O_NONBLOCK` for ever) or a link (`O_NOFOLLOW` refuses it), so
/// what is checked is the descriptor, not the name.
fn open_regular_at(dir: &OwnedFd, name: &OsStr) -> io::Result<Option<File>> {
    let file = match open_at(dir.as_raw_fd(), name, libc::O_NONBLOCK) {
        Ok(fd) => File::from(fd),
        Err(error) if error.raw_os_error() == Some(libc::ELOOP) => return Ok(None),
        Err(error) => return Err(error),
    };
    Ok(file.metadata()?.is_file().then_some(file))
}

/// `fstatat` of `name` in `dir`, the link itself when it is one.
pub(crate) fn stat_at(dir: &OwnedFd, name: &CStr) -> io::Result<libc::stat> {
    // SAFETY: `stat` is plain data, filled by the call.
    let mut stat: libc::stat = unsafe { std::mem::zeroed() };
    // SAFETY: valid descriptor, C string and out pointer.
    let result = unsafe {
        libc::fstatat(
            dir.as_raw_fd(),
            name.as_ptr(),
            &mut stat,
            libc::AT_SYMLINK_NOFOLLOW,
        )
    };
    if result != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(stat)
}

/// The kind of `name` in `dir`, the link itself when it is one.
pub(crate) fn kind_at(dir: &OwnedFd, name: &CStr) -> io::Result<libc::mode_t> {
    Ok(stat_at(dir, name)?.st_mode & libc::S_IFMT)
}

/// The target of the link `name` in `dir`, as written.
fn link_target(dir: &OwnedFd, name: &CStr) -> io::Result<Vec<u8>> {
    let mut buffer = vec![0u8; libc::PATH_MAX as usize];
    // SAFETY: the buffer is as long as the length passed.
    let length = unsafe {
        libc::readlinkat(
            dir.as_raw_fd(),
            name.as_ptr(),
            buffer.as_mut_ptr().cast(),
            buffer.len(),
        )
    };
    if length < 0 {
        return Err(io::Error::last_os_error());
    }
    buffer.truncate(length as usize);
    Ok(buffer)
}

/// The names in the open folder `dir`: listed through its descriptor, so
/// the listing is of the folder held, not of whatever its path names now.
fn names(dir: &OwnedFd) -> io::Result<Vec<CString>> {
    let listing = std::fs::read_dir(format!("/proc/self/fd/{}", dir.as_raw_fd()))?;
    let mut names = Vec::new();
    for entry in listing {
        let name = entry?.file_name();
        names.push(CString::new(name.as_bytes()).map_err(io::Error::other)?);
    }
    names.sort();
    Ok(names)
}

impl Walk {
    fn over_budget(&self) -> io::Error {
        io::Error::other(format!(
            "the folder holds more than grading copies ({} MiB in {} entries)",
            self.budget.bytes >> 20,
            self.budget.entries
        ))
    }

    /// Copy every entry of the open folder `dir` into `to`, folders at
    /// most `depth` levels deep.
    fn copy_entries(&mut self, dir: &OwnedFd, to: &Path, depth: u32) -> io::Result<()> {
        for name in names(dir)? {
            self.left.entries = match self.left.entries.checked_sub(1) {
                Some(left) => left,
                None => return Err(self.over_budget()),
            };
            let os_name = OsStr::from_bytes(name.as_bytes());
            let target = to.join(os_name);
            let kind = kind_at(dir, &name)?;
            if kind == libc::S_IFDIR {
                let Some(depth) = depth.checked_sub(1) else {
                    return Err(io::Error::other(format!(
                        "the folder nests deeper than grading copies ({MAX_DEPTH} levels)"
                    )));
                };
                let inner = open_at(dir.as_raw_fd(), os_name, libc::O_DIRECTORY)?;
                match std::fs::create_dir(&target) {
                    Err(error) if error.kind() == io::ErrorKind::AlreadyExists => {}
                    other => other?,
                }
                self.copy_entries(&inner, &target, depth)?;
            } else if kind == libc::S_IFREG {
                // No program starts while the copy is open for writing.
                let _writing = crate::spawning::SPAWNING
                    .read()
                    .unwrap_or_else(|poisoned| poisoned.into_inner());
                let Some(mut source) = open_regular_at(dir, os_name)? else {
                    // Swapped for something else since it was looked at:
                    // left out, as anything but a file, folder or link is.
                    continue;
                };
                let _ = std::fs::remove_file(&target);
                let mut out = File::create_new(&target)?;
                let limit = self.left.bytes + 1;
                let copied = io::copy(&mut io::Read::take(&mut source, limit), &mut out)?;
                self.left.bytes = match self.left.bytes.checked_sub(copied) {
                    Some(left) => left,
                    None => return Err(self.over_budget()),
                };
                // The same permissions, so a program stays runnable; never
                // set-user-ID, set-group-ID or sticky.
                let mode = source.metadata()?.permissions().mode() & 0o777;
                out.set_permissions(std::fs::Permissions::from_mode(mode))?;
            } else if kind == libc::S_IFLNK {
                let _ = std::fs::remove_file(&target);
                std::os::unix::fs::symlink(OsStr::from_bytes(&link_target(dir, &name)?), &target)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_folders_and_links_are_copied_and_no_link_is_followed() {
        let dir = tempfile::tempdir().unwrap();
        let from = dir.path().join("from");
        std::fs::create_dir_all(from.join("sub")).unwrap();
        std::fs::write(from.join("tracer.py"), "print(1)\n").unwrap();
        std::fs::write(from.join("sub/run"), "#!/bin/sh\n").unwrap();
        std::fs::set_permissions(
            from.join("sub/run"),
            std::fs::Permissions::from_mode(0o6755),
        )
        .unwrap();
        let secret = dir.path().join("secret");
        std::fs::create_dir(&secret).unwrap();
        std::fs::write(secret.join("key"), "not for students").unwrap();
        std::os::unix::fs::symlink(&secret, from.join("linked")).unwrap();
        std::os::unix::fs::symlink(secret.join("key"), from.join("key")).unwrap();

        let to = dir.path().join("to");
        std::fs::create_dir(&to).unwrap();
        copy_folder(&from, &to, STUDENT_FOLDER).unwrap();
        assert_eq!(
            std::fs::read_to_string(to.join("tracer.py")).unwrap(),
            "print(1)\n"
        );
        let mode = std::fs::metadata(to.join("sub/run"))
            .unwrap()
            .permissions()
            .mode();
        assert_eq!(mode & 0o7777, 0o755, "runnable, never set-user-ID");
        for link in ["linked", "key"] {
            let meta = std::fs::symlink_metadata(to.join(link)).unwrap();
            assert!(meta.file_type().is_symlink(), "{link} was followed");
        }
    }

    #[test]
    fn a_folder_over_the_budget_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let from = dir.path().join("from");
        std::fs::create_dir(&from).unwrap();
        std::fs::write(from.join("big"), vec![0u8; 2048]).unwrap();
        let to = dir.path().join("to");
        std::fs::create_dir(&to).unwrap();
        let small = Budget {
            bytes: 1024,
            entries: 10,
        };
        let error = copy_folder(&from, &to, small).unwrap_err();
        assert!(
            error.to_string().contains("more than grading copies"),
            "{error}"
        );
        let few = Budget {
            bytes: 1 << 20,
            entries: 0,
        };
        assert!(copy_folder(&from, &to, few).is_err());
    }

    #[test]
    fn a_link_given_as_the_folder_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real");
        std::fs::create_dir(&real).unwrap();
        let link = dir.path().join("link");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let to = dir.path().join("to");
        std::fs::create_dir(&to).unwrap();
        assert!(copy_folder(&link, &to, STUDENT_FOLDER).is_err());
    }

    #[test]
    fn a_file_swapped_for_a_fifo_or_a_link_is_not_opened_and_nothing_blocks() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = std::ffi::CString::new(dir.path().join("fifo").as_os_str().as_bytes()).unwrap();
        // SAFETY: a NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o644) }, 0);
        std::os::unix::fs::symlink("/etc/passwd", dir.path().join("link")).unwrap();
        std::fs::write(dir.path().join("file"), "x").unwrap();
        let folder = open_at(libc::AT_FDCWD, dir.path().as_os_str(), libc::O_DIRECTORY).unwrap();
        assert!(open_regular_at(&folder, OsStr::new("fifo"))
            .unwrap()
            .is_none());
        assert!(open_regular_at(&folder, OsStr::new("link"))
            .unwrap()
            .is_none());
        assert!(open_regular_at(&folder, OsStr::new("file"))
            .unwrap()
            .is_some());
    }
}
