//! Our reference images, rendered once per scene content and kept in a
//! cache folder: the key is a SHA-256 of this program's own executable
//! (so a different renderer never reuses another's images) and of the
//! scene's files (the scene and its textures, with their paths), and the
//! image is `KEY.png` in the folder. Grading the next student renders
//! nothing.
//!
//! Our renderer can render with a course's constants instead of its own
//! ([`super::options`], `--reference-options` or suite.json's): the ambient share, diffuse
//! and specular weights, pixel point, reflection mode and depth; the key
//! then hashes them too.
//!
//! A course may bring its own reference instead ([`Source`]): a folder of
//! images, or its own solution run under the sandbox once per scene and
//! cached the same way (`instructor-KEY.png`, the key hashing the command,
//! its program's files and the scene's). What each pixel sees (the probes
//! the aspects are judged with) is always our renderer's.
//!
//! The cache is private: its folder is the grader's own, mode 0700 (made
//! so when it is created, corrected when it is the grader's and is not),
//! and a folder that is a link or someone else's is refused. A cached
//! image is read without following a link and only when it is a regular
//! file of the grader's, with one name and no permission for anyone else
//! (mode 0600, as written); anything else is rendered again and replaced.
//! No box ever sees the cache ([`raytracer_box`]).

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::judge;
use super::suite::SuiteScene;
use super::workdir::{self, Template};
use crate::compare::{self, Picture};
use raytracer_box::run::run;
use raytracer_box::{Confinement, Share};
use raytracer_render::render::Precision;
use raytracer_render::render::{self, Options};

/// The reference cache.
pub struct Cache {
    folder: PathBuf,
    /// The hash of the renderer.
    renderer: [u8; 32],
    /// How our references are rendered.
    options: Options,
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
    /// The cache in `folder` (created, private), for the renderer of this
    /// executable.
    pub fn open(folder: &Path) -> std::io::Result<Cache> {
        use std::os::unix::fs::{DirBuilderExt, MetadataExt, OpenOptionsExt, PermissionsExt};
        if let Some(parent) = folder.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent)?;
        }
        match std::fs::DirBuilder::new().mode(0o700).create(folder) {
            Ok(()) => {}
            Err(error) if error.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(error) => return Err(error),
        }
        let dir = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_DIRECTORY | libc::O_NOFOLLOW)
            .open(folder)
            .map_err(|error| {
                if error.raw_os_error() == Some(libc::ELOOP) {
                    std::io::Error::other("the cache folder is a symbolic link: refused")
                } else {
                    error
                }
            })?;
        let meta = dir.metadata()?;
        if meta.uid() != raytracer_box::effective_uid() {
            return Err(std::io::Error::other(format!(
                "the cache folder belongs to uid {}, not to the grader: refused",
                meta.uid()
            )));
        }
        if meta.mode() & 0o077 != 0 {
            dir.set_permissions(std::fs::Permissions::from_mode(0o700))?;
        }
        let exe = std::fs::read(std::env::current_exe()?)?;
        Ok(Cache {
            folder: folder.to_path_buf(),
            renderer: Sha256::digest(&exe).into(),
            options: Options::default(),
        })
    }

    /// This cache, rendering our references with `options`.
    pub fn with_options(self, options: Options) -> Cache {
        Cache { options, ..self }
    }

    /// The reference image of `scene`: read from the cache, else rendered
    /// and stored. Says whether it was rendered.
    pub fn reference(&self, scene: &SuiteScene) -> std::io::Result<(Picture, bool)> {
        let path = self.folder.join(format!("{}.png", self.key(scene)?));
        if let Some(picture) = read_private(&path) {
            return Ok((picture, false));
        }
        let (image, _) = render::render(Precision::F64, &scene.scene, &self.options, &|| {});
        let picture = Picture {
            width: image.size,
            height: image.size,
            rgb: image.rgb,
        };
        self.write_private(&path, &picture)?;
        Ok((picture, true))
    }

    /// Store `picture` at `path` in the cache: written 0600 (a temporary
    /// file's mode) and renamed over whatever was there, a link included.
    fn write_private(&self, path: &Path, picture: &Picture) -> std::io::Result<()> {
        let mut temp = tempfile::Builder::new()
            .prefix(".reference-")
            .permissions(std::os::unix::fs::PermissionsExt::from_mode(0o600))
            .tempfile_in(&self.folder)?;
        {
            let mut out = std::io::BufWriter::new(temp.as_file_mut());
            compare::encode_png(picture, &mut out)?;
            std::io::Write::flush(&mut out)?;
        }
        temp.persist(path).map_err(|e| e.error)?;
        Ok(())
    }

    /// The hex SHA-256 of the renderer and the scene's files.
    fn key(&self, scene: &SuiteScene) -> std::io::Result<String> {
        let mut hash = Sha256::new();
        hash.update(self.renderer);
        // The default options add nothing, so their images keep their keys.
        if !self.options.model.is_default()
            || self.options.max_depth != Options::default().max_depth
        {
            hash.update(b"options\0");
            let model = serde_json::to_vec(&self.options.model).map_err(std::io::Error::other)?;
            hash.update(&model);
            hash.update(self.options.max_depth.to_le_bytes());
        }
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
        template: Template,
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
        if let Some(picture) = read_private(&path) {
            return Ok((picture, false));
        }
        let dir = workdir::prepare(scene, None, &confinement)?;
        let argv = template.argv(&dir.scene_file, workdir::OUT, Some(cwd));
        let share = Share {
            read_write: vec![dir.root.clone()],
            read_only: super::program_files(&argv),
            scratch: Some(raytracer_box::Scratch {
                folder: dir.root.clone(),
                keep: dir.keep(),
            }),
            home: None,
        };
        let run = run(&argv, &dir.start, &share, confinement);
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
        self.write_private(&path, &picture)?;
        Ok((picture, true))
    }
}

/// The cached image at `path` when it is a regular file of the grader's,
/// with one name, closed to everyone else, reached without a link.
fn read_private(path: &Path) -> Option<Picture> {
    let bytes =
        raytracer_box::output::read_private(path, raytracer_scene::limits::MAX_TEXTURE_TEXELS * 4)?;
    let (width, height, texels) = raytracer_scene::texture::decode(
        std::io::Cursor::new(bytes),
        raytracer_scene::limits::MAX_TEXTURE_TEXELS,
    )
    .ok()?;
    Some(Picture::from_texels(width, height, &texels))
}
