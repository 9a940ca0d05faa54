//! How failures from outside (the OS, decoders, parsers) are worded, and
//! the one shape of a failed file operation: what was being done, to which
//! path, and why, in the user's words.
//!
//! Every command that reads or writes files reports an I/O failure as a
//! [`FileError`] ("cannot read scene `a.txt`: no such file"); the enum
//! variant that carries it gives the diagnostic code and any help, so the
//! wording of reasons lives here once. [`io_reason`] turns an
//! `std::io::Error` into those words: the common kinds by name, anything
//! else as the system says it, lowercase, without the temporary file names
//! some wrappers append. A write into a folder that does not exist names
//! the folder instead, since that is what the user can fix.

use std::path::Path;

/// A file (or folder) that could not be read, written or watched.
#[derive(Debug, thiserror::Error)]
#[error("cannot {action} `{path}`: {reason}")]
pub struct FileError {
    /// What was being done, as a verb phrase before the path: `read`,
    /// `read scene`, `write statistics to`.
    action: &'static str,
    path: String,
    reason: String,
}

impl FileError {
    /// `action` on `path` failed with `error`.
    pub fn new(action: &'static str, path: &Path, error: &std::io::Error) -> FileError {
        FileError::with_reason(action, path, io_reason(error))
    }

    /// `action` on `path` failed for a reason already in words (a watcher's
    /// or decoder's message).
    pub fn with_reason(action: &'static str, path: &Path, reason: String) -> FileError {
        FileError {
            action,
            path: path.display().to_string(),
            reason,
        }
    }

    /// The error of reading `path`, for `map_err`.
    pub fn reading(path: &Path) -> impl Fn(std::io::Error) -> FileError + '_ {
        move |error| FileError::new("read", path, &error)
    }

    /// The error of writing `path`, for `map_err`: a missing parent folder
    /// is named as the reason, whatever the system said.
    pub fn writing(path: &Path) -> impl Fn(std::io::Error) -> FileError + '_ {
        move |error| FileError::written("write", path, &error)
    }

    /// `action`, a kind of write, on `path` failed with `error`; see
    /// [`FileError::writing`].
    pub fn written(action: &'static str, path: &Path, error: &std::io::Error) -> FileError {
        let folder = path.parent().filter(|p| !p.as_os_str().is_empty());
        match folder {
            Some(folder) if !folder.is_dir() => FileError::with_reason(
                action,
                path,
                format!("the folder `{}` does not exist", folder.display()),
            ),
            _ => FileError::new(action, path, error),
        }
    }

    /// The path, as shown in the message.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// Why it failed, in words.
    pub fn reason(&self) -> &str {
        &self.reason
    }
}

/// OS, decoder and parser messages start with a capital; diagnostics do not.
pub fn lowercase_first(message: &str) -> String {
    let mut chars = message.chars();
    match chars.next() {
        Some(first) => first.to_lowercase().chain(chars).collect(),
        None => String::new(),
    }
}

/// An I/O error as a diagnostic's reason, worded the same for a scene, a
/// texture or an output: "no such file" and "permission denied" for the
/// common two, else the system's message, lowercase and without the paths
/// some wrappers append (a temporary file's name is no help to the user).
pub fn io_reason(error: &std::io::Error) -> String {
    match error.kind() {
        std::io::ErrorKind::NotFound => return "no such file".to_string(),
        std::io::ErrorKind::PermissionDenied => return "permission denied".to_string(),
        _ => {}
    }
    let message = match error.raw_os_error() {
        Some(code) => std::io::Error::from_raw_os_error(code).to_string(),
        // `tempfile` words its errors `{reason} at path "{temporary file}"`.
        None => {
            let message = error.to_string();
            match message.split_once(" at path \"") {
                Some((reason, _)) => reason.to_string(),
                None => message,
            }
        }
    };
    lowercase_first(&message)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn io_reasons_are_lowercase_without_temporary_paths() {
        let os = std::io::Error::from_raw_os_error(2);
        assert!(
            io_reason(&os).starts_with("no such file"),
            "{}",
            io_reason(&os)
        );
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing");
        let wrapped = tempfile::Builder::new().tempfile_in(&missing).unwrap_err();
        assert!(wrapped.to_string().contains(" at path "), "{wrapped}");
        assert_eq!(io_reason(&wrapped), io_reason(&os));
    }

    #[test]
    fn a_write_into_a_missing_folder_names_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("missing").join("out.json");
        let error = std::fs::write(&target, "x").unwrap_err();
        let message = FileError::writing(&target)(error).to_string();
        assert!(message.starts_with("cannot write `"), "{message}");
        assert!(
            message.ends_with(&format!(
                "the folder `{}` does not exist",
                dir.path().join("missing").display()
            )),
            "{message}"
        );
    }

    #[test]
    fn the_action_reads_before_the_path() {
        let error = std::io::Error::from_raw_os_error(13);
        let message = FileError::new("read scene", Path::new("a.txt"), &error).to_string();
        assert_eq!(message, "cannot read scene `a.txt`: permission denied");
    }
}
