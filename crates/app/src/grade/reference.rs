//! Our reference images, rendered once per scene content and kept in a
//! cache folder: the key is a SHA-256 of this program's own executable
//! (so a different renderer never reuses another's images) and of the
//! scene's files (the scene and its textures, with their paths), and the
//! image is `KEY.png` in the folder. Grading the next student renders
//! nothing.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::suite::SuiteScene;
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
