//! Code actions: each safe fix of the check pass ([`crate::check::fix`]) as
//! a `quickfix` on the attribute it rewrites, and all of a document's safe
//! fixes at once as `source.fixAll` (what `raytracer check --fix` writes).
//! Edits replace single numbers, so they apply to JSON scenes as well.

use std::collections::HashMap;

use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOrCommand, Diagnostic, Range, TextEdit, WorkspaceEdit,
};

use super::document::Document;
use super::position::LineIndex;
use crate::check::fix::{self, Fix};
use crate::frontend;

/// The actions for `range` of `document`; `only` is the client's filter on
/// kinds, and `diagnostics` those the client shows in the range.
pub fn actions(
    document: &Document,
    range: Range,
    only: Option<&[CodeActionKind]>,
    diagnostics: &[Diagnostic],
) -> Vec<CodeActionOrCommand> {
    let Some(file) = frontend::parse(document.language, &document.text).0 else {
        return Vec::new();
    };
    let fixes = fix::fixes(&file);
    let index = LineIndex::new(&document.text);
    let wanted = |kind: &CodeActionKind| {
        only.is_none_or(|only| {
            only.iter().any(|o| {
                kind.as_str() == o.as_str()
                    || kind.as_str().starts_with(&format!("{}.", o.as_str()))
            })
        })
    };
    let mut actions = Vec::new();
    if wanted(&CodeActionKind::QUICKFIX) {
        let (start, end) = (index.offset(range.start), index.offset(range.end));
        for fix in &fixes {
            let span = fix.edits.iter().fold(fix.at, |span, e| span.join(e.span));
            if span.start() > end || span.end() < start {
                continue;
            }
            let fix_range = index.range(span);
            // The diagnostics this fix answers: those with a label on it.
            let overlaps = |r: &Range| r.start <= fix_range.end && fix_range.start <= r.end;
            let covered: Vec<Diagnostic> = diagnostics
                .iter()
                .filter(|d| {
                    overlaps(&d.range)
                        || d.related_information
                            .iter()
                            .flatten()
                            .any(|r| overlaps(&r.location.range))
                })
                .cloned()
                .collect();
            actions.push(CodeActionOrCommand::CodeAction(CodeAction {
                title: fix.description.clone(),
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: (!covered.is_empty()).then_some(covered),
                edit: Some(edit(document, &index, std::slice::from_ref(fix))),
                is_preferred: Some(true),
                ..CodeAction::default()
            }));
        }
    }
    if !fixes.is_empty() && wanted(&CodeActionKind::SOURCE_FIX_ALL) {
        actions.push(CodeActionOrCommand::CodeAction(CodeAction {
            title: format!("apply every safe fix ({})", fixes.len()),
            kind: Some(CodeActionKind::SOURCE_FIX_ALL),
            edit: Some(edit(document, &index, &fixes)),
            ..CodeAction::default()
        }));
    }
    actions
}

fn edit(document: &Document, index: &LineIndex, fixes: &[Fix]) -> WorkspaceEdit {
    let edits = fixes
        .iter()
        .flat_map(|f| &f.edits)
        .map(|e| TextEdit::new(index.range(e.span), e.replacement.clone()))
        .collect();
    WorkspaceEdit {
        changes: Some(HashMap::from([(document.uri.clone(), edits)])),
        ..WorkspaceEdit::default()
    }
}
