//! The scenes a tracer is graded on: the built-in suite embedded in the
//! binary (the repository's suite/ folder: its scenes, their textures and
//! suite.json, which gives each scene its points and one line on what it
//! tests), or scene files and folders given on the command line.
//!
//! A folder with a suite.json is graded on the scenes it lists; one
//! without, on every `.txt`, `.scene` and `.json` file under it, a point
//! each. Every scene must check without errors, and its textures must lie
//! in its suite's folder, because the tracer runs in a copy of that
//! folder holding only the scene and its textures.

use std::path::{Path, PathBuf};

use std::collections::BTreeMap;

use serde::Deserialize;

use super::aspects::{Aspect, AspectPoints};

use raytracer_render::ir;
use raytracer_scene::diagnostic::FileError;
use raytracer_scene::frontend::{self, Loaded};

/// The files of the built-in suite, by their path inside it.
const BUILT_IN: &[(&str, &[u8])] = &[
    (
        "beyond_light.txt",
        include_bytes!("../../../../suite/beyond_light.txt"),
    ),
    (
        "big_shadow.txt",
        include_bytes!("../../../../suite/big_shadow.txt"),
    ),
    (
        "checker.ppm",
        include_bytes!("../../../../suite/checker.ppm"),
    ),
    (
        "checker.txt",
        include_bytes!("../../../../suite/checker.txt"),
    ),
    (
        "colours.txt",
        include_bytes!("../../../../suite/colours.txt"),
    ),
    (
        "facing_mirrors.txt",
        include_bytes!("../../../../suite/facing_mirrors.txt"),
    ),
    (
        "field/2_lights_color.txt",
        include_bytes!("../../../../suite/field/2_lights_color.txt"),
    ),
    (
        "field/christmas_ornaments.txt",
        include_bytes!("../../../../suite/field/christmas_ornaments.txt"),
    ),
    (
        "field/plane.txt",
        include_bytes!("../../../../suite/field/plane.txt"),
    ),
    (
        "field/reflection.txt",
        include_bytes!("../../../../suite/field/reflection.txt"),
    ),
    (
        "field/sphereBox.txt",
        include_bytes!("../../../../suite/field/sphereBox.txt"),
    ),
    (
        "field/sphere_reflection.txt",
        include_bytes!("../../../../suite/field/sphere_reflection.txt"),
    ),
    (
        "field/texture.scene",
        include_bytes!("../../../../suite/field/texture.scene"),
    ),
    (
        "field/two_spheres_shadow.txt",
        include_bytes!("../../../../suite/field/two_spheres_shadow.txt"),
    ),
    (
        "field/wood_tex.ppm",
        include_bytes!("../../../../suite/field/wood_tex.ppm"),
    ),
    (
        "hard/eye_in_plane.txt",
        include_bytes!("../../../../suite/hard/eye_in_plane.txt"),
    ),
    (
        "hard/grazing_plane.txt",
        include_bytes!("../../../../suite/hard/grazing_plane.txt"),
    ),
    (
        "hard/inside_sphere.txt",
        include_bytes!("../../../../suite/hard/inside_sphere.txt"),
    ),
    (
        "hard/light_on_surface.txt",
        include_bytes!("../../../../suite/hard/light_on_surface.txt"),
    ),
    (
        "hard/parallel_mirrors.txt",
        include_bytes!("../../../../suite/hard/parallel_mirrors.txt"),
    ),
    (
        "hard/planet.txt",
        include_bytes!("../../../../suite/hard/planet.txt"),
    ),
    (
        "hard/scaled_1e-3.txt",
        include_bytes!("../../../../suite/hard/scaled_1e-3.txt"),
    ),
    (
        "hard/scaled_1e6.txt",
        include_bytes!("../../../../suite/hard/scaled_1e6.txt"),
    ),
    (
        "hard/shadow_acne.txt",
        include_bytes!("../../../../suite/hard/shadow_acne.txt"),
    ),
    (
        "hard/tangent_sphere.txt",
        include_bytes!("../../../../suite/hard/tangent_sphere.txt"),
    ),
    ("mirror.txt", include_bytes!("../../../../suite/mirror.txt")),
    (
        "near_occluder.txt",
        include_bytes!("../../../../suite/near_occluder.txt"),
    ),
    (
        "reflection.txt",
        include_bytes!("../../../../suite/reflection.txt"),
    ),
    ("sample.txt", include_bytes!("../../../../suite/sample.txt")),
    (
        "shadowed_highlight.txt",
        include_bytes!("../../../../suite/shadowed_highlight.txt"),
    ),
    (
        "shadows.txt",
        include_bytes!("../../../../suite/shadows.txt"),
    ),
    ("suite.json", include_bytes!("../../../../suite/suite.json")),
    (
        "textures.txt",
        include_bytes!("../../../../suite/textures.txt"),
    ),
    (
        "wood_maxval51.ppm",
        include_bytes!("../../../../suite/wood_maxval51.ppm"),
    ),
    (
        "wood_tex.ppm",
        include_bytes!("../../../../suite/wood_tex.ppm"),
    ),
];

/// One scene to grade.
#[derive(Debug)]
pub struct SuiteScene {
    /// The scene's path inside its suite folder, `/`-separated.
    pub name: String,
    /// The points the scene is worth: the sum of `aspects`.
    pub points: f64,
    /// A scene beyond what the assignment asks (suite.json's
    /// `robustness`): judged and reported, worth its points only when its
    /// suite.json sets `robustness_points`, else none.
    pub robustness: bool,
    /// The points of each aspect it is judged on.
    pub aspects: AspectPoints,
    pub description: String,
    /// The folder the scene's relative paths start from.
    pub root: PathBuf,
    /// The scene and its textures, inside `root`.
    pub files: Vec<PathBuf>,
    /// The scene, checked and lowered, for our reference.
    pub scene: ir::Scene,
}

/// A suite.json.
#[derive(Deserialize)]
struct Manifest {
    scenes: Vec<ManifestEntry>,
    /// The constants of our reference, read only when no
    /// `--reference-options` is given ([`Suite::reference_options`]).
    #[serde(default)]
    reference: Option<serde_json::Value>,
    /// Whether the scenes marked `robustness` carry their points.
    #[serde(default)]
    robustness_points: bool,
}

/// The scenes of a suite, and the `reference` objects its suite.json
/// files give, each with the file's path.
pub struct Suite {
    pub scenes: Vec<SuiteScene>,
    references: Vec<(PathBuf, serde_json::Value)>,
}

#[derive(Deserialize)]
struct ManifestEntry {
    scene: String,
    points: Points,
    #[serde(default)]
    description: String,
    /// Beyond what the assignment asks: points only where the suite opts
    /// in.
    #[serde(default)]
    robustness: bool,
}

/// A scene's points in suite.json: per aspect, or a total that
/// [`split`] shares out.
#[derive(Clone, Deserialize)]
#[serde(untagged)]
enum Points {
    Total(f64),
    PerAspect(BTreeMap<Aspect, f64>),
}

/// A total shared out evenly among geometry, the effects the scene has
/// (shadows with a light, reflection with a mirror, textures with a
/// texture) and shading: a wrong light colour costs a scene what a
/// missing shadow costs it.
pub fn split(total: f64, effects: ir::Effects) -> AspectPoints {
    let mut aspects = vec![Aspect::Geometry];
    if effects.shadows {
        aspects.push(Aspect::Shadows);
    }
    if effects.reflection {
        aspects.push(Aspect::Reflection);
    }
    if effects.textures {
        aspects.push(Aspect::Textures);
    }
    aspects.push(Aspect::Shading);
    let each = total / aspects.len() as f64;
    aspects.into_iter().map(|a| (a, each)).collect()
}

/// Points to a millionth, so tenths that add up show as they should.
pub fn round_points(points: f64) -> f64 {
    // `+ 0.0` turns the `-0` of an empty sum into 0.
    (points * 1e6).round() / 1e6 + 0.0
}

/// Why a suite cannot be graded.
#[derive(Debug, thiserror::Error)]
pub enum SuiteError {
    #[error(transparent)]
    Io(#[from] FileError),
    #[error(transparent)]
    Read(#[from] frontend::ReadSceneError),
    #[error("`{path}` is not a valid suite.json: {reason}")]
    Manifest { path: String, reason: String },
    #[error("`{path}` has errors; run `raytracer check {path}` to see them")]
    Scene { path: String },
    #[error("the texture `{texture}` of `{path}` lies outside the suite folder `{root}`")]
    TextureOutside {
        path: String,
        texture: String,
        root: String,
    },
    #[error("no scene found in `{path}`")]
    Empty { path: String },
}

/// Write the built-in suite into `dir` (created if need be).
pub fn export(dir: &Path) -> Result<(), SuiteError> {
    for (name, bytes) in BUILT_IN {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(FileError::writing(parent))?;
        }
        raytracer_render::output::write_atomically(&path, |out| out.write_all(bytes))
            .map_err(FileError::writing(&path))?;
    }
    Ok(())
}

/// Load the scenes of `paths` (files or folders).
pub fn load(paths: &[PathBuf]) -> Result<Suite, SuiteError> {
    let mut suite = Suite {
        scenes: Vec::new(),
        references: Vec::new(),
    };
    for path in paths {
        if path.is_dir() {
            load_folder(path, &mut suite)?;
        } else {
            let (root, name) = file_root(path);
            let entry = ManifestEntry {
                scene: name,
                points: Points::Total(1.0),
                description: String::new(),
                robustness: false,
            };
            let scene = load_scene(&root, entry, true)?;
            suite.scenes.push(scene);
        }
    }
    Ok(suite)
}

/// The folder a scene file given alone is graded from, and its path
/// inside it: the nearest folder above it with a suite.json (an exported
/// suite, whose scenes may name textures in a folder above their own,
/// as hard/inside_sphere.txt names wood_tex.ppm), else its own folder.
fn file_root(path: &Path) -> (PathBuf, String) {
    let own = raytracer_scene::folder::folder_of(path);
    let file = path.file_name().unwrap_or_default();
    let mut inside = PathBuf::from(file);
    let mut folder = own;
    loop {
        if folder.join("suite.json").is_file() {
            return (folder.to_path_buf(), slashed(&inside));
        }
        match folder.file_name() {
            Some(name) => {
                inside = Path::new(name).join(inside);
                folder = folder
                    .parent()
                    .filter(|p| !p.as_os_str().is_empty())
                    .unwrap_or(Path::new("."));
            }
            None => break,
        }
    }
    (own.to_path_buf(), file.to_string_lossy().into_owned())
}

/// A relative path, `/`-separated.
fn slashed(path: &Path) -> String {
    path.to_string_lossy().replace('\\', "/")
}

impl Suite {
    /// The constants our reference is rendered with when a suite.json
    /// gives them (its `reference` object, read as `--reference-options`
    /// reads a file); `None` when none does. Two folders that give
    /// different ones are refused.
    pub fn reference_options(
        &self,
    ) -> Result<Option<raytracer_render::render::Options>, SuiteError> {
        let mut found: Option<(&Path, raytracer_render::render::Options)> = None;
        for (manifest_path, reference) in &self.references {
            let invalid = |reason: String| SuiteError::Manifest {
                path: manifest_path.display().to_string(),
                reason,
            };
            let options = super::options::read_options(&reference.to_string())
                .map_err(|reason| invalid(format!("its `reference`: {reason}")))?;
            if let Some((first, other)) = &found {
                if *other != options {
                    return Err(invalid(format!(
                        "its `reference` differs from that of `{}`",
                        first.display()
                    )));
                }
            }
            found = Some((manifest_path, options));
        }
        Ok(found.map(|(_, options)| options))
    }
}

/// The scenes of one folder, added to `suite`: those of its suite.json
/// (and its `reference`, if any), or every scene file.
fn load_folder(root: &Path, suite: &mut Suite) -> Result<(), SuiteError> {
    let manifest_path = root.join("suite.json");
    let mut robustness_points = false;
    let entries = if manifest_path.is_file() {
        let text =
            std::fs::read_to_string(&manifest_path).map_err(FileError::reading(&manifest_path))?;
        let manifest: Manifest = serde_json::from_str(&text).map_err(|e| SuiteError::Manifest {
            path: manifest_path.display().to_string(),
            reason: e.to_string(),
        })?;
        if let Some(reference) = manifest.reference {
            suite.references.push((manifest_path, reference));
        }
        robustness_points = manifest.robustness_points;
        manifest.scenes
    } else {
        let mut names = Vec::new();
        find_scenes(root, root, &mut names)?;
        names.sort();
        names
            .into_iter()
            .map(|scene| ManifestEntry {
                scene,
                points: Points::Total(1.0),
                description: String::new(),
                robustness: false,
            })
            .collect()
    };
    if entries.is_empty() {
        return Err(SuiteError::Empty {
            path: root.display().to_string(),
        });
    }
    for e in entries {
        let scene = load_scene(root, e, robustness_points)?;
        suite.scenes.push(scene);
    }
    Ok(())
}

/// Collect the scene files under `folder`, as paths relative to `root`.
fn find_scenes(root: &Path, folder: &Path, names: &mut Vec<String>) -> Result<(), SuiteError> {
    let entries = std::fs::read_dir(folder).map_err(FileError::reading(folder))?;
    for entry in entries {
        let path = entry.map_err(FileError::reading(folder))?.path();
        if path.is_dir() {
            find_scenes(root, &path, names)?;
        } else if path.file_name().is_some_and(|n| n != "suite.json")
            && path
                .extension()
                .is_some_and(|e| e == "txt" || e == "scene" || e == "json")
        {
            let relative = path.strip_prefix(root).unwrap_or(&path);
            names.push(relative.to_string_lossy().replace('\\', "/"));
        }
    }
    Ok(())
}

/// Check the scene of `entry` in the suite in `root` and list its files;
/// a robustness scene keeps its points only with `robustness_points`.
fn load_scene(
    root: &Path,
    entry: ManifestEntry,
    robustness_points: bool,
) -> Result<SuiteScene, SuiteError> {
    let ManifestEntry {
        scene: name,
        points,
        description,
        robustness,
    } = entry;
    let name = name.as_str();
    let path = root.join(name);
    let shown = path.display().to_string();
    let Loaded { checked, .. } = frontend::load(&path)?;
    let checked = checked.ok_or(SuiteError::Scene {
        path: shown.clone(),
    })?;
    let canonical_root = root.canonicalize().map_err(FileError::reading(root))?;
    let mut files = vec![PathBuf::from(name)];
    for texture in checked.textures.values() {
        let resolved = Path::new(&texture.path)
            .canonicalize()
            .map_err(FileError::reading(Path::new(&texture.path)))?;
        let relative =
            resolved
                .strip_prefix(&canonical_root)
                .map_err(|_| SuiteError::TextureOutside {
                    path: shown.clone(),
                    texture: texture.path.clone(),
                    root: root.display().to_string(),
                })?;
        files.push(relative.to_path_buf());
    }
    files.sort();
    files.dedup();
    let scene = ir::lower(checked);
    let mut aspects = match points {
        Points::Total(total) => split(total, scene.effects),
        Points::PerAspect(map) => map.into_iter().collect(),
    };
    if robustness && !robustness_points {
        // Judged and reported, for no points.
        for (_, points) in &mut aspects {
            *points = 0.0;
        }
    }
    Ok(SuiteScene {
        name: name.to_string(),
        points: round_points(aspects.iter().map(|(_, p)| p).sum()),
        robustness,
        aspects,
        description,
        root: root.to_path_buf(),
        files,
        scene,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_list_is_the_suite_folder() {
        let folder = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../suite")).to_path_buf();
        let mut on_disk = Vec::new();
        let mut stack = vec![folder.clone()];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                } else {
                    on_disk.push(
                        path.strip_prefix(&folder)
                            .unwrap()
                            .to_string_lossy()
                            .into_owned(),
                    );
                }
            }
        }
        on_disk.sort();
        let embedded: Vec<_> = BUILT_IN.iter().map(|(name, _)| name.to_string()).collect();
        assert_eq!(embedded, on_disk);
    }

    #[test]
    fn the_built_in_suite_loads_every_listed_scene() {
        let dir = tempfile::tempdir().unwrap();
        export(dir.path()).unwrap();
        let scenes = load(&[dir.path().to_path_buf()]).unwrap().scenes;
        assert_eq!(scenes.len(), 30);
        // Every scene the assignment asks for carries points; the
        // robustness ones, none by default.
        assert!(scenes
            .iter()
            .all(|s| (s.points > 0.0) != s.robustness && !s.description.is_empty()));
        assert_eq!(scenes.iter().filter(|s| s.robustness).count(), 7);
        let inside = scenes
            .iter()
            .find(|s| s.name == "hard/inside_sphere.txt")
            .unwrap();
        assert_eq!(
            inside.files,
            [
                PathBuf::from("hard/inside_sphere.txt"),
                PathBuf::from("wood_tex.ppm")
            ]
        );
    }
}
