//! The language table (crates/scene/src/language.rs) is the one source of the
//! attribute table in docs/language.md, and its examples are valid scene
//! text.

use std::path::Path;

use raytracer_scene::ast::SectionKind;
use raytracer_scene::frontend::load_bytes;
use raytracer_scene::language::{attributes_of, markdown_table};

const BEGIN: &str = "<!-- attribute table: generated from crates/scene/src/language.rs -->\n";
const END: &str = "<!-- end of attribute table -->";

#[test]
fn the_docs_table_is_the_generated_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/language.md");
    let page = std::fs::read_to_string(&path).expect("read docs/language.md");
    let start = page
        .find(BEGIN)
        .expect("docs/language.md has the table's start marker")
        + BEGIN.len();
    let end = page[start..].find(END).expect("and its end marker") + start;
    let generated = markdown_table();
    if std::env::var_os("UPDATE_DOCS").is_some() {
        let updated = format!("{}{generated}{}", &page[..start], &page[end..]);
        std::fs::write(&path, updated).expect("write docs/language.md");
    } else {
        assert!(
            page[start..end] == generated,
            "the attribute table in docs/language.md is stale; regenerate it with \
             `UPDATE_DOCS=1 cargo test --release --test integration language_table::`"
        );
    }
}

#[test]
fn every_example_is_valid_scene_text() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for kind in [SectionKind::Sphere, SectionKind::Plane, SectionKind::Light] {
        let lines: Vec<&str> = attributes_of(&kind).iter().map(|s| s.example).collect();
        let text = format!("camera 4\n{}\n  {}\n", kind.as_str(), lines.join("\n  "));
        let loaded = load_bytes("t.txt", &dir, text.as_bytes());
        assert!(
            loaded.checked.is_some(),
            "{text}{}",
            loaded.report.render_human(80, false)
        );
    }
}
