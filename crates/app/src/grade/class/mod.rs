//! The class overview: the report of each student sits in a folder of
//! the class's report folder named after the student, and [`merge`] reads
//! each one's `summary.json` and writes `class.html` ([`html`]: students
//! × scenes, each cell a status linked to the scene in that student's
//! report) and `class.csv` ([`table`]: the scores). `grade --class`
//! grades into that layout and then merges; `grade --merge` merges
//! reports made elsewhere (one machine or task per student), so both give
//! the same overview from the same files.

pub mod html;
pub mod table;

use std::collections::BTreeSet;
use std::ffi::OsString;
use std::os::unix::ffi::OsStrExt;
use std::path::Path;

use miette::Diagnostic;
use serde::Deserialize;

use super::Status;
use raytracer_scene::diagnostic::FileError;

/// The name of the overview page.
pub const HTML: &str = "class.html";
/// The name of the scores table.
pub const CSV: &str = "class.csv";

/// What the overview needs of a summary.json.
#[derive(Debug, Deserialize)]
pub struct StudentSummary {
    pub score: f64,
    pub max_score: f64,
    pub build: Option<Build>,
    pub scenes: Vec<SceneSummary>,
}

/// What the overview needs of summary.json's `build`.
#[derive(Debug, Deserialize)]
pub struct Build {
    pub ok: bool,
    pub reason: Option<String>,
}

/// What the overview needs of a scene of summary.json.
#[derive(Debug, Deserialize)]
pub struct SceneSummary {
    pub scene: String,
    pub status: Status,
    pub reason: Option<String>,
    pub score: f64,
    /// A robustness scene (judged for no points unless the suite opts in).
    #[serde(default)]
    pub robustness: bool,
}

/// One student: the name of their report's folder and their summary.
#[derive(Debug)]
pub struct Student {
    pub folder: OsString,
    pub summary: StudentSummary,
}

/// The class report's own files, whose names no student's report folder
/// may take.
const RESERVED: [&str; 2] = [HTML, CSV];

/// The folder of a student's report in the class's: the student's folder
/// name, with a `~` added where that name, less any `~` it ends with, is
/// one of the class report's files (`class.csv`, `class.csv~`), so no
/// student's report takes a report file's place and no two share one.
pub fn report_folder(student: &std::ffi::OsStr) -> OsString {
    let bytes = student.as_bytes();
    let base = bytes.strip_suffix(b"~").map_or(bytes, |_| {
        let end = bytes.iter().rposition(|&b| b != b'~').map_or(0, |i| i + 1);
        &bytes[..end]
    });
    let mut folder = student.to_os_string();
    if RESERVED.iter().any(|name| name.as_bytes() == base) {
        folder.push("~");
    }
    folder
}

/// The student a report folder is of: [`report_folder`] undone.
fn student_of(folder: &std::ffi::OsStr) -> OsString {
    let bytes = folder.as_bytes();
    match bytes.strip_suffix(b"~") {
        Some(less) if report_folder(std::ffi::OsStr::from_bytes(less)) == folder => {
            std::ffi::OsStr::from_bytes(less).to_os_string()
        }
        _ => folder.to_os_string(),
    }
}

impl Student {
    /// The name to show: the student's folder's, any byte that is not
    /// UTF-8 replaced.
    pub fn name(&self) -> String {
        student_of(&self.folder).to_string_lossy().into_owned()
    }

    /// The scene `name` of this student, if they were graded on it.
    pub fn scene(&self, name: &str) -> Option<&SceneSummary> {
        self.summary.scenes.iter().find(|s| s.scene == name)
    }
}

/// The class: its students in the order of their folders' names, and
/// every scene any of them was graded on, in the order of their names.
#[derive(Debug)]
pub struct Class {
    pub students: Vec<Student>,
    pub scenes: Vec<String>,
}

/// Why the overview cannot be made.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum ClassError {
    #[error(transparent)]
    #[diagnostic(
        code(grade::merge),
        help("each folder in the class's report folder is one student's report, made by `grade --student` or `--class`; grade that student again, or move the folder out")
    )]
    Read(FileError),

    #[error("`{path}` is not a summary of `raytracer grade`: {reason}")]
    #[diagnostic(code(grade::merge))]
    Parse { path: String, reason: String },

    #[error("no student reports in `{path}`")]
    #[diagnostic(
        code(grade::merge),
        help("`--merge REPORT` reads REPORT/<student>/summary.json for each student")
    )]
    Empty { path: String },

    #[error(transparent)]
    #[diagnostic(code(io::grade))]
    Write(FileError),
}

/// Read every student's summary in `report`: each folder in it whose name
/// does not start with `.`.
pub fn read(report: &Path) -> Result<Class, ClassError> {
    let read_error =
        |path: &Path, error: std::io::Error| ClassError::Read(FileError::new("read", path, &error));
    let mut folders: Vec<OsString> = std::fs::read_dir(report)
        .map_err(|error| read_error(report, error))?
        .flatten()
        .filter(|entry| entry.path().is_dir())
        .map(|entry| entry.file_name())
        .filter(|name| !name.to_string_lossy().starts_with('.'))
        .collect();
    folders.sort();
    if folders.is_empty() {
        return Err(ClassError::Empty {
            path: report.display().to_string(),
        });
    }
    let mut students = Vec::with_capacity(folders.len());
    for folder in folders {
        let path = report.join(&folder).join("summary.json");
        let bytes = std::fs::read(&path).map_err(|error| read_error(&path, error))?;
        let summary = serde_json::from_slice(&bytes).map_err(|error| ClassError::Parse {
            path: path.display().to_string(),
            reason: error.to_string(),
        })?;
        students.push(Student { folder, summary });
    }
    let scenes: BTreeSet<&str> = students
        .iter()
        .flat_map(|s| s.summary.scenes.iter().map(|scene| scene.scene.as_str()))
        .collect();
    let scenes = scenes.into_iter().map(String::from).collect();
    Ok(Class { students, scenes })
}

/// Read the students' summaries in `report` and write `class.html` and
/// `class.csv` there.
pub fn merge(report: &Path) -> Result<Class, ClassError> {
    let class = read(report)?;
    let files = [(HTML, html::page(&class)), (CSV, table::csv(&class))];
    for (name, text) in files {
        let path = report.join(name);
        raytracer_render::output::write_atomically(&path, |out| out.write_all(text.as_bytes()))
            .map_err(FileError::writing(&path))
            .map_err(ClassError::Write)?;
    }
    Ok(class)
}

/// The status name of a scene, as summary.json spells it.
fn status_name(status: Status) -> &'static str {
    super::report::status_name(status)
}

#[cfg(test)]
mod tests {
    use super::{report_folder, student_of};
    use std::ffi::OsStr;

    #[test]
    fn a_student_named_as_a_report_file_gets_a_folder_of_its_own() {
        for (student, folder) in [
            ("alice", "alice"),
            ("class.csv", "class.csv~"),
            ("class.html", "class.html~"),
            ("class.csv~", "class.csv~~"),
            ("alice~", "alice~"),
        ] {
            assert_eq!(report_folder(OsStr::new(student)), OsStr::new(folder));
            assert_eq!(student_of(OsStr::new(folder)), OsStr::new(student));
        }
    }
}
