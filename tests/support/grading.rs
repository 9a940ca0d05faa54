//! The set-up the grading tests share: a test's folder that anyone may
//! enter, holding a one-scene suite and either a student's script (graded
//! with `grade --tracer`) or student folders (graded with `--student` or
//! `--class`), each run writing a report and a cache of its own per kind
//! of run; the kinds of run (as the tests run, as root, as an ordinary
//! user); the binary where a graded program can run it, and a student's
//! own copy of the renderer.

use std::ffi::OsStr;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

use serde_json::Value;

use super::{bin, is_root, skipped, tool_available, under_ci};

/// A sphere lit from the side, 32 pixels.
pub const BALL: &str = "camera 32\nsphere\n  dimension 1\n  center 0 0 -5\n  color .9 .6 .3\n\
light\n  location 6 4 -3\n  color 1 1 1\n";

/// The binary, where the graded programs (run as `nobody` when the tests
/// run as root) can execute it: in place when every folder above it lets
/// others in, else a copy in the system's temporary folder.
pub fn binary() -> &'static Path {
    static BINARY: OnceLock<PathBuf> = OnceLock::new();
    BINARY.get_or_init(|| {
        let built = PathBuf::from(bin());
        let open = built.ancestors().skip(1).all(|dir| {
            dir.metadata()
                .is_ok_and(|m| m.permissions().mode() & 0o001 != 0)
        });
        if open {
            return built;
        }
        // This process's own copy: another suite running beside this one
        // (or another test process) may be replacing its own meanwhile.
        let copy = std::env::temp_dir().join(format!(
            "raytracer-grade-tests-binary-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_file(&copy);
        std::fs::copy(&built, &copy).unwrap();
        copy
    })
}

/// A copy of the binary as a student's own tracer: the grader's own
/// executable is not in the box a program runs in (a tracer that runs it
/// must not match), while a student may well ship a renderer of its own.
pub fn student_binary() -> &'static Path {
    static COPY: OnceLock<PathBuf> = OnceLock::new();
    COPY.get_or_init(|| {
        let copy = std::env::temp_dir().join(format!(
            "raytracer-grade-tests-student-tracer-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_file(&copy);
        std::fs::copy(bin(), &copy).unwrap();
        std::fs::set_permissions(&copy, std::fs::Permissions::from_mode(0o755)).unwrap();
        copy
    })
}

/// A folder anyone may use (the graded program writes its working folder's
/// name into it).
pub fn open_folder(prefix: &str) -> tempfile::TempDir {
    let dir = tempfile::Builder::new().prefix(prefix).tempdir().unwrap();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o777)).unwrap();
    dir
}

/// Who runs `grade`: as the tests run (root under CI, else their user),
/// what holds for either; as root (CI's kind); and as an ordinary user
/// (`nobody`, through `setpriv`, when the tests run as root).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    Tests,
    Root,
    User,
}

/// The kinds of run an attack is tried in on this machine: root and user
/// as root; as an ordinary user only the user run (CI runs as root, so
/// there it is a failure).
pub fn kinds() -> Vec<Kind> {
    if is_root() {
        if !tool_available(
            "setpriv",
            "the user-run attacks",
            "apt-get install util-linux",
        ) {
            return vec![Kind::Root];
        }
        vec![Kind::Root, Kind::User]
    } else {
        assert!(!under_ci(), "CI runs as root");
        skipped("the root-run attacks: the tests do not run as root");
        vec![Kind::User]
    }
}

/// `grade` for a run of `kind`: a user run as `nobody` through `setpriv`
/// when the tests run as root, else as the tests' own user; diagnostics
/// at their default width (no `$COLUMNS`).
pub fn grader(kind: Kind) -> Command {
    let mut command = if kind == Kind::User && is_root() {
        let mut command = Command::new("setpriv");
        command
            .args(["--reuid=65534", "--regid=65534", "--clear-groups", "--"])
            .arg(binary());
        command
    } else {
        Command::new(binary())
    };
    command.env_remove("COLUMNS");
    command
}

/// A test's folder: a one-scene suite (`suite/ball.txt`), the student's
/// script (`tracer.sh`) when there is one, student folders, and each
/// kind's report and cache; open to `nobody`.
pub struct Case {
    dir: tempfile::TempDir,
    /// Options given to every `--tracer` run that does not give its own.
    defaults: Vec<(&'static str, &'static str)>,
}

impl Case {
    /// A folder named `prefix…` with `scene` as its suite, and no script.
    pub fn suite(prefix: &str, scene: &str) -> Case {
        let dir = open_folder(prefix);
        std::fs::create_dir(dir.path().join("suite")).unwrap();
        std::fs::write(dir.path().join("suite/ball.txt"), scene).unwrap();
        Case {
            dir,
            defaults: vec![("--timeout", "5")],
        }
    }

    /// [`Case::suite`] with the student's script: `script` is the
    /// tracer's body (bash; `$1` the scene, `$2` the image, `$RAYTRACER`
    /// a copy of the renderer the student may ship, `$CASE` this folder).
    pub fn new(prefix: &str, scene: &str, script: &str) -> Case {
        let case = Case::suite(prefix, scene);
        let text = format!(
            "#!/bin/bash\nRAYTRACER={}\nCASE={}\n{script}\n",
            student_binary().display(),
            case.path().display()
        );
        let tracer = case.path().join("tracer.sh");
        std::fs::write(&tracer, text).unwrap();
        std::fs::set_permissions(&tracer, std::fs::Permissions::from_mode(0o755)).unwrap();
        case
    }

    /// This case, its `--tracer` runs given `defaults` (option and value)
    /// unless they give the option themselves.
    pub fn with_defaults(self, defaults: &[(&'static str, &'static str)]) -> Case {
        Case {
            defaults: defaults.to_vec(),
            ..self
        }
    }

    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// The student's tracer command: the script, with the student's
    /// renderer as a word so the box holds it.
    pub fn tracer(&self) -> String {
        format!(
            "{} {{scene}} {{out}} {}",
            self.path().join("tracer.sh").display(),
            student_binary().display()
        )
    }

    /// The report folder of a run of `kind`.
    pub fn report(&self, kind: Kind) -> PathBuf {
        self.path().join(format!("report-{kind:?}"))
    }

    /// A student folder at `relative` in the case: `tracer.txt` holding
    /// `tracer`, the `files` (name and text), and the student's renderer
    /// as `renderer`; it and a folder of students above it open to read.
    pub fn student(&self, relative: &str, tracer: &str, files: &[(&str, &[u8])]) -> PathBuf {
        let folder = self.path().join(relative);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join("tracer.txt"), tracer).unwrap();
        for (name, bytes) in files {
            std::fs::write(folder.join(name), bytes).unwrap();
        }
        std::fs::copy(student_binary(), folder.join("renderer")).unwrap();
        for path in folder.ancestors().take_while(|p| *p != self.path()) {
            std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
        folder
    }

    /// `grade` in a run of `kind` with `args` (what to grade, and
    /// options), into `report`, with the kind's cache and the case's
    /// suite; `HOME` the case's folder, no stdin.
    pub fn grade_command<I, S>(&self, kind: Kind, report: &Path, args: I) -> Command
    where
        I: IntoIterator<Item = S>,
        S: AsRef<OsStr>,
    {
        let d = self.path();
        let mut command = grader(kind);
        command
            .arg("grade")
            .args(args)
            .arg("-o")
            .arg(report)
            .arg("--cache")
            .arg(d.join(format!("cache-{kind:?}")))
            .arg(d.join("suite"))
            .env("HOME", d)
            .stdin(Stdio::null());
        command
    }

    /// The command that grades with `tracer` (default: [`Case::tracer`])
    /// in a run of `kind`, into [`Case::report`] (emptied first), with
    /// `extra` options and `env`.
    pub fn command(
        &self,
        kind: Kind,
        tracer: Option<&str>,
        extra: &[&str],
        env: &[(&str, &str)],
    ) -> Command {
        let report = self.report(kind);
        let _ = std::fs::remove_dir_all(&report);
        let default = self.tracer();
        let mut args = vec!["--tracer", tracer.unwrap_or(&default)];
        for (option, value) in &self.defaults {
            if !extra.contains(option) {
                args.extend([*option, *value]);
            }
        }
        args.extend_from_slice(extra);
        let mut command = self.grade_command(kind, &report, args);
        for (key, value) in env {
            command.env(key, value);
        }
        command
    }

    /// Grade as [`Case::command`] says; the exit code, the first scene's
    /// entry and summary.json's sandbox.
    pub fn grade(
        &self,
        kind: Kind,
        tracer: Option<&str>,
        extra: &[&str],
        env: &[(&str, &str)],
    ) -> (i32, Value, Value) {
        self.grade_by(kind, self.command(kind, tracer, extra, env))
    }

    /// Grade by `command`, made by [`Case::command`] for `kind`.
    pub fn grade_by(&self, kind: Kind, mut command: Command) -> (i32, Value, Value) {
        let output = command.output().unwrap();
        let summary = self.summary(kind, &String::from_utf8_lossy(&output.stderr));
        (
            output.status.code().unwrap_or(-1),
            summary["scenes"][0].clone(),
            summary["sandbox"].clone(),
        )
    }

    /// The summary.json a run of `kind` wrote; `stderr` is what `grade`
    /// said, for the failure.
    pub fn summary(&self, kind: Kind, stderr: &str) -> Value {
        let path = self.report(kind).join("summary.json");
        let bytes =
            std::fs::read(&path).unwrap_or_else(|_| panic!("{kind:?}: no summary: {stderr}"));
        serde_json::from_slice(&bytes).unwrap()
    }
}
