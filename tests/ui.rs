//! UI tests: one fixture per diagnostic code in `tests/ui/<namespace>/<name>.txt`
//! (`.json` for the `json` namespace, whose fixtures are JSON scenes) with an
//! insta snapshot of its human rendering (plain Unicode, 80 columns)
//! in `tests/ui/snapshots/`.
//!
//! Coverage cannot drift: every code of the diagnostic enums (derived from
//! their variant names, `codes()`) must have a fixture that produces it,
//! every fixture must be named after a code, and docs/diagnostics/ must
//! have a section per code, on the page and at the anchor its links name,
//! showing the fixture's current output. Every code
//! either carries a fix in its fixture (snapshotted as JSON) or is on
//! [`raytracer_scene::fix::WITHOUT_FIX`], whose reason its section states.
//! Beside them, `tests/ui/cascade/` holds scenes whose mistakes once drew
//! a message too many, or two that contradicted each other, each with the
//! number of its mistakes and a snapshot of what `check` says.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use raytracer_scene::check::CheckError;
use raytracer_scene::fix::{documentation, markdown_table, WITHOUT_FIX, WITH_FIX};
use raytracer_scene::frontend::Loaded;
use raytracer_scene::json::JsonError;
use raytracer_scene::syntax::SyntaxError;

/// Each namespace's fixture folder and the extension of its fixtures.
const NAMESPACES: [(&str, &str); 3] = [("syntax", "txt"), ("scene", "txt"), ("json", "json")];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every fixture, as a path relative to the repository (so rendered file
/// names and texture paths do not depend on where the repository is).
fn fixtures() -> Vec<PathBuf> {
    let mut fixtures = Vec::new();
    for (namespace, extension) in NAMESPACES {
        let dir = Path::new("tests/ui").join(namespace);
        for entry in std::fs::read_dir(root().join(&dir)).expect("fixture dir") {
            let name = entry.expect("fixture").file_name();
            let path = dir.join(name);
            if path.extension().is_some_and(|e| e == extension) {
                fixtures.push(path);
            }
        }
    }
    fixtures.sort();
    fixtures
}

/// A fixture checked as `check` would, by its path relative to the
/// repository, so rendered file names and texture paths are the same
/// wherever the repository is. Cargo starts the suite in its package's
/// folder (`tests/`); the first fixture loaded moves the process to the
/// repository's, once (no other test of this binary reads files by
/// relative paths, and the commands the tests spawn are given theirs).
fn load(fixture: &Path) -> Loaded {
    static IN_REPOSITORY: std::sync::OnceLock<()> = std::sync::OnceLock::new();
    IN_REPOSITORY.get_or_init(|| {
        std::env::set_current_dir(root()).expect("the repository is a folder");
    });
    raytracer_scene::frontend::load(fixture).expect("fixture readable")
}

/// `syntax::invalid_number` for `tests/ui/syntax/invalid_number.txt`.
fn code_of(fixture: &Path) -> String {
    let namespace = fixture
        .parent()
        .and_then(Path::file_name)
        .expect("namespace");
    let name = fixture.file_stem().expect("name");
    format!(
        "{}::{}",
        namespace.to_string_lossy(),
        name.to_string_lossy()
    )
}

fn listed_codes() -> BTreeSet<String> {
    CheckError::codes()
        .into_iter()
        .chain(SyntaxError::codes())
        .chain(JsonError::codes())
        .collect()
}

#[test]
fn every_fixture_renders_as_its_snapshot() {
    let fixtures = fixtures();
    assert!(!fixtures.is_empty());
    for fixture in fixtures {
        let code = code_of(&fixture);
        let loaded = load(&fixture);
        let codes: Vec<String> = loaded.report.entries().map(|e| e.code).collect();
        assert!(
            codes.contains(&code),
            "{} should report `{code}`, reported {codes:?}",
            fixture.display()
        );
        let rendered = loaded.report.render_human(80, false);
        insta::with_settings!({
            snapshot_path => "ui/snapshots",
            prepend_module_to_snapshot => false,
            omit_expression => true,
        }, {
            insta::assert_snapshot!(code.replace("::", "-"), rendered);
        });
    }
}

#[test]
fn every_code_is_listed_and_has_a_fixture() {
    let listed = listed_codes();
    let with_fixture: BTreeSet<String> = fixtures().iter().map(|f| code_of(f)).collect();
    let missing: Vec<_> = listed.difference(&with_fixture).collect();
    assert!(
        missing.is_empty(),
        "codes without a fixture in tests/ui: {missing:?}"
    );
    let stale: Vec<_> = with_fixture.difference(&listed).collect();
    assert!(stale.is_empty(), "fixtures named after no code: {stale:?}");
}

/// Scenes whose mistakes once drew more messages than there are mistakes,
/// or messages that contradict each other (issue 56): `tests/ui/cascade/`,
/// each fixture's first line saying how many mistakes it holds (`# 1
/// mistake: …`). Each reports that many diagnostics, rendered as its
/// snapshot (`cascade-<name>`).
#[test]
fn one_mistake_is_one_message() {
    let dir = Path::new("tests/ui/cascade");
    let mut fixtures: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .expect("tests/ui/cascade")
        .map(|entry| dir.join(entry.expect("fixture").file_name()))
        .filter(|path| path.extension().is_some_and(|e| e == "txt"))
        .collect();
    fixtures.sort();
    assert!(!fixtures.is_empty());
    for fixture in fixtures {
        let text = std::fs::read_to_string(root().join(&fixture)).expect("fixture");
        let mistakes: usize = text
            .strip_prefix("# ")
            .and_then(|rest| rest.split_once(' '))
            .and_then(|(n, rest)| rest.starts_with("mistake").then(|| n.parse().ok())?)
            .unwrap_or_else(|| panic!("{} should start `# N mistakes`", fixture.display()));
        let loaded = load(&fixture);
        let codes: Vec<String> = loaded.report.entries().map(|e| e.code).collect();
        assert_eq!(
            codes.len(),
            mistakes,
            "{}: {mistakes} mistakes, reported {codes:?}",
            fixture.display()
        );
        let rendered = loaded.report.render_human(80, false);
        let name = fixture.file_stem().expect("name").to_string_lossy();
        insta::with_settings!({
            snapshot_path => "ui/snapshots",
            prepend_module_to_snapshot => false,
            omit_expression => true,
        }, {
            insta::assert_snapshot!(format!("cascade-{name}"), rendered);
        });
    }
}

/// Lines without trailing whitespace, without leading or trailing blank lines.
fn normalized(text: &str) -> String {
    let lines: Vec<&str> = text.lines().map(str::trim_end).collect();
    lines.join("\n").trim_matches('\n').to_string()
}

/// The section of `code` in docs/ (its heading, the code in backticks, to
/// the next), found where its links say: on the page and at the anchor of
/// [`documentation`], the address docs/diagnostics.md's tables, the
/// language server and the preview link it by.
fn doc_section(code: &str) -> String {
    let link = documentation(code);
    let (page, anchor) = link.split_once('#').expect("a page and an anchor");
    let text = std::fs::read_to_string(root().join("docs").join(page))
        .unwrap_or_else(|e| panic!("docs/{page}, where `{code}` links: {e}"));
    let heading = format!("\n## `{code}`\n");
    let start = text
        .find(&heading)
        .unwrap_or_else(|| panic!("docs/{page} has no section `## `{code}``"))
        + heading.len();
    // GitHub's anchor of the heading: the code without its backticks and colons.
    assert_eq!(anchor, code.replace("::", ""), "{code}");
    let section = &text[start..];
    section[..section.find("\n## ").unwrap_or(section.len())].to_string()
}

#[test]
fn docs_show_every_code_as_rendered() {
    for fixture in fixtures() {
        let code = code_of(&fixture);
        let section = doc_section(&code);
        for part in ["**What.**", "**Why.**", "**Example.**", "**Fix.**"] {
            assert!(
                section.contains(part),
                "`{code}` in docs/diagnostics/ lacks {part}"
            );
        }
        let rendered = load(&fixture).report.render_human(80, false);
        assert!(
            normalized(&section).contains(&normalized(&rendered)),
            "the example for `{code}` in docs/diagnostics/ is out of date; it should show:\n{rendered}"
        );
    }
}

#[test]
fn fixes_show_in_the_json_format() {
    let mut with_fixes = Vec::new();
    for fixture in fixtures() {
        let loaded = load(&fixture);
        let fixed: Vec<_> = loaded
            .report
            .entries()
            .filter(|e| e.fix.is_some())
            .collect();
        if fixed.is_empty() {
            continue;
        }
        let code = code_of(&fixture);
        // Each fix is applied as the registry says.
        if let Some(rule) = WITH_FIX.iter().find(|rule| rule.code == code) {
            for entry in fixed.iter().filter(|e| e.code == code) {
                let applicability = entry.fix.as_ref().expect("a fix").applicability;
                assert!(
                    rule.applicability.contains(&applicability),
                    "`{code}`: a {applicability:?} fix, fix::WITH_FIX says {:?}",
                    rule.applicability
                );
            }
        }
        with_fixes.push(code);
        let json = serde_json::to_string_pretty(&fixed).expect("serialise");
        insta::with_settings!({
            snapshot_path => "ui/snapshots",
            prepend_module_to_snapshot => false,
            omit_expression => true,
        }, {
            insta::assert_snapshot!(format!("{}-fix", code_of(&fixture).replace("::", "-")), json);
        });
    }
    // Every code either carries a fix in its fixture or is on the list of
    // codes without one, with its reason, and not both; the fix registry
    // lists exactly the codes with a fix.
    let without: BTreeSet<&str> = WITHOUT_FIX.iter().map(|(code, _)| *code).collect();
    let registered: BTreeSet<&str> = WITH_FIX.iter().map(|rule| rule.code).collect();
    assert_eq!(
        registered,
        with_fixes
            .iter()
            .map(String::as_str)
            .collect::<BTreeSet<_>>(),
        "fix::WITH_FIX lists the codes whose fixtures carry a fix"
    );
    for code in listed_codes() {
        let fixed = with_fixes.contains(&code);
        let listed = without.contains(code.as_str());
        assert!(
            fixed != listed,
            "`{code}`: {}",
            if fixed {
                "its fixture carries a fix, yet it is on fix::WITHOUT_FIX"
            } else {
                "its fixture carries no fix and it is not on fix::WITHOUT_FIX with a reason"
            }
        );
    }
    let stale: Vec<_> = without
        .iter()
        .filter(|code| !listed_codes().contains(**code))
        .collect();
    assert!(
        stale.is_empty(),
        "fix::WITHOUT_FIX names no code: {stale:?}"
    );
}

const FIX_TABLE_BEGIN: &str = "<!-- fix table: generated from crates/scene/src/fix.rs -->\n";
const FIX_TABLE_END: &str = "<!-- end of fix table -->";

/// The table of fixes in docs/diagnostics.md is the one the registry
/// writes (`UPDATE_DOCS=1` rewrites it).
#[test]
fn the_docs_table_of_fixes_is_the_generated_one() {
    let path = root().join("docs/diagnostics.md");
    let page = std::fs::read_to_string(&path).expect("read docs/diagnostics.md");
    let start = page
        .find(FIX_TABLE_BEGIN)
        .expect("docs/diagnostics.md has the fix table's start marker")
        + FIX_TABLE_BEGIN.len();
    let end = page[start..]
        .find(FIX_TABLE_END)
        .expect("and its end marker")
        + start;
    let generated = markdown_table();
    if std::env::var_os("UPDATE_DOCS").is_some() {
        let updated = format!("{}{generated}{}", &page[..start], &page[end..]);
        std::fs::write(&path, updated).expect("write docs/diagnostics.md");
    } else {
        assert!(
            page[start..end] == generated,
            "the table of fixes in docs/diagnostics.md is stale; regenerate it with \
             `UPDATE_DOCS=1 cargo test --release --test integration ui::the_docs_table_of_fixes`"
        );
    }
}

#[test]
fn docs_give_the_reason_a_code_has_no_fix() {
    for (code, reason) in WITHOUT_FIX {
        let section = doc_section(code);
        let line = format!("No structured fix: {reason}.");
        assert!(
            section.contains(&line),
            "the section of `{code}` in docs/diagnostics/ should say `{line}`"
        );
    }
}

/// The **Fix.** paragraph of `code` in docs/diagnostics/.
fn fix_paragraph(code: &str) -> String {
    let section = doc_section(code);
    let fix = section.find("**Fix.**").expect("a Fix paragraph");
    section[fix..]
        .split("\n\n")
        .next()
        .unwrap_or_default()
        .to_string()
}

/// What docs/diagnostics/ says each fix does is what the program does:
/// a code whose fixture carries a fix says whether it is safe or unsafe
/// as the fix is, and the edits of `headup_not_perpendicular`'s fix leave
/// the `normal` as written, as language.md says (the page once said
/// `--fix` normalised it).
#[test]
fn docs_say_what_each_fix_does() {
    let mut wrong = Vec::new();
    for fixture in fixtures() {
        let code = code_of(&fixture);
        let loaded = load(&fixture);
        let Some(fix) = loaded
            .report
            .entries()
            .filter(|e| e.code == code)
            .find_map(|e| e.fix)
        else {
            continue;
        };
        let paragraph = fix_paragraph(&code);
        let word = match fix.applicability {
            raytracer_scene::fix::Applicability::Safe => "safe",
            raytracer_scene::fix::Applicability::Unsafe => "unsafe",
        };
        let says = paragraph.match_indices(word).any(|(at, _)| {
            !paragraph[..at].ends_with(|c: char| c.is_alphabetic())
                && !paragraph[at + word.len()..].starts_with(|c: char| c.is_alphabetic())
        });
        if !says {
            wrong.push(format!(
                "`{code}` should say its fix is {word}: {paragraph}"
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    let fixture = Path::new("tests/ui/scene/headup_not_perpendicular.txt");
    let loaded = load(fixture);
    let text = std::fs::read_to_string(root().join(fixture)).expect("fixture");
    let fixes = loaded
        .report
        .fixes_up_to(raytracer_scene::fix::Applicability::Unsafe);
    let (fixed, _) = raytracer_scene::fix::apply(&text, fixes);
    let normal = |t: &str| {
        t.lines()
            .find(|l| l.trim_start().starts_with("normal"))
            .map(str::to_string)
    };
    assert_eq!(normal(&fixed), normal(&text), "--fix leaves the normal");
    assert!(!fix_paragraph("scene::headup_not_perpendicular").contains("normalises the normal"));
}
