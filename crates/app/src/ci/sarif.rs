//! `check --format sarif`: a SARIF 2.1.0 log (the OASIS standard that
//! code-scanning services ingest) of every diagnostic of every file.
//!
//! One run, whose tool lists a rule per code that occurs, in order of first
//! occurrence: its descriptions come from that code's section of
//! docs/diagnostics/ (compiled in, so they cannot drift from the docs,
//! and travel with the binary: no link into the folder it was built in,
//! which an installed binary's users do not have). Each result has
//! the code as `ruleId`, its first label as its location and the others
//! as related locations, and the fix it carries (if any) as a `fixes`
//! entry whose `artifactChanges` replace regions of the file; columns count
//! Unicode code points, as the run's `columnKind` says. docs/cli.md shows
//! the shape.

use serde_json::{json, Value};

use super::{Finding, Region};

/// The published schema of the log's shape (its `id`).
const SCHEMA: &str =
    "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json";

/// Every code's documentation: the pages of docs/diagnostics/, one per
/// prefix.
const DIAGNOSTICS_PAGES: [&str; 3] = [
    include_str!("../../../../docs/diagnostics/syntax.md"),
    include_str!("../../../../docs/diagnostics/json.md"),
    include_str!("../../../../docs/diagnostics/scene.md"),
];

/// The SARIF log of `findings`.
pub fn log(findings: &[Finding]) -> Value {
    let mut codes: Vec<&str> = Vec::new();
    for finding in findings {
        let code = finding.diagnostic.code.as_str();
        if !codes.contains(&code) {
            codes.push(code);
        }
    }
    let results: Vec<Value> = findings
        .iter()
        .map(|finding| {
            let index = codes
                .iter()
                .position(|&c| c == finding.diagnostic.code)
                .expect("every code is listed");
            result(finding, index)
        })
        .collect();
    json!({
        "$schema": SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": {
                "driver": {
                    "name": "raytracer",
                    "version": env!("CARGO_PKG_VERSION"),
                    "rules": codes.iter().map(|code| rule(code)).collect::<Vec<_>>(),
                }
            },
            "columnKind": "unicodeCodePoints",
            "results": results,
        }]
    })
}

/// A rule: the code with its documentation.
fn rule(code: &str) -> Value {
    let doc = documentation(code);
    let what = doc
        .what
        .unwrap_or_else(|| "a problem reading or writing a file".to_string());
    let help = doc.help.unwrap_or_else(|| {
        "See the command-line reference for what each exit code means.".to_string()
    });
    json!({
        "id": code,
        "shortDescription": { "text": what },
        "help": { "text": help },
    })
}

fn result(finding: &Finding, rule_index: usize) -> Value {
    let d = &finding.diagnostic;
    let text = match &d.help {
        Some(help) => format!("{}\nhelp: {help}", d.message),
        None => d.message.clone(),
    };
    let uri = file_uri_reference(&d.file);
    let mut locations: Vec<Value> = d
        .labels
        .iter()
        .zip(&finding.regions)
        .enumerate()
        .map(|(id, (label, region))| {
            let mut location = json!({
                "id": id,
                "physicalLocation": {
                    "artifactLocation": { "uri": uri },
                    "region": sarif_region(region),
                }
            });
            if let Some(label) = &label.label {
                location["message"] = json!({ "text": label });
            }
            location
        })
        .collect();
    if locations.is_empty() {
        locations.push(json!({ "physicalLocation": { "artifactLocation": { "uri": uri } } }));
    }
    let related = locations.split_off(1);
    let mut result = json!({
        "ruleId": d.code,
        "ruleIndex": rule_index,
        "level": level(d.severity),
        "message": { "text": text },
        "locations": locations,
    });
    if !related.is_empty() {
        result["relatedLocations"] = Value::Array(related);
    }
    if let Some(fix) = &d.fix {
        let replacements: Vec<Value> = fix
            .edits
            .iter()
            .zip(&finding.fix_regions)
            .map(|(edit, region)| {
                json!({
                    "deletedRegion": sarif_region(region),
                    "insertedContent": { "text": edit.content },
                })
            })
            .collect();
        result["fixes"] = json!([{
            "description": { "text": fix.message },
            "artifactChanges": [{
                "artifactLocation": { "uri": uri },
                "replacements": replacements,
            }],
        }]);
    }
    result
}

/// A region as SARIF writes it: lines and columns, and the character
/// offset and length.
fn sarif_region(region: &Region) -> Value {
    json!({
        "startLine": region.start.0,
        "startColumn": region.start.1,
        "endLine": region.end.0,
        "endColumn": region.end.1,
        "charOffset": region.char_offset,
        "charLength": region.char_length,
    })
}

/// SARIF's level for our severity.
fn level(severity: &str) -> &'static str {
    match severity {
        "error" => "error",
        "warning" => "warning",
        _ => "note",
    }
}

/// What docs/diagnostics/ says about a code.
#[derive(Debug, Default, PartialEq, Eq)]
struct Documentation {
    /// The **What.** paragraph.
    what: Option<String>,
    /// The **Why.** and **Fix.** paragraphs.
    help: Option<String>,
}

/// The paragraphs of `code`'s section of docs/diagnostics/.
fn documentation(code: &str) -> Documentation {
    let heading = format!("## `{code}`\n");
    let Some((page, start)) = DIAGNOSTICS_PAGES
        .iter()
        .find_map(|page| Some((page, page.find(&heading)?)))
    else {
        return Documentation::default();
    };
    let section = &page[start + heading.len()..];
    let section = &section[..section.find("\n## ").unwrap_or(section.len())];
    let paragraph = |name: &str| {
        let marker = format!("**{name}.** ");
        section
            .split("\n\n")
            .find_map(|p| p.trim().strip_prefix(&marker))
            .map(|p| p.replace('\n', " "))
    };
    let help: Vec<String> = [paragraph("Why"), paragraph("Fix")]
        .into_iter()
        .flatten()
        .collect();
    Documentation {
        what: paragraph("What"),
        help: (!help.is_empty()).then(|| help.join("\n\n")),
    }
}

/// The file as a URI reference: a relative path stays relative (SARIF
/// consumers resolve it against the repository), an absolute one becomes a
/// `file:` URI; `\` separators become `/`.
pub fn file_uri_reference(file: &str) -> String {
    let path = file.replace('\\', "/");
    if path.starts_with('/') {
        format!("file://{}", percent_encode(&path))
    } else {
        percent_encode(&path)
    }
}

/// Percent-encode every byte that may not appear in a URI path, and `:`
/// (which would make a relative path's first segment read as a scheme).
fn percent_encode(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    for byte in path.bytes() {
        let unreserved = byte.is_ascii_alphanumeric() || b"-._~/!$&'()*+,;=@".contains(&byte);
        if unreserved {
            out.push(byte as char);
        } else {
            out.push_str(&format!("%{byte:02X}"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_take_their_text_from_the_docs() {
        let doc = documentation("scene::unknown_attribute");
        let what = doc.what.expect("a What paragraph");
        assert!(what.starts_with("An attribute name is not one the language has"));
        let help = doc.help.expect("Why and Fix paragraphs");
        assert!(help.starts_with("An unknown name cannot be applied"));
        assert!(help.contains("\n\nUse the suggested name."));
        assert_eq!(documentation("io::read_scene"), Documentation::default());
    }

    #[test]
    fn paths_become_uri_references() {
        assert_eq!(file_uri_reference("scenes/a b.txt"), "scenes/a%20b.txt");
        assert_eq!(file_uri_reference("/tmp/x#1.txt"), "file:///tmp/x%231.txt");
        assert_eq!(file_uri_reference("<stdin>"), "%3Cstdin%3E");
        assert_eq!(file_uri_reference("c:d.txt"), "c%3Ad.txt");
        assert_eq!(file_uri_reference("dir\\é.txt"), "dir/%C3%A9.txt");
    }
}
