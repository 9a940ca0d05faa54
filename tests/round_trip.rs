//! Round trips between scene text and JSON, through the real front end
//! (`frontend::load`, so files, folders and textures are as for the CLI):
//!
//! - every corpus scene and every file in scenes/ prints as canonical text
//!   and as JSON that both load back to the same model, bit for bit;
//! - text → JSON → text → JSON is a fixed point after one step;
//! - the same for generated valid scenes (proptest), with extreme numbers
//!   and texture paths that need quoting;
//! - the JSON is what the serde model reads, and docs/scene.schema.json is
//!   the schema generated from that model.

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use raytracer_scene::convert::json::{schema, to_json};
use raytracer_scene::convert::scene_text::to_scene_text;
use raytracer_scene::frontend::load;
use raytracer_scene::geometry;
use raytracer_scene::model::{self, Camera, Light, Material, Object, Scene, Shape};

const CORPUS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/corpus/field");
const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");
/// An error by docs/language.md: its headup is parallel to its normal.
const PARALLEL: &str = "reflection_91b7c2f_headup010.txt";
/// A 2 × 2 texture for scenes that name `wood_tex.ppm`.
const WOOD: &str = "P3\n2 2\n255\n160 82 45  139 69 19\n205 133 63  160 82 45\n";

/// The checked model of the scene at `path`; panics with the diagnostics
/// when it has errors.
fn model_of(path: &Path) -> Scene {
    let loaded = load(path).expect("readable");
    match loaded.checked {
        Some(checked) => checked.scene,
        None => panic!(
            "{} does not check:\n{}",
            path.display(),
            loaded.report.render_human(100, false)
        ),
    }
}

/// Bit-exact equality: JSON prints every f64 in its shortest exact form
/// (and `-0.0` as such), so equal JSON means equal bits.
fn assert_same(a: &Scene, b: &Scene, what: &str) {
    assert_eq!(to_json(a), to_json(b), "{what}");
    assert_eq!(a, b, "{what}");
}

/// Print `scene` both ways into `dir`, load both back, and check the round
/// trips. Returns the canonical text.
fn round_trip(scene: &Scene, dir: &Path, stem: &str) -> String {
    let text = to_scene_text(scene).expect("printable");
    let json = to_json(scene);
    let text_path = dir.join(format!("{stem}.canonical.txt"));
    let json_path = dir.join(format!("{stem}.json"));
    std::fs::write(&text_path, &text).unwrap();
    std::fs::write(&json_path, &json).unwrap();

    // parse(print(scene)) == scene, for both languages.
    let from_text = model_of(&text_path);
    assert_same(
        &from_text,
        scene,
        &format!("{stem}: text round trip\n{text}"),
    );
    let from_json = model_of(&json_path);
    assert_same(
        &from_json,
        scene,
        &format!("{stem}: JSON round trip\n{json}"),
    );

    // text → JSON → text → JSON: fixed after one step.
    assert_eq!(to_scene_text(&from_json).unwrap(), text, "{stem}");
    assert_eq!(to_json(&from_text), json, "{stem}");

    // The serde model reads the JSON as the front end does.
    let serde: Scene = serde_json::from_str(&json).expect("serde reads the JSON");
    assert_same(&serde, scene, &format!("{stem}: serde"));
    text
}

/// `dir` with the corpus and scenes/ copied in, and a texture beside them.
fn corpus_copy(dir: &Path) -> Vec<PathBuf> {
    let corpus = PathBuf::from(CORPUS);
    assert!(
        corpus.is_dir(),
        "the scene corpus is missing: expected {}",
        corpus.display()
    );
    let mut scenes = Vec::new();
    for (folder, prefix) in [(corpus, "corpus-"), (PathBuf::from(SCENES), "scenes-")] {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            let is_scene = name.ends_with(".txt") || name.ends_with(".scene");
            if !is_scene || name == "SOURCE.txt" || name == PARALLEL {
                continue;
            }
            let copy = dir.join(format!("{prefix}{name}"));
            std::fs::copy(&path, &copy).unwrap();
            scenes.push(copy);
        }
    }
    std::fs::write(dir.join("wood_tex.ppm"), WOOD).unwrap();
    scenes.sort();
    scenes
}

#[test]
fn every_corpus_and_example_scene_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = corpus_copy(dir.path());
    assert!(
        scenes.len() >= 11,
        "expected the 10 checkable corpus scenes and scenes/sample.txt, found {}",
        scenes.len()
    );
    for path in &scenes {
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        round_trip(&model_of(path), dir.path(), &stem);
    }
    eprintln!("{} scenes round-trip", scenes.len());
}

#[test]
fn canonical_text_of_the_sample() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("wood_tex.ppm"), WOOD).unwrap();
    let path = dir.path().join("sample.txt");
    std::fs::copy(Path::new(SCENES).join("sample.txt"), &path).unwrap();
    let text = round_trip(&model_of(&path), dir.path(), "sample");
    assert_eq!(
        text,
        "camera 400\n\nsphere\n  dimension 1\n  center 0 1 -5\n  color 0.3 0.3 0.3\n  \
         reflectivity 0.7\n\nplane\n  dimension 4 4\n  center 0 -1 -5\n  normal 0 1 0\n  \
         headup 0 0 1\n  texture wood_tex.ppm\n\nlight\n  location -1 2 -2\n  color 1 0.7 0.7\n\n\
         light\n  location 1 0 -6\n  color 0.3 0.3 1\n"
    );
}

#[test]
fn committed_schema_is_the_generated_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scene.schema.json");
    let generated = schema();
    if std::env::var_os("UPDATE_SCHEMA").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "docs/scene.schema.json is stale; regenerate it with \
         `UPDATE_SCHEMA=1 cargo test --release --test integration round_trip::committed_schema`"
    );
    let schema: serde_json::Value = serde_json::from_str(&committed).unwrap();
    assert_eq!(schema["title"], "Scene");
    let required = schema["required"].as_array().unwrap();
    assert!(required.contains(&"format".into()) && required.contains(&"camera".into()));
}

/// Texture files the generated scenes may name, all present in the folder
/// they are loaded from; the odd names need quoting in scene text.
const TEXTURES: [&str; 4] = [
    "wood_tex.ppm",
    "my wood.ppm",
    "say \"cheese\" \\ #1.ppm",
    "color",
];

/// Finite numbers, biased to the edges: zero of both signs, subnormals,
/// huge values, and ordinary ones.
fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -100.0..100.0f64,
        1 => Just(-0.0),
        1 => Just(0.0),
        1 => Just(5e-324),
        1 => Just(1e300),
        1 => Just(-1.7976931348623157e308),
        2 => any::<f64>().prop_filter("finite", |x| x.is_finite()),
    ]
}

fn positive() -> impl Strategy<Value = f64> {
    number().prop_map(f64::abs).prop_filter("> 0", |x| *x > 0.0)
}

fn unit_interval() -> impl Strategy<Value = f64> {
    prop_oneof![0.0..=1.0f64, Just(-0.0), Just(1.0), Just(5e-324)]
}

fn vector() -> impl Strategy<Value = [f64; 3]> {
    [number(), number(), number()]
}

fn material() -> impl Strategy<Value = Material> {
    (
        [unit_interval(), unit_interval(), unit_interval()],
        unit_interval(),
        proptest::option::weighted(0.3, proptest::sample::select(&TEXTURES[..])),
    )
        .prop_map(|(color, reflectivity, texture)| Material {
            color,
            reflectivity,
            texture: texture.map(str::to_string),
        })
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (vector(), positive()).prop_map(|(center, radius)| Shape::Sphere { center, radius }),
        (vector(), positive(), positive(), vector(), vector())
            .prop_filter("a plane needs a basis", |(_, _, _, n, h)| {
                geometry::plane_basis(*n, *h).is_some()
            })
            .prop_map(|(center, width, height, normal, headup)| Shape::Plane {
                center,
                width,
                height,
                normal,
                headup,
            }),
    ]
}

fn scene() -> impl Strategy<Value = Scene> {
    (
        1..=16384u32,
        proptest::collection::vec((shape(), material()), 0..4),
        proptest::collection::vec((vector(), (positive(), unit_interval(), number())), 0..3),
    )
        .prop_map(|(resolution, objects, lights)| Scene {
            format: model::FORMAT.to_string(),
            camera: Camera { resolution },
            objects: objects
                .into_iter()
                .map(|(shape, material)| Object { shape, material })
                .collect(),
            lights: lights
                .into_iter()
                .map(|(location, (r, g, b))| Light {
                    location,
                    color: [r, g, b.abs()],
                })
                .collect(),
        })
}

/// Run on a thread with a large stack: the strategy's value trees (a
/// scene of tuples of tuples) are large values, and the tests are built
/// without optimisation, which moves them through the stack whole.
#[test]
fn generated_scenes_round_trip() {
    let run = || {
        let config = ProptestConfig {
            cases: 256,
            source_file: Some(file!()),
            ..ProptestConfig::default()
        };
        let result = proptest::test_runner::TestRunner::new(config).run(&scene(), |scene| {
            let dir = tempfile::tempdir().unwrap();
            for name in TEXTURES {
                std::fs::write(dir.path().join(name), WOOD).unwrap();
            }
            round_trip(&scene, dir.path(), "generated");
            Ok(())
        });
        if let Err(failure) = result {
            panic!("{failure}");
        }
    };
    std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(run)
        .expect("a thread")
        .join()
        .expect("every generated scene round-trips");
}
