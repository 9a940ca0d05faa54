//! Our reference images, rendered once per scene content and kept in a
//! cache folder: the key is a SHA-256 of this program's own executable
//! (so a different renderer never reuses another's images) and of the
//! scene's files (the scene and its textures, with their paths), and the
//! image is `KEY.png` in the folder. Grading the next student renders
//! nothing.
//!
//! A course may bring its own reference instead ([`Source`]): a folder of
//! images, or its own solution run under the sandbox once per scene and
//! cached the same way (`instructor-KEY.png`, the key hashing the command,
//! its program's files and the scene's). What each pixel sees (the probes
//! the aspects are judged with) is always our renderer's.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::judge;
use super::sandbox::{self, Confinement};
use super::suite::SuiteScene;
use super::workdir::{self, Template};
use crate::compare::{self, Picture};
use raytracer_render::render::Precision;
use raytracer_render::render::{self, Options};

/// The reference cache.
pub struct Cache {
    folder: PathBuf,
    /// The hash of the renderer.
    renderer: [u8; 32],
}

/// The default cache folder: `$XDG_CACHE_HOME/raytracer/references`, else
/// `$HOME/.cache/raytracer/references`.
pub fn default_folder() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|home| Path::new(&home).join(".cache")))?;
    Some(base.join("raytracer").join("references"))
}

impl Cache {
    /// The cache in `folder` (created), for the renderer of this executable.
    pub fn open(folder: &Path) -> std::io::Result<Cache> {
        std::fs::create_dir_all(folder)?;
        let exe = std::fs::read(std::env::current_exe()?)?;
        Ok(Cache {
            folder: folder.to_path_buf(),
            renderer: Sha256::digest(&exe).into(),
        })
    }

    /// The reference image of `scene`: read from the cache, else rendered
    /// and stored. Says whether it was rendered.
    pub fn reference(&self, scene: &SuiteScene) -> std::io::Result<(Picture, bool)> {
        let path = self.folder.join(format!("{}.png", self.key(scene)?));
        if let Ok((picture, _)) = compare::read(&path) {
            return Ok((picture, false));
        }
        let (image, _) = render::render(Precision::F64, &scene.scene, &Options::default(), &|| {});
        let picture = Picture {
            width: image.size,
            height: image.size,
            rgb: image.rgb,
        };
        raytracer_render::output::write_atomically(&path, |out| {
            compare::encode_png(&picture, out)
        })?;
        Ok((picture, true))
    }

    /// The hex SHA-256 of the renderer and the scene's files.
    fn key(&self, scene: &SuiteScene) -> std::io::Result<String> {
        let mut hash = Sha256::new();
        hash.update(self.renderer);
        for file in &scene.files {
            let bytes = std::fs::read(scene.root.join(file))?;
            let name = file.to_string_lossy();
            hash.update((name.len() as u64).to_le_bytes());
            hash.update(name.as_bytes());
            hash.update((bytes.len() as u64).to_le_bytes());
            hash.update(&bytes);
        }
        Ok(hash.finalize().iter().map(|b| format!("{b:02x}")).collect())
    }
}

/// Where the reference images come from: ours (rendered and cached), a
/// folder of the instructor's images, or the instructor's own tracer.
pub enum Source<'a> {
    Ours,
    /// `--references DIR`: `DIR/<scene path>` with its extension replaced
    /// by `.png` or `.ppm` (or added to it).
    Folder(&'a Path),
    /// `--reference-tracer CMD`: the course's own solution, run once per
    /// scene under the same sandbox as the students, from `cwd`.
    Tracer {
        command: &'a str,
        template: &'a Template,
        cwd: &'a Path,
        confinement: Confinement,
    },
}

impl Cache {
    /// The reference image of `scene` from `source`; says whether it was
    /// made now (rendered, or the tracer run).
    pub fn reference_from(
        &self,
        scene: &SuiteScene,
        source: &Source,
    ) -> std::io::Result<(Picture, bool)> {
        match source {
            Source::Ours => self.reference(scene),
            Source::Folder(folder) => {
                let stem = Path::new(&scene.name).with_extension("");
                let candidates = [
                    folder.join(stem.with_extension("png")),
                    folder.join(stem.with_extension("ppm")),
                    folder.join(format!("{}.png", scene.name)),
                    folder.join(format!("{}.ppm", scene.name)),
                ];
                let found = candidates.iter().find(|p| p.is_file()).ok_or_else(|| {
                    std::io::Error::other(format!(
                        "no reference image for `{}` in `{}` (looked for `{}`)",
                        scene.name,
                        folder.display(),
                        candidates[0].display()
                    ))
                })?;
                let (picture, _) = compare::read(found)
                    .map_err(|e| std::io::Error::other(format!("{}: {e}", found.display())))?;
                Ok((picture, false))
            }
            Source::Tracer {
                command,
                template,
                cwd,
                confinement,
            } => self.instructor(scene, command, template, cwd, *confinement),
        }
    }

    /// The instructor's image of `scene`, cached by a hash of the command,
    /// the files of its program (the first word, when it names a file, and
    /// every other word that names a file in `cwd`) and the scene's files.
    fn instructor(
        &self,
        scene: &SuiteScene,
        command: &str,
        template: &Template,
        cwd: &Path,
        confinement: Confinement,
    ) -> std::io::Result<(Picture, bool)> {
        let mut hash = Sha256::new();
        hash.update(b"instructor\0");
        hash.update(command.as_bytes());
        for word in command.split_whitespace() {
            let path = cwd.join(word);
            if path.is_file() {
                let bytes = std::fs::read(&path)?;
                hash.update((bytes.len() as u64).to_le_bytes());
                hash.update(&bytes);
            }
        }
        hash.update(self.key(scene)?.as_bytes());
        let key: String = hash.finalize().iter().map(|b| format!("{b:02x}")).collect();
        let path = self.folder.join(format!("instructor-{key}.png"));
        if let Ok((picture, _)) = compare::read(&path) {
            return Ok((picture, false));
        }
        let dir = workdir::prepare(scene, None, confinement.user)?;
        let argv = template.argv(&dir.scene_file, workdir::OUT, Some(cwd));
        let run = sandbox::run(&argv, &dir.start, confinement);
        if let Some((_, reason)) = judge::failure(&run.ended) {
            return Err(std::io::Error::other(format!(
                "the reference tracer failed on `{}`: {reason}",
                scene.name
            )));
        }
        let (picture, _) = compare::read(&dir.out()).map_err(|e| {
            std::io::Error::other(format!(
                "the reference tracer wrote no readable image for `{}`: {e}",
                scene.name
            ))
        })?;
        raytracer_render::output::write_atomically(&path, |out| {
            compare::encode_png(&picture, out)
        })?;
        Ok((picture, true))
    }
}
