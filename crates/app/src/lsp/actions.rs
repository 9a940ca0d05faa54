//! Code actions from the structured fixes the diagnostics carry
//! ([`raytracer_scene::fix`]): each as a `quickfix` on its diagnostic (preferred when
//! safe), and all the safe ones at once as `source.fixAll` (what
//! `raytracer check --fix` writes). Fixes replace bytes of the document, so
//! they apply to JSON scenes as they do to scene text.

use std::collections::HashMap;

use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOrCommand, Diagnostic, Range, TextEdit, Url,
    WorkspaceEdit,
};

use super::position::Positions;
use raytracer_scene::fix::{self, Applicability, Fix};

/// The actions for `range` of the document at `uri` with `text`, given its
/// diagnostics and their fixes; `only` is the client's filter on kinds.
pub fn actions(
    uri: &Url,
    text: &str,
    fixed: &[(Diagnostic, Option<Fix>)],
    range: Range,
    only: Option<&[CodeActionKind]>,
) -> Vec<CodeActionOrCommand> {
    let wanted = |kind: &CodeActionKind| {
        only.is_none_or(|only| {
            only.iter().any(|o| {
                kind.as_str() == o.as_str()
                    || kind.as_str().starts_with(&format!("{}.", o.as_str()))
            })
        })
    };
    let index = Positions::new(text);
    let mut actions = Vec::new();
    if wanted(&CodeActionKind::QUICKFIX) {
        // A diagnostic is in the range when any of its labels is on one of
        // its lines (a cursor on a line offers the fixes of that line).
        let overlaps = |r: &Range| r.start.line <= range.end.line && range.start.line <= r.end.line;
        let labelled = |d: &Diagnostic| {
            overlaps(&d.range)
                || d.related_information
                    .iter()
                    .flatten()
                    .any(|r| overlaps(&r.location.range))
        };
        for (diagnostic, fix) in fixed {
            let Some(fix) = fix.as_ref().filter(|_| labelled(diagnostic)) else {
                continue;
            };
            actions.push(CodeActionOrCommand::CodeAction(CodeAction {
                title: fix.message.clone(),
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![diagnostic.clone()]),
                edit: Some(edit(uri, &index, &[fix])),
                is_preferred: Some(fix.applicability == Applicability::Safe),
                ..CodeAction::default()
            }));
        }
    }
    let safe: Vec<&Fix> = fixed
        .iter()
        .filter_map(|(_, fix)| fix.as_ref())
        .filter(|f| f.applicability == Applicability::Safe)
        .collect();
    if !safe.is_empty() && wanted(&CodeActionKind::SOURCE_FIX_ALL) {
        // The fixes that apply together (none overlapping another).
        let (_, applied) = fix::apply(text, safe);
        actions.push(CodeActionOrCommand::CodeAction(CodeAction {
            title: format!("apply every safe fix ({})", applied.len()),
            kind: Some(CodeActionKind::SOURCE_FIX_ALL),
            edit: Some(edit(uri, &index, &applied)),
            ..CodeAction::default()
        }));
    }
    actions
}

fn edit(uri: &Url, index: &Positions, fixes: &[&Fix]) -> WorkspaceEdit {
    let edits = fixes
        .iter()
        .flat_map(|f| &f.edits)
        .map(|e| TextEdit::new(index.range(e.span), e.content.clone()))
        .collect();
    WorkspaceEdit {
        changes: Some(HashMap::from([(uri.clone(), edits)])),
        ..WorkspaceEdit::default()
    }
}
