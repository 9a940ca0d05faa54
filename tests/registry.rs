//! The rule registry (src/language.rs) drives the check pass: for every
//! row whose rule a value can break, a scene that breaks it gets a
//! diagnostic on that line carrying a fix, whose message is the help line,
//! and applying the fixes leaves no error. Scenes are built from the
//! registry's own example lines, so a new row is covered without a new
//! test.

use std::path::Path;
use std::time::Instant;

use raytracer::ast::SectionKind;
use raytracer::fix::{self, Applicability};
use raytracer::frontend::{load_bytes, Loaded};
use raytracer::language::{attributes_of, rows, AttrSpec, Constraint, Key};

fn load(text: &str) -> Loaded {
    load_bytes("t.txt", Path::new("."), text.as_bytes(), Instant::now())
}

/// Values (as scene text) that break `spec`'s rule, one set per way to
/// break it; none for a rule no number breaks.
fn breaking(spec: &AttrSpec) -> Vec<Vec<f64>> {
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
    let line = format!(
        "{} {}",
        spec.name.as_str(),
        values
            .iter()
            .map(f64::to_string)
            .collect::<Vec<_>>()
            .join(" ")
    );
    let mut text = String::new();
    if spec.name != Key::Resolution {
        text.push_str("camera 4\n");
        text.push_str(kind.as_str());
        text.push('\n');
    }
    let line_number = text.lines().count() + 1;
    text.push_str(&line);
    text.push('\n');
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
                assert_eq!(
                    diagnostic.help.as_deref(),
                    Some(fix.message.as_str()),
                    "the help of `{}` is its fix's message",
                    diagnostic.code
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
        .find_map(|e| e.help)
        .expect("a help line");
    assert_eq!(
        help,
        "to keep the hue without clipping, write `color 1 0.333 0.333`"
    );
}
