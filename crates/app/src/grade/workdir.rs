//! The folder a student's program runs in, and its argument vector.
//!
//! Each scene gets a fresh temporary folder holding a copy of the scene
//! and its textures at their paths inside the suite, so `../wood_tex.ppm`
//! still resolves; the program starts in the scene's own folder there.
//! A student's program (`--student`, `--class`) finds its own files there
//! too: the scene's folder starts as a copy of the student's built folder
//! ([`raytracer_box::copy`]), so `python3 tracer.py {scene} {out}` and
//! `./raytracer {scene} {out}` run as they do at home, beside the scene
//! and its textures. Without a student folder (`--tracer`), a program
//! named by a relative path is taken from the folder `grade` runs in.
//! The folder lies in a folder of its own that only the grader may enter
//! ([`raytracer_box::folder`]), and is removed after the run by a walk
//! no folder can stop. When the program runs as another user, the folder
//! is given to it, and
//! the order of that matters: the folder is created by the grader with
//! mode 0700, so until its own owner changes no other user can enter it,
//! rename an entry or put a link in its place. Everything under it is
//! therefore given away first, without following links, and the folder
//! itself last; after that the grader changes nothing in it by path. In
//! a box the program works on a tmpfs copy of it (`Scratch`), and only
//! its image comes back.
//! The command template is split into words like a shell would split it
//! (quotes, backslashes) and `{scene}` and `{out}` are replaced inside
//! each word, so no file name can add a word or run a command.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use super::suite::SuiteScene;
use raytracer_box::copy::{copy_folder, STUDENT_FOLDER};
use raytracer_box::folder::{private_folder, RunFolder};
use raytracer_box::Confinement;

/// The name of the image the program is asked to write.
pub const OUT: &str = "out.ppm";

/// A prepared folder: removed when dropped, or by [`RunFolder::remove`].
pub struct Workdir {
    pub folder: RunFolder,
    /// `folder`'s canonical path: what a box gives the run.
    pub root: PathBuf,
    /// Where the program starts: the scene's folder inside `folder`.
    pub start: PathBuf,
    /// The scene's file name, for `{scene}`.
    pub scene_file: String,
}

impl Workdir {
    /// The image the program was asked to write.
    pub fn out(&self) -> PathBuf {
        self.start.join(OUT)
    }

    /// The image's path relative to the folder: what a box copies out.
    pub fn keep(&self) -> PathBuf {
        self.start
            .strip_prefix(&self.root)
            .unwrap_or(Path::new(""))
            .join(OUT)
    }
}

/// Copy `scene`'s files into a fresh temporary folder, into the scene's
/// folder there after the contents of `program` (a student's built
/// folder) when given; owned by the run's user of `confinement` when
/// the grader is root.
pub fn prepare(
    scene: &SuiteScene,
    program: Option<&Path>,
    confinement: &Confinement,
) -> std::io::Result<Workdir> {
    let folder = private_folder()?;
    let scene_path = Path::new(&scene.name);
    // Canonical while the folder is still the grader's alone, so reading
    // `{out}` later can refuse a link anywhere on its path.
    let root = folder.path().to_path_buf();
    let start = root.join(scene_path.parent().unwrap_or(Path::new("")));
    std::fs::create_dir_all(&start)?;
    if let Some(program) = program {
        copy_folder(program, &start, STUDENT_FOLDER)?;
        // An image left in the student's folder is not this run's.
        let _ = std::fs::remove_file(start.join(OUT));
    }
    for file in &scene.files {
        let to = root.join(file);
        if let Some(parent) = to.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let _ = std::fs::remove_file(&to);
        std::fs::copy(scene.root.join(file), &to)?;
    }
    if let Some(id) = confinement.user {
        folder.give(id, !confinement.boxed)?;
    }
    Ok(Workdir {
        root,
        start,
        scene_file: scene_path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned(),
        folder,
    })
}

/// Why a command template cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum TemplateError {
    #[error("cannot split the command into words: {0}")]
    Split(String),
    #[error("the command is empty")]
    Empty,
    #[error("expected `{{scene}}` and `{{out}}` in the command, found no {missing}")]
    Placeholder { missing: &'static str },
}

/// The words of a `--tracer` template, checked once.
#[derive(Clone, Debug)]
pub struct Template(Vec<String>);

impl Template {
    /// Split `text` into words.
    pub fn parse(text: &str) -> Result<Template, TemplateError> {
        let words = shell_words::split(text).map_err(|e| TemplateError::Split(e.to_string()))?;
        if words.is_empty() {
            return Err(TemplateError::Empty);
        }
        Ok(Template(words))
    }

    /// Split a tracer's command into words, refusing one without `{scene}`
    /// or `{out}`: the tracer would be told neither which scene to read nor
    /// where to write, and every scene would fail the same way.
    pub fn tracer(text: &str) -> Result<Template, TemplateError> {
        let template = Template::parse(text)?;
        let has = |placeholder: &str| template.0.iter().any(|word| word.contains(placeholder));
        let missing = match (has("{scene}"), has("{out}")) {
            (true, true) => return Ok(template),
            (false, false) => "`{scene}` and no `{out}`",
            (false, true) => "`{scene}`",
            (true, false) => "`{out}`",
        };
        Err(TemplateError::Placeholder { missing })
    }

    /// The first word after the program that names, relative to `cwd`,
    /// a file or folder that exists there (`tracer.py` in `python3
    /// tracer.py {scene} {out}`, `.` in `java -cp . Main`): a `--tracer`
    /// program runs without the files beside it, so such a command could
    /// only crash on every scene.
    pub fn local_file(&self, cwd: &Path) -> Option<&str> {
        self.0[1..]
            .iter()
            .filter(|word| !word.contains("{scene}") && !word.contains("{out}"))
            .filter(|word| !word.is_empty() && !word.starts_with('-'))
            .filter(|word| Path::new(word).is_relative())
            .find(|word| cwd.join(word).symlink_metadata().is_ok())
            .map(String::as_str)
    }

    /// The argument vector for one scene. A program given as a relative
    /// path with a `/` is taken from `cwd` when given (the folder `grade`
    /// runs in), else left relative, to be found where the program starts.
    pub fn argv(&self, scene: &str, out: &str, cwd: Option<&Path>) -> Vec<OsString> {
        self.words(cwd, |word| {
            word.replace("{scene}", scene).replace("{out}", out)
        })
    }

    /// The argument vector as written (a build command), found where it
    /// starts.
    pub fn argv_as_written(&self) -> Vec<OsString> {
        self.words(None, str::to_string)
    }

    fn words(&self, cwd: Option<&Path>, substitute: impl Fn(&str) -> String) -> Vec<OsString> {
        self.0
            .iter()
            .enumerate()
            .map(|(i, word)| {
                let word = substitute(word);
                match cwd {
                    Some(cwd) if i == 0 && word.contains('/') && Path::new(&word).is_relative() => {
                        cwd.join(word).into_os_string()
                    }
                    _ => word.into(),
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_named_beside_the_program_is_found() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("tracer.py"), "").unwrap();
        std::fs::write(dir.path().join("run.sh"), "").unwrap();
        let local = |command: &str| {
            Template::tracer(command)
                .unwrap()
                .local_file(dir.path())
                .map(String::from)
        };
        assert_eq!(
            local("python3 tracer.py {scene} {out}").as_deref(),
            Some("tracer.py")
        );
        assert_eq!(local("java -cp . Main {scene} {out}").as_deref(), Some("."));
        assert_eq!(local("sh run.sh {scene} {out}").as_deref(), Some("run.sh"));
        assert_eq!(local("./tracer.py {scene} {out}"), None);
        assert_eq!(local("python3 /abs/tracer.py {scene} {out}"), None);
        assert_eq!(local("python3 missing.py {scene} {out}"), None);
    }

    #[test]
    fn a_scene_name_never_adds_a_word() {
        let template = Template::parse("tracer --in '{scene}' {out}").unwrap();
        let argv = template.argv("a b; rm -rf ~.txt", "out.ppm", Some(Path::new("/g")));
        assert_eq!(argv, ["tracer", "--in", "a b; rm -rf ~.txt", "out.ppm"]);
    }

    #[test]
    fn a_relative_program_is_taken_from_the_grader_folder_or_left_relative() {
        let template = Template::parse("./bin/tracer {scene} {out}").unwrap();
        let argv = template.argv("s.txt", "out.ppm", Some(Path::new("/home/g")));
        assert_eq!(argv[0], "/home/g/./bin/tracer");
        let argv = template.argv("s.txt", "out.ppm", None);
        assert_eq!(argv[0], "./bin/tracer");
        assert!(matches!(Template::parse("  "), Err(TemplateError::Empty)));
        assert!(Template::tracer("./bin/tracer --in={scene} {out}").is_ok());
        for (command, missing) in [
            ("raytracer render", "found no `{scene}` and no `{out}`"),
            ("t {scene}", "found no `{out}`"),
            ("t out.ppm {out}", "found no `{scene}`"),
        ] {
            let error = Template::tracer(command).unwrap_err().to_string();
            assert!(error.ends_with(missing), "{command}: {error}");
        }
        assert!(matches!(
            Template::parse("a 'b"),
            Err(TemplateError::Split(_))
        ));
    }
}
