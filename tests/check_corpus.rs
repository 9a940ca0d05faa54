//! Every real course scene in `tests/corpus/field` checks (warnings
//! allowed), except the one whose headup is parallel to its normal.

mod support;

use raytracer::frontend::load;
use support::corpus_copy;

const PARALLEL: &str = "reflection_91b7c2f_headup010.txt";

#[test]
fn every_corpus_scene_checks_except_the_parallel_headup() {
    let (_dir, scenes) = corpus_copy();
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
