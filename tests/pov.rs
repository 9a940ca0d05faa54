//! `convert --to pov` end to end against the real POV-Ray: for every
//! checkable scene in the corpus and in scenes/, our renderer and `povray`
//! agree on which pixels an object covers, except on silhouettes.
//!
//! The comparison renders a coverage copy of each scene (no lights, every
//! object white with reflectivity 0 and no texture, at a smaller size), so
//! a covered pixel is the ambient 0.1 (26/255) in both renderers and the
//! background is black. Pixels may differ only where the pixel has a
//! neighbour of the other class in either image (sampling positions and
//! edge tests differ by rounding there).
//!
//! A second test renders the scenes as they are (lights, reflections and
//! the real scenes/wood_tex.ppm texture) and asserts that at most 1% of the
//! pixels differ by more than 1/255: the shading, reflection, gamma and
//! texture mapping agree, not only the geometry.
//!
//! POV-Ray is a Debian package (`povray`) that .ci/run installs; without it
//! the tests fail under CI (`support::under_ci`) and print `SKIPPED` visibly otherwise.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::Command;

use raytracer_scene::convert::scene_text::to_scene_text;
use raytracer_scene::frontend::load;
use raytracer_scene::model::{Material, Scene};

const CORPUS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/corpus/field");
const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");
const PARALLEL: &str = "reflection_91b7c2f_headup010.txt";
/// The coverage images' width and height.
const SIZE: u32 = 96;
/// A covered pixel is 26/255 and the background 0: split halfway.
const COVERED: u8 = 13;

fn run(command: &mut Command) {
    let output = command.output().expect("start the command");
    assert!(
        output.status.success(),
        "{command:?} failed:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// Every checkable scene text in the corpus and scenes/.
fn scenes() -> Vec<PathBuf> {
    let corpus = PathBuf::from(CORPUS);
    assert!(
        corpus.is_dir(),
        "the scene corpus is missing: {}",
        corpus.display()
    );
    let mut scenes = Vec::new();
    for folder in [corpus, PathBuf::from(SCENES)] {
        for entry in std::fs::read_dir(folder).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            if (name.ends_with(".txt") || name.ends_with(".scene"))
                && name != "SOURCE.txt"
                && name != PARALLEL
            {
                scenes.push(path);
            }
        }
    }
    scenes.sort();
    scenes
}

/// The scene at `scene`, copied into `dir` beside scenes/wood_tex.ppm, at
/// the comparison size.
fn small_scene(scene: &Path, dir: &Path) -> Scene {
    let copy = dir.join(scene.file_name().unwrap());
    std::fs::copy(scene, &copy).unwrap();
    std::fs::copy(
        Path::new(SCENES).join("wood_tex.ppm"),
        dir.join("wood_tex.ppm"),
    )
    .unwrap();
    let loaded = load(&copy).unwrap();
    let mut model = loaded.checked.expect("the scene checks").scene;
    model.camera.resolution = SIZE;
    model
}

/// Render `model` with our renderer and with POV-Ray (through `convert
/// --to pov`) in `dir`; the two images' paths.
fn render_both(model: &Scene, dir: &Path) -> (PathBuf, PathBuf) {
    let bin = support::bin();
    let text = dir.join("compare.txt");
    std::fs::write(&text, to_scene_text(model).unwrap()).unwrap();
    let ours = dir.join("ours.png");
    run(Command::new(bin)
        .arg("render")
        .arg(&text)
        .arg(&ours)
        .arg("--quiet"));
    let pov = dir.join("compare.pov");
    run(Command::new(bin)
        .args(["convert", "--to", "pov", "-o"])
        .arg(&pov)
        .arg(&text));
    run(Command::new("povray")
        .current_dir(dir)
        .arg("+Icompare.pov")
        .arg("+Opovray.png")
        .arg(format!("+W{SIZE}"))
        .arg(format!("+H{SIZE}"))
        .args(["-A", "-D", "+FN", "File_Gamma=1", "-V", "-GA"]));
    (ours, dir.join("povray.png"))
}

/// The coverage copy of a scene: no lights, plain white matte objects.
fn coverage_scene(scene: &Path, dir: &Path) -> Scene {
    let mut model = small_scene(scene, dir);
    model.lights.clear();
    for object in &mut model.objects {
        object.material = Material::default();
    }
    model
}

/// Which pixels are covered, row-major.
fn mask(path: &Path) -> Vec<bool> {
    let image = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    assert_eq!(image.dimensions(), (SIZE, SIZE), "{}", path.display());
    image.pixels().map(|p| p.0[0] >= COVERED).collect()
}

/// True when pixel `i` has an 8-neighbour of the other class in `mask`.
fn on_silhouette(mask: &[bool], i: usize) -> bool {
    let n = SIZE as i64;
    let (x, y) = ((i as i64) % n, (i as i64) / n);
    (-1..=1).any(|dy| {
        (-1..=1).any(|dx| {
            let (nx, ny) = (x + dx, y + dy);
            (0..n).contains(&nx) && (0..n).contains(&ny) && mask[(ny * n + nx) as usize] != mask[i]
        })
    })
}

#[test]
fn povray_covers_the_same_pixels_as_our_renderer() {
    if !support::tool_available(
        "povray",
        "povray_covers_the_same_pixels_as_our_renderer",
        "apt-get install povray",
    ) {
        return;
    }
    let scenes = scenes();
    assert!(scenes.len() >= 11, "found {} scenes", scenes.len());
    let mut report = Vec::new();
    for scene in &scenes {
        let name = scene.file_name().unwrap().to_string_lossy().to_string();
        let dir = tempfile::tempdir().unwrap();
        let (ours, theirs) = render_both(&coverage_scene(scene, dir.path()), dir.path());
        let (ours, theirs) = (mask(&ours), mask(&theirs));
        let covered = ours.iter().filter(|&&c| c).count();
        let differ: Vec<usize> = (0..ours.len()).filter(|&i| ours[i] != theirs[i]).collect();
        let inside: Vec<usize> = differ
            .iter()
            .copied()
            .filter(|&i| !on_silhouette(&ours, i) && !on_silhouette(&theirs, i))
            .collect();
        report.push(format!(
            "{name}: {covered} covered, {} differ on silhouettes, {} elsewhere",
            differ.len() - inside.len(),
            inside.len()
        ));
        assert!(
            covered > 0,
            "{name}: the coverage image is empty, so it tests nothing"
        );
        assert!(
            inside.is_empty(),
            "{name}: {} pixels differ away from silhouettes, first at {:?}",
            inside.len(),
            inside
                .iter()
                .take(5)
                .map(|i| (i % SIZE as usize, i / SIZE as usize))
                .collect::<Vec<_>>()
        );
    }
    eprintln!("{}", report.join("\n"));
}

#[test]
fn povray_renders_the_same_picture_but_for_a_few_pixels() {
    if !support::tool_available(
        "povray",
        "povray_renders_the_same_picture_but_for_a_few_pixels",
        "apt-get install povray",
    ) {
        return;
    }
    let mut report = Vec::new();
    for scene in &scenes() {
        let name = scene.file_name().unwrap().to_string_lossy().to_string();
        let dir = tempfile::tempdir().unwrap();
        let (ours, theirs) = render_both(&small_scene(scene, dir.path()), dir.path());
        let (ours, theirs) = (
            image::open(&ours).unwrap().to_rgb8(),
            image::open(&theirs).unwrap().to_rgb8(),
        );
        let differ = ours
            .pixels()
            .zip(theirs.pixels())
            .filter(|(a, b)| (0..3).any(|c| a.0[c].abs_diff(b.0[c]) > 1))
            .count();
        report.push(format!("{name}: {differ} pixels differ by more than 1/255"));
        assert!(
            differ * 100 <= (SIZE * SIZE) as usize,
            "{name}: {differ} of {} pixels differ by more than 1/255",
            SIZE * SIZE
        );
    }
    eprintln!("{}", report.join("\n"));
}
