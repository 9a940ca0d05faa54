//! The rule registry (crates/scene/src/language.rs) drives the check pass: for every
//! row whose rule a value can break, a scene that breaks it gets a
//! diagnostic on that line carrying a fix, whose message is the help line,
//! and applying the fixes leaves no error. The same holds for every row's
//! wrong value counts and missing lines that have a mechanical remedy.
//! Scenes are built from the registry's own example lines, so a new row is
//! covered without a new test.

use std::path::Path;

use raytracer_scene::ast::SectionKind;
use raytracer_scene::fix::{self, Applicability};
use raytracer_scene::frontend::{load_bytes, Loaded};
use raytracer_scene::language::{attributes_of, rows, Arity, AttrSpec, Constraint, Key};

fn load(text: &str) -> Loaded {
    load_bytes("t.txt", Path::new("."), text.as_bytes())
}

/// Values (as scene text) that break `spec`'s rule, one set per way to
/// break it; none for a rule no number breaks. The fix property test
/// (tests/fix_never_worse.rs) breaks rules the same ways.
pub fn breaking(spec: &AttrSpec) -> Vec<Vec<f64>> {
    let n = spec.count();
    match spec.constraint {
        Constraint::Any | Constraint::Image => Vec::new(),
        Constraint::Range { min, max, .. } => vec![vec![max + 0.5; n], vec![min - 0.5; n]],
        Constraint::Positive => vec![vec![0.0; n], vec![-2.0; n]],
        Constraint::NonNegative { warn_above } => vec![vec![-1.0; n], vec![warn_above * 2.0; n]],
        Constraint::NonZero { .. } => vec![vec![0.0; n]],
        Constraint::Whole { min, max } => vec![
            vec![f64::from(max) + 1.0],
            vec![f64::from(min) - 1.0],
            vec![f64::from(min) + 0.5],
        ],
    }
}

/// A valid scene whose line for `spec` in a `kind` section says `values`.
fn scene_with(kind: &SectionKind, spec: &AttrSpec, values: &[f64]) -> (String, usize) {
    let values: Vec<String> = values.iter().map(f64::to_string).collect();
    let line = format!("{} {}", spec.name.as_str(), values.join(" "));
    scene_with_line(kind, spec, &line)
}

/// A valid scene whose line for `spec` in a `kind` section is `line`
/// (none when empty), and the number of that line.
fn scene_with_line(kind: &SectionKind, spec: &AttrSpec, line: &str) -> (String, usize) {
    let mut text = String::new();
    if spec.name != Key::Resolution {
        text.push_str("camera 4\n");
        text.push_str(kind.as_str());
        text.push('\n');
    }
    let line_number = text.lines().count() + 1;
    if !line.is_empty() {
        text.push_str(line);
        text.push('\n');
    }
    for other in attributes_of(kind) {
        if other.required && other.name != spec.name {
            text.push_str(other.example);
            text.push('\n');
        }
    }
    if *kind == SectionKind::Camera {
        text.push_str("light location 0 5 0 color 1 1 1\n");
    }
    (text, line_number)
}

#[test]
fn every_single_attribute_rule_reports_with_a_fix_that_clears_it() {
    let mut checked = 0;
    for (kind, spec) in rows() {
        for values in breaking(spec) {
            let (text, line) = scene_with(&kind, spec, &values);
            let loaded = load(&text);
            let on_line: Vec<_> = loaded
                .report
                .entries()
                .filter(|e| e.labels.first().is_some_and(|l| l.line == line))
                .collect();
            assert!(
                !on_line.is_empty(),
                "a diagnostic on line {line} of:\n{text}"
            );
            for diagnostic in &on_line {
                let fix = diagnostic
                    .fix
                    .as_ref()
                    .unwrap_or_else(|| panic!("`{}` carries no fix for:\n{text}", diagnostic.code));
                // The fix's message is the edit ("write `color 1 0 0`"),
                // which the help shows with its reason if it gives one.
                let help = diagnostic.help.as_deref().unwrap_or_default();
                assert!(
                    help.contains(fix.message.as_str()),
                    "the help of `{}` shows its fix's message `{}`: {help}",
                    diagnostic.code,
                    fix.message
                );
            }
            let diagnostic = &on_line[0];
            let (fixed, _) = fix::apply(&text, loaded.report.fixes_up_to(Applicability::Unsafe));
            let again = load(&fixed);
            assert_eq!(
                again.report.error_count(),
                0,
                "`{}`: the fixed scene still has errors:\n{fixed}\n{}",
                diagnostic.code,
                again.report.render_short()
            );
            assert!(
                !again.report.entries().any(|e| e.code == diagnostic.code),
                "`{}` is reported again after its fix:\n{fixed}",
                diagnostic.code
            );
            checked += 1;
        }
    }
    assert!(checked >= 14, "only {checked} broken rules were tried");
}

#[test]
fn fixes_write_numbers_short() {
    let loaded = load("camera 4\nlight location 0 5 0 color 3 1 1\n");
    let help = loaded
        .report
        .entries()
        .filter(|e| e.code == "scene::light_color_above_one")
        .find_map(|e| e.help)
        .expect("a help line");
    assert_eq!(
        help,
        "to keep the hue without clipping, write `color 1 0.333 0.333`"
    );
}

/// The fixes of `text` applied, unsafe ones too; the fixed text and its
/// check.
fn fixed(text: &str) -> (String, Loaded) {
    let loaded = load(text);
    let (fixed, _) = fix::apply(text, loaded.report.fixes_up_to(Applicability::Unsafe));
    let again = load(&fixed);
    (fixed, again)
}

/// For every row, the ways a line can have the wrong number of values or be
/// missing that have a mechanical remedy: a surplus value (dropped), a line
/// with no values (the row's example values written) and, for a required
/// row, no line at all (the row's example line added). Each is reported
/// with a fix, and the fixed scene no longer reports it and has no errors.
#[test]
fn every_row_fixes_wrong_counts_and_missing_lines() {
    let mut checked = 0;
    for (kind, spec) in rows() {
        let name = spec.name.as_str();
        let mut cases = vec![("scene::wrong_value_count", format!("{} 7", spec.example))];
        if spec.arity != Arity::Path {
            cases.push(("scene::wrong_value_count", name.to_string()));
        }
        if spec.required && spec.name != Key::Resolution {
            cases.push(("scene::missing_attribute", String::new()));
        }
        if spec.name == Key::Resolution {
            cases.push(("scene::missing_camera", String::new()));
        }
        for (code, line) in cases {
            let (text, _) = scene_with_line(&kind, spec, &line);
            let loaded = load(&text);
            let diagnostic = loaded
                .report
                .entries()
                .find(|e| e.code == code)
                .unwrap_or_else(|| panic!("`{code}` for:\n{text}"));
            assert!(
                diagnostic.fix.is_some(),
                "`{code}` carries no fix for:\n{text}"
            );
            let (fixed, again) = fixed(&text);
            assert!(
                !again.report.entries().any(|e| e.code == code),
                "`{code}` is reported again after its fix:\n{fixed}"
            );
            // A texture line keeps a path no test file answers to.
            let errors_left = if spec.arity == Arity::Path { 1 } else { 0 };
            assert_eq!(
                again.report.error_count(),
                errors_left,
                "`{code}`: the fixed scene has errors:\n{fixed}\n{}",
                again.report.render_short()
            );
            checked += 1;
        }
    }
    assert!(checked >= 30, "only {checked} cases were tried");
}

/// Attributes that belong to another section, values after a section
/// keyword and numbers in quotes are fixed too.
#[test]
fn misplaced_lines_section_values_and_quoted_numbers_are_fixed() {
    for (code, scene, expected) in [
        (
            "scene::misplaced_attribute",
            "camera 4\nsphere\n  dimension 1\n  normal 0 1 0\n  center 0 0 -5\n",
            "camera 4\nsphere\n  dimension 1\n  center 0 0 -5\n",
        ),
        (
            "scene::section_values",
            "camera 4\nsphere 1 2 # values\n  dimension 1 center 0 0 -5\n",
            "camera 4\nsphere # values\n  dimension 1 center 0 0 -5\n",
        ),
        (
            "scene::not_a_number",
            "camera 4\nsphere dimension \"-.5e1\" center 0 0 -5\n",
            "camera 4\nsphere dimension -.5e1 center 0 0 -5\n",
        ),
    ] {
        let loaded = load(scene);
        assert!(
            loaded
                .report
                .entries()
                .any(|e| e.code == code && e.fix.is_some()),
            "`{code}` with a fix for:\n{scene}"
        );
        let (text, again) = fixed(scene);
        assert_eq!(text, expected);
        assert!(!again.report.entries().any(|e| e.code == code), "{text}");
    }
}
