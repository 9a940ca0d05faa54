//! The working folder of a run in a box: a tmpfs of `--disk` MiB and
//! [`INODES`] inodes mounted over the folder the grader prepared, so what
//! the program writes is bounded in bytes and in files, never reaches the
//! grader's disk, and goes with the box.
//!
//! In the box's pid 1 ([`crate::jail`]), before the program starts, the
//! prepared folder (held open from below the mount) is copied into the
//! tmpfs ([`fill`]): folders, regular files and links, following none,
//! each given to the run's user, with no set-user-ID, set-group-ID or
//! sticky bit. After the program has ended and every process of the box
//! is killed, [`keep`] copies back into the prepared folder the one file
//! the grader reads (`{out}`), and only when it is a regular file of the
//! run's user with one name, or a link (copied as one, so the grader
//! refuses it as before); [`full`] says whether the tmpfs had no block
//! or no inode left. All of it runs between fork and exec: system calls
//! only, on buffers of the stack.

use std::io;

use crate::child::check;

/// The inodes of a run's tmpfs: room for a student's whole folder (its
/// copy holds at most 20,000 entries, [`crate::copy::STUDENT_FOLDER`])
/// and a scene's files.
pub(crate) const INODES: u64 = 32_768;

/// How deep [`fill`] goes: deeper than any folder the grader's copy makes
/// ([`crate::copy::MAX_DEPTH`]) inside a scene's path in its suite.
pub(crate) const DEPTH: u32 = crate::copy::MAX_DEPTH + 16;

/// `openat` of `name` in `dir` with `flags`, never following a link.
///
/// # Safety
/// Async-signal-safe; `name` is a C string.
unsafe fn open_under(
    dir: libc::c_int,
    name: *const libc::c_char,
    flags: libc::c_int,
) -> io::Result<libc::c_int> {
    // SAFETY: the caller passes a C string; the descriptor is returned.
    let fd = unsafe {
        libc::openat(
            dir,
            name,
            flags | libc::O_NOFOLLOW | libc::O_CLOEXEC,
            0o600 as libc::c_uint,
        )
    };
    check(fd)?;
    Ok(fd)
}

/// Give the open file `fd` to `owner` (when the grader is root) with the
/// permission bits of `mode`.
///
/// # Safety
/// Async-signal-safe.
pub(crate) unsafe fn give(
    fd: libc::c_int,
    mode: libc::mode_t,
    owner: Option<u32>,
) -> io::Result<()> {
    unsafe {
        if let Some(id) = owner {
            check(libc::fchown(fd, id, id))?;
        }
        check(libc::fchmod(fd, mode & 0o777))
    }
}

/// Copy every entry of the open folder `from` into the open folder `to`,
/// folders at most `depth` levels deep.
///
/// # Safety
/// Async-signal-safe: called between fork and exec.
pub(crate) unsafe fn fill(
    from: libc::c_int,
    to: libc::c_int,
    owner: Option<u32>,
    depth: u32,
) -> io::Result<()> {
    // `getdents64` needs a buffer aligned for `dirent64`.
    let mut buffer = [0u64; 256];
    loop {
        // SAFETY: the buffer is as long as the length passed.
        let read = unsafe {
            libc::syscall(
                libc::SYS_getdents64,
                from,
                buffer.as_mut_ptr(),
                std::mem::size_of_val(&buffer),
            )
        };
        if read < 0 {
            return Err(io::Error::last_os_error());
        }
        if read == 0 {
            return Ok(());
        }
        let mut offset = 0usize;
        while offset < read as usize {
            // SAFETY: the kernel wrote whole entries, each with its length
            // and a NUL-terminated name, up to `read`.
            let (length, name) = unsafe {
                let entry = buffer
                    .as_ptr()
                    .cast::<u8>()
                    .add(offset)
                    .cast::<libc::dirent64>();
                ((*entry).d_reclen, (*entry).d_name.as_ptr())
            };
            offset += usize::from(length);
            // SAFETY: as above, `name` is a C string.
            let bytes = unsafe { std::ffi::CStr::from_ptr(name) }.to_bytes();
            if bytes != b"." && bytes != b".." {
                // SAFETY: async-signal-safe, on a C string.
                unsafe { copy_entry(from, to, name, owner, depth)? };
            }
        }
    }
}

/// Copy the entry `name` of `from` into `to`.
///
/// # Safety
/// Async-signal-safe; `name` is a C string.
unsafe fn copy_entry(
    from: libc::c_int,
    to: libc::c_int,
    name: *const libc::c_char,
    owner: Option<u32>,
    depth: u32,
) -> io::Result<()> {
    unsafe {
        let mut stat: libc::stat = std::mem::zeroed();
        check(libc::fstatat(
            from,
            name,
            &mut stat,
            libc::AT_SYMLINK_NOFOLLOW,
        ))?;
        match stat.st_mode & libc::S_IFMT {
            libc::S_IFDIR => {
                let Some(depth) = depth.checked_sub(1) else {
                    return Err(io::Error::from_raw_os_error(libc::ELOOP));
                };
                check(libc::mkdirat(to, name, 0o700))?;
                let inner_from = open_under(from, name, libc::O_RDONLY | libc::O_DIRECTORY)?;
                let copied =
                    open_under(to, name, libc::O_RDONLY | libc::O_DIRECTORY).and_then(|inner_to| {
                        let done = fill(inner_from, inner_to, owner, depth)
                            .and_then(|()| give(inner_to, stat.st_mode, owner));
                        libc::close(inner_to);
                        done
                    });
                libc::close(inner_from);
                copied
            }
            libc::S_IFREG => {
                let source = open_under(from, name, libc::O_RDONLY | libc::O_NONBLOCK)?;
                let copied = open_under(to, name, libc::O_WRONLY | libc::O_CREAT | libc::O_EXCL)
                    .and_then(|target| {
                        let done = send_all(source, target)
                            .and_then(|()| give(target, stat.st_mode, owner));
                        libc::close(target);
                        done
                    });
                libc::close(source);
                copied
            }
            libc::S_IFLNK => copy_link(from, to, name, owner),
            // A FIFO, a socket or a device is no program's file.
            _ => Ok(()),
        }
    }
}

/// Copy the link `name` of `from` into `to` as a link (its target
/// unread). Apart from [`copy_entry`], so the recursion's frames hold no
/// buffer of a path's length.
///
/// # Safety
/// Async-signal-safe; `name` is a C string.
#[inline(never)]
unsafe fn copy_link(
    from: libc::c_int,
    to: libc::c_int,
    name: *const libc::c_char,
    owner: Option<u32>,
) -> io::Result<()> {
    let mut target = [0u8; libc::PATH_MAX as usize + 1];
    unsafe {
        let length = libc::readlinkat(from, name, target.as_mut_ptr().cast(), target.len() - 1);
        if length < 0 {
            return Err(io::Error::last_os_error());
        }
        target[length as usize] = 0;
        check(libc::symlinkat(target.as_ptr().cast(), to, name))?;
        if let Some(id) = owner {
            check(libc::fchownat(to, name, id, id, libc::AT_SYMLINK_NOFOLLOW))?;
        }
    }
    Ok(())
}

/// Copy the rest of `from` into `to`.
///
/// # Safety
/// Async-signal-safe.
unsafe fn send_all(from: libc::c_int, to: libc::c_int) -> io::Result<()> {
    loop {
        // SAFETY: two descriptors and no offset pointer.
        let sent = unsafe { libc::sendfile(to, from, std::ptr::null_mut(), 1 << 30) };
        match sent {
            0 => return Ok(()),
            1.. => {}
            _ if io::Error::last_os_error().raw_os_error() == Some(libc::EINTR) => {}
            _ => return Err(io::Error::last_os_error()),
        }
    }
}

/// `openat2` of `path` beneath `dir`, refusing a link anywhere on it.
///
/// # Safety
/// Async-signal-safe; `path` is a C string.
unsafe fn open_beneath(
    dir: libc::c_int,
    path: *const libc::c_char,
    flags: libc::c_int,
) -> io::Result<libc::c_int> {
    unsafe {
        let mut how: libc::open_how = std::mem::zeroed();
        how.flags = (flags | libc::O_NOFOLLOW | libc::O_CLOEXEC) as u64;
        how.resolve =
            libc::RESOLVE_BENEATH | libc::RESOLVE_NO_SYMLINKS | libc::RESOLVE_NO_MAGICLINKS;
        let fd = libc::syscall(
            libc::SYS_openat2,
            dir,
            path,
            &how as *const libc::open_how,
            std::mem::size_of::<libc::open_how>(),
        );
        if fd < 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(fd as libc::c_int)
    }
}

/// Copy the entry `name` of the folder `folder` (relative to the tmpfs
/// `scratch`) back into the same folder of the prepared folder `host`:
/// a regular file of `owner` (the run's user; this process's uid when
/// `None`) with one name, or a link as a link. Anything else, or nothing,
/// leaves nothing there.
///
/// # Safety
/// Async-signal-safe; `folder` and `name` are C strings.
pub(crate) unsafe fn keep(
    scratch: libc::c_int,
    host: libc::c_int,
    folder: *const libc::c_char,
    name: *const libc::c_char,
    owner: Option<u32>,
) -> io::Result<()> {
    unsafe {
        let to = open_beneath(host, folder, libc::O_RDONLY | libc::O_DIRECTORY)?;
        if libc::unlinkat(to, name, 0) == -1 && *libc::__errno_location() != libc::ENOENT {
            let error = io::Error::last_os_error();
            libc::close(to);
            return Err(error);
        }
        let kept = match open_beneath(scratch, folder, libc::O_PATH | libc::O_DIRECTORY) {
            Ok(from) => {
                let kept = keep_entry(from, to, name, owner);
                libc::close(from);
                kept
            }
            Err(_) => Ok(()),
        };
        libc::close(to);
        kept
    }
}

/// [`keep`]'s copy of `name` from the open folder `from` into `to`.
///
/// # Safety
/// Async-signal-safe; `name` is a C string.
unsafe fn keep_entry(
    from: libc::c_int,
    to: libc::c_int,
    name: *const libc::c_char,
    owner: Option<u32>,
) -> io::Result<()> {
    unsafe {
        let mut stat: libc::stat = std::mem::zeroed();
        if libc::fstatat(from, name, &mut stat, libc::AT_SYMLINK_NOFOLLOW) != 0 {
            return Ok(());
        }
        let user = owner.unwrap_or_else(|| libc::geteuid());
        match stat.st_mode & libc::S_IFMT {
            libc::S_IFLNK => copy_link(from, to, name, owner),
            libc::S_IFREG if stat.st_nlink == 1 && stat.st_uid == user => {
                let source = open_under(from, name, libc::O_RDONLY | libc::O_NONBLOCK)?;
                let mut opened: libc::stat = std::mem::zeroed();
                let same = libc::fstat(source, &mut opened) == 0
                    && (opened.st_dev, opened.st_ino) == (stat.st_dev, stat.st_ino);
                let copied = if same {
                    open_under(to, name, libc::O_WRONLY | libc::O_CREAT | libc::O_EXCL).and_then(
                        |target| {
                            let done = send_all(source, target)
                                .and_then(|()| give(target, stat.st_mode, owner));
                            libc::close(target);
                            done
                        },
                    )
                } else {
                    Ok(())
                };
                libc::close(source);
                copied
            }
            _ => Ok(()),
        }
    }
}

/// Whether the tmpfs open at `scratch` has no block or no inode left.
///
/// # Safety
/// Async-signal-safe.
pub(crate) unsafe fn full(scratch: libc::c_int) -> bool {
    unsafe {
        let mut stat: libc::statfs = std::mem::zeroed();
        libc::fstatfs(scratch, &mut stat) == 0 && (stat.f_bavail == 0 || stat.f_ffree == 0)
    }
}
