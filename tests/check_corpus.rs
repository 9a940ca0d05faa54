//! Every real course scene in `../shared/corpus/field` checks (warnings
//! allowed), except the one whose headup is parallel to its normal.
//! `RAYTRACER_CORPUS` overrides where the corpus is (for git worktrees that
//! do not have `shared/` beside them).

use std::path::PathBuf;

use raytracer::commands::load;

const CORPUS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/corpus/field");
const PARALLEL: &str = "reflection_91b7c2f_headup010.txt";

/// The corpus copied into a temporary folder with a small `wood_tex.ppm`
/// beside it, and the scene files in it.
fn corpus() -> (tempfile::TempDir, Vec<PathBuf>) {
    let source =
        std::env::var_os("RAYTRACER_CORPUS").map_or_else(|| PathBuf::from(CORPUS), PathBuf::from);
    assert!(
        source.is_dir(),
        "the scene corpus is missing: expected {} (clone the repository with `shared/` \
         beside it, or set RAYTRACER_CORPUS)",
        source.display()
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let mut scenes = Vec::new();
    for entry in std::fs::read_dir(&source).expect("read corpus") {
        let path = entry.expect("corpus entry").path();
        let name = path.file_name().expect("file name");
        if name == "SOURCE.txt" {
            continue;
        }
        let copy = dir.path().join(name);
        std::fs::copy(&path, &copy).expect("copy scene");
        scenes.push(copy);
    }
    scenes.sort();
    std::fs::write(
        dir.path().join("wood_tex.ppm"),
        "P3\n2 2\n255\n160 82 45  139 69 19\n205 133 63  160 82 45\n",
    )
    .expect("write texture");
    (dir, scenes)
}

#[test]
fn every_corpus_scene_checks_except_the_parallel_headup() {
    let (_dir, scenes) = corpus();
    assert!(
        scenes.len() >= 11,
        "expected the 11 corpus scenes, found {}",
        scenes.len()
    );
    for scene in &scenes {
        let loaded = load(scene).expect("readable");
        let name = scene.file_name().unwrap().to_string_lossy();
        let codes: Vec<String> = loaded
            .report
            .entries()
            .filter(|e| e.severity == "error")
            .map(|e| e.code)
            .collect();
        if name == PARALLEL {
            assert_eq!(codes, ["scene::headup_parallel_to_normal"], "{name}");
            assert!(loaded.checked.is_none(), "{name}");
        } else {
            assert_eq!(codes, Vec::<String>::new(), "{name}");
            assert!(loaded.checked.is_some(), "{name} did not produce a scene");
        }
    }
}
