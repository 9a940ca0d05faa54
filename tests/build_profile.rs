//! The dependency choices that keep a cold build short
//! (docs/performance.md, "Build time"), held where a `cargo update` could
//! undo them silently: the lock file must not bring back the crates they
//! keep out of the build.

/// Crates the lock file keeps out, each with the choice that does it.
const KEPT_OUT: [(&str, &str); 4] = [
    (
        "backtrace",
        "miette's `fancy-no-backtrace` feature (Cargo.toml)",
    ),
    (
        "icu_segmenter",
        "textwrap 0.16.2, whose line breaking is the small unicode-linebreak crate (`cargo update -p textwrap --precise 0.16.2`)",
    ),
    (
        "icu_normalizer",
        "idna_adapter 1.1, the unicode-rs back end of url's `idna` (`cargo update -p idna_adapter --precise 1.1.0`)",
    ),
    (
        "icu_properties",
        "idna_adapter 1.1, the unicode-rs back end of url's `idna` (`cargo update -p idna_adapter --precise 1.1.0`)",
    ),
];

fn locked_packages(lock: &str) -> Vec<&str> {
    lock.lines()
        .filter_map(|line| line.strip_prefix("name = \""))
        .filter_map(|rest| rest.strip_suffix('"'))
        .collect()
}

#[test]
fn the_lock_files_keep_the_heavy_crates_out() {
    let root = env!("CARGO_MANIFEST_DIR");
    for lock in ["Cargo.lock", "fuzz/Cargo.lock"] {
        let text = std::fs::read_to_string(format!("{root}/{lock}")).expect("the lock file reads");
        let packages = locked_packages(&text);
        assert!(packages.contains(&"miette"), "{lock} lists no packages");
        for (crate_name, choice) in KEPT_OUT {
            assert!(
                !packages.contains(&crate_name),
                "{lock} brings `{crate_name}` back into the build; restore {choice}"
            );
        }
    }
}
