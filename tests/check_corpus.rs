//! Every real course scene in `tests/corpus/field` checks (warnings
//! allowed); the one whose headup is parallel to its normal is warned
//! about and rendered with the stand-in headup its warning names.

use crate::support::corpus_copy;
use raytracer_scene::frontend::load;

const PARALLEL: &str = "reflection_91b7c2f_headup010.txt";

#[test]
fn every_corpus_scene_checks() {
    let (_dir, scenes) = corpus_copy();
    assert!(
        scenes.len() >= 11,
        "expected the 11 corpus scenes, found {}",
        scenes.len()
    );
    for scene in &scenes {
        let loaded = load(scene).expect("readable");
        let name = scene.file_name().unwrap().to_string_lossy();
        let errors: Vec<String> = loaded
            .report
            .entries()
            .filter(|e| e.severity == "error")
            .map(|e| e.code)
            .collect();
        assert_eq!(errors, Vec::<String>::new(), "{name}");
        assert!(loaded.checked.is_some(), "{name} did not produce a scene");
        let parallel = loaded
            .report
            .entries()
            .filter(|e| e.code == "scene::headup_parallel_to_normal")
            .count();
        assert_eq!(parallel, usize::from(name == PARALLEL), "{name}");
    }
}
