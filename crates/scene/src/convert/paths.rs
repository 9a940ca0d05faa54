//! Texture paths that survive conversion.
//!
//! A scene names its textures relative to its own folder. A converted scene
//! written to another folder must name the same files relative to *its*
//! folder, so [`rebase_textures`] rewrites every relative texture path as
//! the path from the output's folder to the file: both folders are made
//! absolute and canonical (symbolic links and `..` resolved; the texture's
//! own file name is kept, so a texture that is a link stays that link),
//! and the result is the shortest relative path between them. A path
//! written absolute stays as written. Only where no relative path exists
//! (a folder that cannot be resolved, or on Windows another drive) is the
//! texture's absolute path written.

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use crate::check::Checked;

/// Rewrite every texture path of `checked` (its objects and the keys of
/// its decoded textures) to resolve from the folder `destination`.
pub fn rebase_textures(checked: &mut Checked, destination: &Path) {
    let destination = destination.canonicalize().ok();
    let mut rebased: BTreeMap<String, String> = BTreeMap::new();
    for (written, texture) in &checked.textures {
        let path = if Path::new(written).is_absolute() {
            written.clone()
        } else {
            rebase(Path::new(&texture.path), destination.as_deref())
                .display()
                .to_string()
        };
        rebased.insert(written.clone(), path);
    }
    for object in &mut checked.scene.objects {
        if let Some(path) = &mut object.material.texture {
            if let Some(new) = rebased.get(path) {
                *path = new.clone();
            }
        }
    }
    checked.textures = std::mem::take(&mut checked.textures)
        .into_iter()
        .map(|(written, texture)| (rebased.remove(&written).unwrap_or(written), texture))
        .collect();
}

/// The path from the canonical folder `destination` to the file `texture`
/// (relative to the working directory, or absolute).
fn rebase(texture: &Path, destination: Option<&Path>) -> PathBuf {
    let absolute = canonical_file(texture)
        .or_else(|| std::path::absolute(texture).ok())
        .unwrap_or_else(|| texture.to_path_buf());
    destination
        .and_then(|destination| relative(destination, &absolute))
        .unwrap_or(absolute)
}

/// `file` with its folder made canonical and its name kept.
fn canonical_file(file: &Path) -> Option<PathBuf> {
    let name = file.file_name()?;
    let folder = crate::folder::folder_of(file);
    Some(folder.canonicalize().ok()?.join(name))
}

/// The relative path from the folder `from` to `to`, both absolute and
/// normalised; `None` when they have different roots.
fn relative(from: &Path, to: &Path) -> Option<PathBuf> {
    let from: Vec<Component> = from.components().collect();
    let to: Vec<Component> = to.components().collect();
    let root = |components: &[Component]| -> usize {
        components
            .iter()
            .take_while(|c| !matches!(c, Component::Normal(_)))
            .count()
    };
    let (from_root, to_root) = (root(&from), root(&to));
    if from_root == 0 || from_root != to_root || from[..from_root] != to[..to_root] {
        return None;
    }
    let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
    let mut path = PathBuf::new();
    for _ in common..from.len() {
        path.push("..");
    }
    for component in &to[common..] {
        path.push(component);
    }
    Some(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_between_folders() {
        let rel = |a: &str, b: &str| relative(Path::new(a), Path::new(b));
        assert_eq!(rel("/a/b", "/a/b/t.ppm"), Some("t.ppm".into()));
        assert_eq!(rel("/a/b/c/d", "/a/b/t.ppm"), Some("../../t.ppm".into()));
        assert_eq!(rel("/a", "/a/b/c/t.ppm"), Some("b/c/t.ppm".into()));
        assert_eq!(rel("/x/y", "/a/t.ppm"), Some("../../a/t.ppm".into()));
        assert_eq!(rel("/", "/t.ppm"), Some("t.ppm".into()));
        assert_eq!(rel("a/b", "/a/t.ppm"), None);
    }

    #[test]
    fn rebased_paths_resolve_from_the_destination() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().canonicalize().unwrap();
        std::fs::create_dir_all(root.join("scenes/tex")).unwrap();
        std::fs::create_dir_all(root.join("out/deep/er")).unwrap();
        let texture = root.join("scenes/tex/../tex/wood.ppm");
        let rebased = rebase(&texture, Some(&root.join("out/deep/er")));
        assert_eq!(rebased, Path::new("../../../scenes/tex/wood.ppm"));
        assert_eq!(
            rebase(&texture, Some(&root)),
            Path::new("scenes/tex/wood.ppm")
        );
        // No destination folder: the absolute path.
        assert_eq!(rebase(&texture, None), root.join("scenes/tex/wood.ppm"));
    }
}
