//! The folders a run works in: made where no other account can reach
//! them, given to the run's user from the inside out, and removed by a
//! walk the run's program cannot stop.
//!
//! Each folder of a run (a student's prepared copy, a scene's working
//! folder) is `run` inside a folder of its own, `raytracer-grade-*` in
//! the temporary folder ([`private_folder`]), which is never given to the
//! student: root's (0700) as root, the grader's own (0700) as an ordinary
//! user. The program may open its own folder (`chmod 755`) and make a
//! set-user-ID file there, but no other account can pass the parent to
//! run it. A root grader's program without a box reaches its folder by
//! path as the run's uid, so there the parent is 0710 of the run's group,
//! which no account has (a leased id names no group, [`crate::uids`]).
//!
//! [`remove_tree`] removes a folder whatever a program left in it: the
//! walk holds two descriptors at most (a folder and, on the way up, its
//! parent, found again through `..` and checked by device and inode),
//! never a stack frame per level, so 30,000 nested folders take no more
//! stack than one; each folder is given back to the grader (0700) through
//! its descriptor before its entries are removed, so a `chmod 000` folder
//! goes too; no link is followed. What still cannot be removed is counted
//! and returned as an error for the caller to report.

use std::ffi::{CStr, CString, OsStr};
use std::fs::Permissions;
use std::io;
use std::os::fd::{AsRawFd, OwnedFd};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::{DirBuilderExt, PermissionsExt};
use std::path::{Path, PathBuf};

/// A run's folder, `path`, alone inside `parent`, a folder only the
/// grader may enter. Removed with its parent when dropped; [`RunFolder::remove`]
/// says what could not be removed.
#[derive(Debug)]
pub struct RunFolder {
    parent: PathBuf,
    path: PathBuf,
    removed: bool,
}

/// A fresh run folder: `raytracer-grade-*/run` in the temporary folder,
/// both 0700, the grader's.
pub fn private_folder() -> io::Result<RunFolder> {
    let parent = tempfile::Builder::new()
        .prefix("raytracer-grade-")
        .permissions(Permissions::from_mode(0o700))
        .tempdir()?
        .keep();
    let made = (|| {
        let path = parent.join("run");
        std::fs::DirBuilder::new().mode(0o700).create(&path)?;
        std::fs::canonicalize(path)
    })();
    match made {
        Ok(path) => Ok(RunFolder {
            parent,
            path,
            removed: false,
        }),
        Err(error) => {
            let _ = remove_tree(&parent);
            Err(error)
        }
    }
}

impl RunFolder {
    /// The run's folder (canonical, made while it was the grader's alone).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Give the run's folder, and everything in it, to user and group
    /// `id` ([`give`]). When the program will reach it by path outside a
    /// box (`by_path`), the parent is opened to group `id` alone (0710).
    pub fn give(&self, id: u32, by_path: bool) -> io::Result<()> {
        give(&self.path, id)?;
        if by_path {
            std::os::unix::fs::lchown(&self.parent, None, Some(id))?;
            std::fs::set_permissions(&self.parent, Permissions::from_mode(0o710))?;
        }
        Ok(())
    }

    /// Remove the folder and its parent; an error says what is left.
    pub fn remove(mut self) -> io::Result<()> {
        self.removed = true;
        remove_tree(&self.parent)
    }
}

impl Drop for RunFolder {
    fn drop(&mut self) {
        if !self.removed {
            let _ = remove_tree(&self.parent);
        }
    }
}

/// Give `dir`, and everything under it, to user and group `id`: the
/// entries first, while `dir` is still the grader's own and closed to
/// everyone else, and `dir` itself last. No link is followed: an entry is
/// given as what it is, and a folder is walked only when it is one. The
/// walk recurses per level: what it walks is a copy ([`crate::copy`]),
/// whose depth is bounded.
pub fn give(dir: &Path, id: u32) -> io::Result<()> {
    give_entries(dir, id)?;
    std::os::unix::fs::lchown(dir, Some(id), Some(id))
}

/// Give everything under the folder `dir` to `id`, deepest first.
fn give_entries(dir: &Path, id: u32) -> io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let path = entry.path();
        if entry.file_type()?.is_dir() {
            give_entries(&path, id)?;
        }
        std::os::unix::fs::lchown(&path, Some(id), Some(id))?;
    }
    Ok(())
}

/// A folder being removed: its name in its parent, its device and inode
/// (to know its parent again on the way up), and the entries of it that
/// could not be removed.
struct Level {
    name: CString,
    id: (u64, u64),
    left: Vec<CString>,
}

/// Remove `path` and everything under it, without a frame per level and
/// without following a link (module header). `Ok` when nothing is left.
pub fn remove_tree(path: &Path) -> io::Result<()> {
    let (Some(parent), Some(name)) = (path.parent(), path.file_name()) else {
        return Err(io::Error::from(io::ErrorKind::InvalidInput));
    };
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    let top = open_at(libc::AT_FDCWD, parent.as_os_str(), libc::O_RDONLY)?;
    let name = c_name(name)?;
    match unlink_at(&top, &name, 0) {
        Ok(()) => return Ok(()),
        Err(error) if error.raw_os_error() == Some(libc::ENOENT) => return Ok(()),
        Err(error) if !is_folder_error(&error) => return Err(error),
        Err(_) => {}
    }
    let mut current = open_folder(&top, &name)?;
    let mut levels = vec![Level {
        name,
        id: id_of(&current)?,
        left: Vec::new(),
    }];
    let mut left = 0u64;
    loop {
        let level = levels.last_mut().expect("a level while walking");
        if let Some(inner) = next_folder(&current, &mut level.left, &mut left)? {
            match open_folder(&current, &inner).and_then(|fd| Ok((id_of(&fd)?, fd))) {
                Ok((id, fd)) => {
                    current = fd;
                    levels.push(Level {
                        name: inner,
                        id,
                        left: Vec::new(),
                    });
                }
                Err(_) => {
                    left += 1;
                    level.left.push(inner);
                }
            }
            continue;
        }
        // `current` holds nothing more that can go: go up and remove it.
        let done = levels.pop().expect("the level just walked");
        current = match levels.last() {
            None => open_at(top.as_raw_fd(), OsStr::new("."), libc::O_RDONLY)?,
            Some(up) => {
                let parent = open_at(current.as_raw_fd(), OsStr::new(".."), libc::O_RDONLY)?;
                if id_of(&parent)? != up.id {
                    return Err(io::Error::other(
                        "a folder was moved while it was being removed",
                    ));
                }
                parent
            }
        };
        let removed =
            done.left.is_empty() && unlink_at(&current, &done.name, libc::AT_REMOVEDIR).is_ok();
        if !removed {
            left += 1;
            if let Some(up) = levels.last_mut() {
                up.left.push(done.name);
            }
        }
        if levels.is_empty() {
            break;
        }
    }
    if left == 0 {
        Ok(())
    } else {
        Err(io::Error::other(format!(
            "{left} of its entries could not be removed"
        )))
    }
}

/// Whether `unlinkat` without `AT_REMOVEDIR` failed because the entry is
/// a folder (`EISDIR` on Linux; `EPERM` where POSIX allows it).
fn is_folder_error(error: &io::Error) -> bool {
    matches!(error.raw_os_error(), Some(libc::EISDIR | libc::EPERM))
}

/// Remove every entry of the open folder `dir` that is not a folder, and
/// return the name of the first folder found, skipping the names in
/// `skip` (entries that could not be removed, counted in `left`).
fn next_folder(
    dir: &OwnedFd,
    skip: &mut Vec<CString>,
    left: &mut u64,
) -> io::Result<Option<CString>> {
    // A descriptor of its own, so each listing starts at the beginning.
    let listing = open_at(dir.as_raw_fd(), OsStr::new("."), libc::O_RDONLY)?;
    // SAFETY: `fdopendir` takes ownership of the fresh descriptor.
    let stream = unsafe { libc::fdopendir(listing.as_raw_fd()) };
    if stream.is_null() {
        return Err(io::Error::last_os_error());
    }
    std::mem::forget(listing);
    let mut found = None;
    loop {
        // SAFETY: `stream` is an open directory stream.
        let entry = unsafe { libc::readdir(stream) };
        if entry.is_null() {
            break;
        }
        // SAFETY: `d_name` of an entry `readdir` returned is a C string.
        let name = unsafe { CStr::from_ptr((*entry).d_name.as_ptr()) };
        if matches!(name.to_bytes(), b"." | b"..") || skip.iter().any(|s| s.as_c_str() == name) {
            continue;
        }
        match unlink_at(dir, name, 0) {
            Ok(()) => {}
            Err(error) if error.raw_os_error() == Some(libc::ENOENT) => {}
            Err(error) if is_folder_error(&error) && is_folder(dir, name) => {
                found = Some(name.to_owned());
                break;
            }
            Err(_) => {
                *left += 1;
                skip.push(name.to_owned());
            }
        }
    }
    // SAFETY: closing the stream `fdopendir` made (and its descriptor).
    unsafe { libc::closedir(stream) };
    Ok(found)
}

/// Whether `name` in `dir` is a folder, not following a link.
fn is_folder(dir: &OwnedFd, name: &CStr) -> bool {
    crate::copy::kind_at(dir, name).is_ok_and(|kind| kind == libc::S_IFDIR)
}

/// Open the folder `name` in `dir` for listing, not following a link,
/// after giving it back to the grader (0700) through a descriptor of it.
fn open_folder(dir: &OwnedFd, name: &CStr) -> io::Result<OwnedFd> {
    let place = open_at(
        dir.as_raw_fd(),
        OsStr::from_bytes(name.to_bytes()),
        libc::O_PATH | libc::O_DIRECTORY,
    )?;
    let through = format!("/proc/self/fd/{}", place.as_raw_fd());
    // Root may list any folder; the grader's own is only mode away.
    let _ = std::fs::set_permissions(through, Permissions::from_mode(0o700));
    open_at(place.as_raw_fd(), OsStr::new("."), libc::O_RDONLY)
}

/// `openat` of a folder, with `O_NOFOLLOW | O_CLOEXEC | O_DIRECTORY` and
/// `flags` ([`crate::copy::open_at`]).
fn open_at(dir: libc::c_int, name: &OsStr, flags: libc::c_int) -> io::Result<OwnedFd> {
    crate::copy::open_at(dir, name, flags | libc::O_DIRECTORY)
}

/// `unlinkat(dir, name, flags)`.
fn unlink_at(dir: &OwnedFd, name: &CStr, flags: libc::c_int) -> io::Result<()> {
    // SAFETY: a valid descriptor and C string.
    if unsafe { libc::unlinkat(dir.as_raw_fd(), name.as_ptr(), flags) } == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

/// The device and inode of an open file.
fn id_of(fd: &OwnedFd) -> io::Result<(u64, u64)> {
    // SAFETY: `stat` is plain data, filled by the call.
    let mut stat: libc::stat = unsafe { std::mem::zeroed() };
    // SAFETY: a valid descriptor and out pointer.
    if unsafe { libc::fstat(fd.as_raw_fd(), &mut stat) } != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok((stat.st_dev, stat.st_ino))
}

fn c_name(name: &OsStr) -> io::Result<CString> {
    CString::new(name.as_bytes()).map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_closed_and_linked_folders_are_removed_and_no_link_is_followed() {
        let dir = tempfile::tempdir().unwrap();
        let outside = dir.path().join("outside");
        std::fs::create_dir(&outside).unwrap();
        std::fs::write(outside.join("kept"), "").unwrap();
        let tree = dir.path().join("tree");
        std::fs::create_dir(&tree).unwrap();
        let mut current = open_at(libc::AT_FDCWD, tree.as_os_str(), libc::O_RDONLY).unwrap();
        for _ in 0..5_000 {
            // SAFETY: a valid descriptor and C string.
            assert_eq!(
                unsafe { libc::mkdirat(current.as_raw_fd(), c"d".as_ptr(), 0o755) },
                0
            );
            current = open_at(current.as_raw_fd(), OsStr::new("d"), libc::O_RDONLY).unwrap();
        }
        let deepest = format!("/proc/self/fd/{}", current.as_raw_fd());
        std::fs::write(Path::new(&deepest).join("file"), "").unwrap();
        std::os::unix::fs::symlink(&outside, Path::new(&deepest).join("link")).unwrap();
        let closed = tree.join("closed");
        std::fs::create_dir(&closed).unwrap();
        std::fs::write(closed.join("file"), "").unwrap();
        std::fs::set_permissions(&closed, Permissions::from_mode(0o000)).unwrap();
        drop(current);
        // On a thread with a small stack: nothing recurses per level.
        let removing = tree.clone();
        std::thread::Builder::new()
            .stack_size(64 << 10)
            .spawn(move || remove_tree(&removing))
            .unwrap()
            .join()
            .unwrap()
            .unwrap();
        assert!(!tree.exists());
        assert!(outside.join("kept").exists());
    }
}
