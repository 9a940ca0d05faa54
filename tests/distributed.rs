//! docs/distributed.md's GNU parallel recipe, run as written: the block
//! under "GNU parallel on one machine" renders N tiles with `parallel` and
//! stitches them, and the frame is the whole render, pixel for pixel, with
//! statistics that sum to the whole render's. Run for the recipe's N and for
//! N = the row count (one row a tile).
//!
//! GNU parallel is a Debian package (`parallel`) that .ci/run installs;
//! without it the test fails under CI (`support::under_ci`) and says it was skipped
//! otherwise.

use crate::support;

use std::path::Path;

use serde_json::Value;

/// 21 rows, with a light, a mirror and a texture.
const SCENE: &str = "camera 21
sphere dimension 1 center 0 .5 -4 reflectivity .6 color .4 .5 .6
plane dimension 6 6 center 0 -1 -4 normal 0 1 0 headup 0 0 1 texture wood_tex.ppm
light location -1 2 0 color 1 .8 .8
";
const TEXTURE: &str = "P3 2 2 255\n255 0 0  0 255 0\n0 0 255  250 250 250\n";

fn json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).expect("read JSON")).expect("JSON")
}

#[test]
fn the_parallel_recipe_stitches_the_whole_render() {
    if !support::tool_available(
        "parallel",
        "the distributed recipe",
        "apt-get install parallel",
    ) {
        return;
    }
    let recipe = support::doc_recipe("docs/distributed.md", "## GNU parallel on one machine");
    assert!(recipe.contains("N=8\n"), "the recipe sets N: {recipe}");
    for n in [8, 21] {
        let dir = tempfile::tempdir().expect("temp dir");
        let d = dir.path();
        std::fs::write(d.join("scene.txt"), SCENE).unwrap();
        std::fs::write(d.join("wood_tex.ppm"), TEXTURE).unwrap();
        let output = support::run_recipe(d, &recipe.replace("N=8\n", &format!("N={n}\n")));
        assert!(
            output.status.success(),
            "the recipe failed for N = {n}:\n{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
        let whole = support::run(&[
            "render",
            d.join("scene.txt").to_str().unwrap(),
            d.join("whole.png").to_str().unwrap(),
            "--stats-json",
            d.join("whole.json").to_str().unwrap(),
        ]);
        assert!(
            whole.status.success(),
            "{}",
            String::from_utf8_lossy(&whole.stderr)
        );
        let decode = |name: &str| image::open(d.join(name)).expect(name).to_rgb8().into_raw();
        assert_eq!(decode("frame.png"), decode("whole.png"), "N = {n}");

        let (frame, whole) = (json(&d.join("frame.json")), json(&d.join("whole.json")));
        assert_eq!(frame["tiles"], n);
        for counter in [
            "primary_rays",
            "shadow_rays",
            "reflection_rays",
            "texture_lookups",
        ] {
            assert_eq!(frame[counter], whole[counter], "{counter}, N = {n}");
        }
    }
}
