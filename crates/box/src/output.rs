//! Reading a file that a student's program could write (its image,
//! `{out}`), or that a program run as the grader's uid could have
//! replaced, safely and within a budget.
//!
//! The grader never follows a link to such a file: the whole path is
//! resolved with `openat2(RESOLVE_NO_SYMLINKS)` (a link in any component
//! fails), the last component with `O_NOFOLLOW | O_NONBLOCK` (a FIFO
//! cannot block), and what was opened must be a regular file with one
//! name, owned by the owner of the folder it is in (the user the program
//! ran as): a hard link to a file of someone else's is refused, not
//! read. The file's size is checked against the caller's byte budget
//! before anything is read, and the read stops one byte past it.

use std::fs::File;
use std::io::{self, Read as _};
use std::os::fd::{FromRawFd, OwnedFd};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::MetadataExt;
use std::path::Path;

/// Why a program's output was not read.
#[derive(Debug)]
pub enum Refused {
    /// No file at that path, or no folder.
    Missing,
    /// Its folder cannot be opened.
    Folder(io::Error),
    /// The file, or a folder on its path, is a symbolic link.
    Link,
    /// Not a regular file (a FIFO, a device, a folder).
    NotRegular,
    /// Another owner than its folder's, or more than one name.
    Foreign,
    /// Larger than the budget on disk.
    TooLarge { bytes: u64, budget: u64 },
    /// It grew past the budget while it was read.
    Grew,
    /// Opening or reading it failed.
    Io(io::Error),
}

/// Open `path` for reading without following a link anywhere on it.
pub fn open_no_links(path: &Path) -> io::Result<File> {
    let name = std::ffi::CString::new(path.as_os_str().as_bytes())
        .map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))?;
    // SAFETY: `open_how` is plain integers, for which zero is valid.
    let mut how: libc::open_how = unsafe { std::mem::zeroed() };
    how.flags = (libc::O_RDONLY | libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_CLOEXEC) as u64;
    how.resolve = libc::RESOLVE_NO_SYMLINKS | libc::RESOLVE_NO_MAGICLINKS;
    // SAFETY: `name` is a NUL-terminated string and `how` a valid
    // `open_how` of the size passed; the returned descriptor is ours.
    let fd = unsafe {
        libc::syscall(
            libc::SYS_openat2,
            libc::AT_FDCWD,
            name.as_ptr(),
            &how as *const libc::open_how,
            std::mem::size_of::<libc::open_how>(),
        )
    };
    if fd < 0 {
        return Err(io::Error::last_os_error());
    }
    // SAFETY: a descriptor just opened, owned by nothing else.
    Ok(File::from(unsafe { OwnedFd::from_raw_fd(fd as i32) }))
}

/// The bytes of the program's output at `path`, at most `budget` of
/// them, under the checks of the module's header.
pub fn read_output(path: &Path, budget: u64) -> Result<Vec<u8>, Refused> {
    let missing = |error: &io::Error| error.raw_os_error() == Some(libc::ENOENT);
    let folder_owner = match path.parent().map(open_no_links) {
        Some(Ok(folder)) => folder.metadata().map_err(Refused::Io)?.uid(),
        Some(Err(error)) if missing(&error) => return Err(Refused::Missing),
        Some(Err(error)) => return Err(Refused::Folder(error)),
        None => return Err(Refused::Missing),
    };
    let mut file = match open_no_links(path) {
        Ok(file) => file,
        Err(error) if missing(&error) => return Err(Refused::Missing),
        Err(error) if error.raw_os_error() == Some(libc::ELOOP) => return Err(Refused::Link),
        Err(error) => return Err(Refused::Io(error)),
    };
    let meta = file.metadata().map_err(Refused::Io)?;
    if !meta.is_file() {
        return Err(Refused::NotRegular);
    }
    if meta.nlink() != 1 || meta.uid() != folder_owner {
        return Err(Refused::Foreign);
    }
    if meta.len() > budget {
        return Err(Refused::TooLarge {
            bytes: meta.len(),
            budget,
        });
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    (&mut file)
        .take(budget + 1)
        .read_to_end(&mut bytes)
        .map_err(Refused::Io)?;
    if bytes.len() as u64 > budget {
        return Err(Refused::Grew);
    }
    Ok(bytes)
}

/// The bytes of the grader's own private file at `path` (at most
/// `budget`): a regular file of this process's uid, with one name,
/// closed to everyone else, reached without a link; `None` otherwise.
pub fn read_private(path: &Path, budget: u64) -> Option<Vec<u8>> {
    let mut file = open_no_links(path).ok()?;
    let meta = file.metadata().ok()?;
    let mine = meta.uid() == crate::effective_uid();
    if !meta.is_file() || !mine || meta.nlink() != 1 || meta.mode() & 0o077 != 0 {
        return None;
    }
    let mut bytes = Vec::new();
    file.by_ref().take(budget).read_to_end(&mut bytes).ok()?;
    Some(bytes)
}
