//! A student's folder, for `grade --student` and `grade --class`:
//! `tracer.txt` holds the command that runs the student's tracer (one
//! line with `{scene}` and `{out}`, split into words like `--tracer`,
//! never run through a shell), and an optional `build.txt` the command
//! that builds it. In both files, blank lines and lines starting with `#`
//! are skipped. A class is a folder of such folders, one per student, each
//! named after its student; folders whose name starts with `.` (and links)
//! are not students.
//!
//! The grader only reads a student's folder, never through a link: it is
//! copied ([`super::copy`]) into a private folder, the build runs there
//! once under the sandbox's limits before any scene (its `HOME` a folder
//! of its own, dropped afterwards), and each scene's working folder
//! starts as a copy of the result, so the program runs beside its own
//! files as it does at home.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use miette::Diagnostic;

use super::report::BuildSummary;
use super::workdir::{Template, TemplateError};
use raytracer_box::copy::{copy_folder, STUDENT_FOLDER};
use raytracer_box::folder::{private_folder, RunFolder};
use raytracer_box::run::run;
use raytracer_box::{Confinement, Share};
use raytracer_scene::diagnostic::FileError;

/// The file that names the tracer's command.
pub const TRACER_FILE: &str = "tracer.txt";
/// The file that names the build command, when there is one.
pub const BUILD_FILE: &str = "build.txt";

/// A student's folder, read.
#[derive(Debug)]
pub struct Student {
    /// The folder's own name: the student's report folder is named so.
    pub name: OsString,
    pub folder: PathBuf,
    /// The command line of `tracer.txt`, as written.
    pub tracer: String,
    pub template: Template,
    /// The command line of `build.txt` and its words.
    pub build: Option<(String, Template)>,
}

/// Why a student's folder cannot be graded.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum StudentError {
    #[error(transparent)]
    #[diagnostic(
        code(grade::student),
        help("a student's folder holds `tracer.txt`, one line such as `./tracer {{scene}} {{out}}`, and optionally `build.txt` (see docs/grading.md)")
    )]
    Read(FileError),

    #[error("`{path}`: {source}")]
    #[diagnostic(
        code(grade::student),
        help("write the command on one line, e.g. `python3 tracer.py {{scene}} {{out}}`")
    )]
    Command { path: String, source: TemplateError },

    #[error("`{path}` holds {lines} command lines; expected one")]
    #[diagnostic(
        code(grade::student),
        help("no shell runs the command: put several steps in a script and name the script")
    )]
    Lines { path: String, lines: usize },

    #[error("no student folders in `{path}`")]
    #[diagnostic(
        code(grade::student),
        help("`--class DIR` grades each folder in DIR, one per student, named after the student")
    )]
    NoStudents { path: String },
}

impl Student {
    /// Read the student folder `folder`.
    pub fn read(folder: &Path) -> Result<Student, StudentError> {
        let tracer = command_line(&folder.join(TRACER_FILE))?;
        let template = parse(&folder.join(TRACER_FILE), &tracer, Template::tracer)?;
        let build_file = folder.join(BUILD_FILE);
        let build = if build_file.symlink_metadata().is_ok() {
            let line = command_line(&build_file)?;
            let template = parse(&build_file, &line, Template::parse)?;
            Some((line, template))
        } else {
            None
        };
        let name = folder
            .file_name()
            .map_or_else(|| OsString::from("student"), OsString::from);
        Ok(Student {
            name,
            folder: folder.to_path_buf(),
            tracer,
            template,
            build,
        })
    }

    /// The folder copied into a private one (given to the sandbox's user)
    /// and built there; the build's summary when there is `build.txt`.
    pub fn prepare(&self, confinement: Confinement) -> std::io::Result<Prepared> {
        let folder = private_folder()?;
        // Canonical while the folder is still the grader's alone: a box
        // binds it by this path.
        let path = folder.path().to_path_buf();
        copy_folder(&self.folder, folder.path(), STUDENT_FOLDER)?;
        if let Some(id) = confinement.user {
            folder.give(id, !confinement.boxed)?;
        }
        let build = self.build(&path, confinement)?;
        Ok(Prepared { folder, build })
    }

    /// Run the build command, if any, in `folder` under `confinement`,
    /// with a `HOME` of its own, removed afterwards: what a compiler keeps
    /// there (Go's build cache, hundreds of files) is not the student's
    /// program, and would otherwise be copied into every scene's working
    /// folder.
    fn build(
        &self,
        folder: &Path,
        confinement: Confinement,
    ) -> std::io::Result<Option<BuildSummary>> {
        let Some((command, template)) = &self.build else {
            return Ok(None);
        };
        let home = private_folder()?;
        if let Some(id) = confinement.user {
            home.give(id, !confinement.boxed)?;
        }
        let argv = template.argv_as_written();
        let share = Share {
            read_write: vec![folder.to_path_buf(), home.path().to_path_buf()],
            read_only: Vec::new(),
            scratch: None,
            home: Some(home.path().to_path_buf()),
        };
        let run = run(&argv, folder, &share, confinement);
        super::remove_reporting(home, "the build's home folder");
        let (exit_code, signal) = super::judge::exit_code_and_signal(&run.ended);
        let failed = super::judge::failure(&run.ended).map(|(_, reason)| reason);
        let reason = match run.disk_full {
            true => Some(super::with_full_disk(failed, confinement.limits.disk)),
            false => failed,
        };
        Ok(Some(BuildSummary {
            command: command.clone(),
            ok: reason.is_none(),
            reason,
            seconds: run.seconds,
            exit_code,
            signal,
            stdout: run.stdout.text(),
            stderr: run.stderr.text(),
        }))
    }
}

/// A student's folder as grading uses it: a private copy, built.
pub struct Prepared {
    /// Each scene's working folder starts as a copy of this one.
    pub folder: RunFolder,
    pub build: Option<BuildSummary>,
}

/// Every student folder in `dir`, read, in the order of their names; the
/// errors of every folder that cannot be read.
pub fn class(dir: &Path) -> Result<Vec<Student>, Vec<StudentError>> {
    let entries = std::fs::read_dir(dir)
        .map_err(|error| vec![StudentError::Read(FileError::new("read", dir, &error))])?;
    // A link is no student's folder: as root, following one a student
    // planted would copy whatever it names into the sandbox.
    let mut folders: Vec<PathBuf> = entries
        .flatten()
        .filter(|entry| !entry.file_name().to_string_lossy().starts_with('.'))
        .filter(|entry| entry.file_type().is_ok_and(|kind| kind.is_dir()))
        .map(|entry| entry.path())
        .collect();
    folders.sort();
    if folders.is_empty() {
        return Err(vec![StudentError::NoStudents {
            path: dir.display().to_string(),
        }]);
    }
    let mut students = Vec::new();
    let mut errors = Vec::new();
    for folder in &folders {
        match Student::read(folder) {
            Ok(student) => students.push(student),
            Err(error) => errors.push(error),
        }
    }
    if errors.is_empty() {
        Ok(students)
    } else {
        Err(errors)
    }
}

/// The one command line of `path`, read without following a link (as
/// root, a link to a file only root may read would show its first line in
/// the report): blank lines and `#` comments skipped.
fn command_line(path: &Path) -> Result<String, StudentError> {
    let read = || {
        use std::io::Read;
        use std::os::unix::fs::OpenOptionsExt;
        let mut text = String::new();
        std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
            .open(path)?
            .take(64 * 1024)
            .read_to_string(&mut text)?;
        Ok(text)
    };
    let text = read().map_err(|error: std::io::Error| {
        StudentError::Read(FileError::new("read", path, &error))
    })?;
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|line| !line.is_empty() && !line.starts_with('#'))
        .collect();
    match lines.as_slice() {
        [] => Err(StudentError::Command {
            path: path.display().to_string(),
            source: TemplateError::Empty,
        }),
        [line] => Ok(line.to_string()),
        _ => Err(StudentError::Lines {
            path: path.display().to_string(),
            lines: lines.len(),
        }),
    }
}

/// The command `line` of the file at `path`, split by `split`.
fn parse(
    path: &Path,
    line: &str,
    split: fn(&str) -> Result<Template, TemplateError>,
) -> Result<Template, StudentError> {
    split(line).map_err(|source| StudentError::Command {
        path: path.display().to_string(),
        source,
    })
}
