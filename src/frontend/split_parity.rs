//! The two-thread check against the one-thread check: cut at every safe
//! cut of every scene text in the repository and of generated and mutated
//! scenes, the same report (every diagnostic, its spans and its order) and
//! the same checked scene.

use std::path::Path;
use std::time::Instant;

use proptest::prelude::*;

use super::*;

/// The human report and the checked scene of `text`, cut at `cut` or
/// read on one thread.
fn run(name: &str, dir: &Path, text: &str, cut: Option<usize>) -> (String, String) {
    let (source, utf8_error) = SourceFile::from_bytes(name, dir, text.as_bytes());
    let diagnostics = utf8_error
        .into_iter()
        .map(|e| (Box::new(e) as BoxedDiagnostic, None))
        .collect();
    let start = Instant::now();
    let loaded = load_text_cut_at::<Collect>(source, diagnostics, Language::Text, start, cut);
    (
        loaded.report.render_human(100, false),
        format!("{:?}", loaded.checked),
    )
}

/// Every safe cut of `text` checked against one run; how many of them
/// joined (the rest fell back to one run, equal by construction).
fn assert_every_cut_agrees(name: &str, dir: &Path, text: &str) -> usize {
    let whole = run(name, dir, text, None);
    let mut joined = 0;
    let mut from = 0;
    while let Some(cut) = split::cut_at_or_after(text, from) {
        assert_eq!(
            run(name, dir, text, Some(cut)),
            whole,
            "{name} cut at {cut}"
        );
        let (source, _) = SourceFile::from_bytes(name, dir, text.as_bytes());
        joined += usize::from(on_two_threads::<Collect>(&source, cut).is_some());
        from = cut;
    }
    joined
}

#[test]
fn every_cut_of_every_scene_text_in_the_repository_agrees() {
    let mut joined = 0;
    let mut scenes = 0;
    let mut paths = Vec::new();
    for dir in ["scenes", "tests/corpus/field", "tests/ui"] {
        super::summary_parity::scenes_under(Path::new(dir), &mut paths);
    }
    for path in paths
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e != "json"))
    {
        let bytes = std::fs::read(path).expect("scene readable");
        let text = String::from_utf8_lossy(&bytes);
        let folder = path.parent().expect("a scene has a folder");
        joined += assert_every_cut_agrees(&path.display().to_string(), folder, &text);
        scenes += 1;
    }
    assert!(scenes > 40, "found {scenes}");
    assert!(joined > 50, "only {joined} cuts joined");
}

/// A section, valid or not, with the tokens that run to a line's end
/// (comments, unterminated strings) and the line ends the parser knows.
fn section() -> impl Strategy<Value = String> {
    let n = || prop::sample::select(vec!["0", "1", "-1", "2", "-5", "0.5", "1e999", "x"]);
    let v = move || (n(), n(), n()).prop_map(|(a, b, c)| format!("{a} {b} {c}"));
    let junk = prop::sample::select(vec![
        "",
        "# sphere\n",
        "\"open sphere\n",
        "\u{2028}",
        "\r\n",
        "sphre 1\n",
        "1 2\n",
        "\u{85}",
        "camera 8\n",
    ]);
    let body = prop_oneof![
        (n(), v(), any::<bool>()).prop_map(|(r, c, textured)| {
            let texture = if textured {
                " texture wood_tex.ppm"
            } else {
                ""
            };
            format!("sphere dimension {r}\n center {c}{texture}")
        }),
        (v(), v()).prop_map(|(c, normal)| format!(
            "plane dimension 1 1 center {c} normal {normal} headup 0 1 0"
        )),
        (v(), v()).prop_map(|(l, c)| format!("light location {l}\ncolor {c}")),
    ];
    (junk, body).prop_map(|(junk, body)| format!("{junk}{body}\n"))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    #[test]
    fn every_cut_of_generated_scenes_agrees(
        sections in prop::collection::vec(section(), 0..40),
    ) {
        let text = format!("camera 4\n{}", sections.concat());
        assert_every_cut_agrees("t.txt", Path::new("scenes"), &text);
    }
}
