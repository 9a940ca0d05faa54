//! `check --format sarif` and `--format github` against their published
//! shapes: the SARIF log validates against the official SARIF 2.1.0 JSON
//! schema (vendored in tests/sarif/, provenance beside it), the workflow
//! commands parse by the runner's command grammar, both carry the same
//! diagnostics at the same places as `--format json`, and insta snapshots
//! keep both layouts.

use std::path::Path;
use std::process::Output;

use serde_json::Value;

use crate::support::command;

/// Fixtures with one label, two labels, a warning, a fix that inserts
/// (an empty region replaced), a JSON scene and an error without a scene:
/// every path the two formats take (src/ci tests columns past multi-byte
/// characters).
const FILES: [&str; 6] = [
    "tests/ui/scene/unknown_attribute.txt",
    "tests/ui/scene/missing_attribute.txt",
    "tests/ui/scene/duplicate_attribute.txt",
    "tests/ui/scene/headup_not_perpendicular.txt",
    "tests/ui/json/missing_field.json",
    "tests/ui/no such scene.txt",
];

fn check(format: &str) -> Output {
    let mut args = vec!["check", "--format", format];
    args.extend(FILES);
    command(&args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run raytracer")
}

fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).expect("UTF-8")
}

/// The `--format json` entries, which the other formats must agree with.
fn json_entries() -> Vec<Value> {
    let output = check("json");
    let entries: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    entries.as_array().expect("an array").clone()
}

fn sarif() -> Value {
    let output = check("sarif");
    assert_eq!(output.status.code(), Some(2), "a file is missing");
    serde_json::from_slice(&output.stdout).expect("one JSON document")
}

#[test]
fn sarif_validates_against_the_official_schema() {
    let schema_path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/sarif/sarif-schema-2.1.0.json");
    let schema: Value =
        serde_json::from_str(&std::fs::read_to_string(schema_path).expect("vendored schema"))
            .expect("schema is JSON");
    let validator = jsonschema::draft4::options()
        .should_validate_formats(true)
        .build(&schema)
        .expect("the schema compiles");
    let log = sarif();
    let errors: Vec<String> = validator
        .iter_errors(&log)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{errors:#?}");
    assert_eq!(log["$schema"], schema["id"], "names the schema it follows");

    // The schema cannot fail anything: the same log with a wrong level
    // or a missing message does not validate.
    let mut broken = log.clone();
    broken["runs"][0]["results"][0]["level"] = "fatal".into();
    assert!(!validator.is_valid(&broken));
    let mut broken = log.clone();
    broken["runs"][0]["results"][0]
        .as_object_mut()
        .unwrap()
        .remove("message");
    assert!(!validator.is_valid(&broken));
}

#[test]
fn sarif_carries_what_json_carries() {
    let log = sarif();
    let run = &log["runs"][0];
    let driver = &run["tool"]["driver"];
    assert_eq!(driver["name"], "raytracer");
    // The version the binary reports (this package has its own), without
    // the commit `--version` names after it.
    let version = command(&["--version"]).output().expect("runs");
    let version = String::from_utf8(version.stdout).expect("UTF-8");
    assert_eq!(
        Some(driver["version"].as_str().expect("a string")),
        version
            .trim()
            .strip_prefix("raytracer ")
            .and_then(|v| v.split(' ').next())
    );
    assert_eq!(run["columnKind"], "unicodeCodePoints");
    let rules = driver["rules"].as_array().unwrap();
    let results = run["results"].as_array().unwrap();
    let entries = json_entries();
    assert_eq!(results.len(), entries.len());

    let docs: String = ["syntax", "json", "scene"]
        .iter()
        .map(|page| {
            std::fs::read_to_string(
                Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("docs/diagnostics/{page}.md")),
            )
            .unwrap()
        })
        .collect();
    for rule in rules {
        let id = rule["id"].as_str().unwrap();
        // The documentation travels in the log: no link into a folder.
        assert!(rule.get("helpUri").is_none(), "{rule}");
        if !id.starts_with("io::") {
            // The rule's text is its section of docs/diagnostics/.
            let section = format!(
                "## `{id}`\n\n**What.** {}",
                rule["shortDescription"]["text"].as_str().unwrap()
            );
            assert!(docs.contains(&section), "{id}");
        }
        assert!(!rule["help"]["text"].as_str().unwrap().is_empty());
    }

    for (result, entry) in results.iter().zip(&entries) {
        let index = result["ruleIndex"].as_u64().unwrap() as usize;
        assert_eq!(result["ruleId"], entry["code"]);
        assert_eq!(rules[index]["id"], entry["code"]);
        let level = match entry["severity"].as_str().unwrap() {
            "advice" => "note",
            other => other,
        };
        assert_eq!(result["level"], level);
        let text = result["message"]["text"].as_str().unwrap();
        assert!(text.starts_with(entry["message"].as_str().unwrap()));
        if let Some(help) = entry["help"].as_str() {
            assert!(text.ends_with(&format!("\nhelp: {help}")));
        }
        let locations: Vec<&Value> = result["locations"]
            .as_array()
            .unwrap()
            .iter()
            .chain(result["relatedLocations"].as_array().into_iter().flatten())
            .collect();
        let file = entry["file"].as_str().unwrap();
        let labels = entry["labels"].as_array().unwrap();
        for location in &locations {
            let uri = &location["physicalLocation"]["artifactLocation"]["uri"];
            assert_eq!(uri.as_str().unwrap(), file.replace(' ', "%20"));
        }
        if labels.is_empty() {
            assert_eq!(locations.len(), 1);
            assert!(locations[0]["physicalLocation"].get("region").is_none());
        } else {
            assert_eq!(locations.len(), labels.len());
        }
        for (location, label) in locations.iter().zip(labels) {
            let region = &location["physicalLocation"]["region"];
            assert_eq!(region["startLine"], label["line"]);
            assert_eq!(region["startColumn"], label["column"]);
            assert_eq!(location["message"]["text"], label["label"]);
        }
        // A fix is a SARIF `fixes` entry with one replacement per edit.
        match entry.get("fix") {
            None => assert!(result.get("fixes").is_none(), "{result}"),
            Some(fix) => {
                let sarif_fix = &result["fixes"][0];
                assert_eq!(sarif_fix["description"]["text"], fix["message"]);
                let change = &sarif_fix["artifactChanges"][0];
                assert_eq!(
                    change["artifactLocation"]["uri"].as_str().unwrap(),
                    file.replace(' ', "%20")
                );
                let replacements = change["replacements"].as_array().unwrap();
                let edits = fix["edits"].as_array().unwrap();
                assert_eq!(replacements.len(), edits.len());
                for (replacement, edit) in replacements.iter().zip(edits) {
                    assert_eq!(replacement["insertedContent"]["text"], edit["content"]);
                    let region = &replacement["deletedRegion"];
                    assert_eq!(region["startLine"], edit["line"]);
                    assert_eq!(region["startColumn"], edit["column"]);
                }
            }
        }
    }
    assert!(
        results.iter().any(|r| r.get("fixes").is_some()),
        "the fixtures carry fixes"
    );
}

/// One workflow command, parsed by the grammar the runner reads:
/// `::NAME[ KEY=VALUE[,KEY=VALUE]*]::DATA` on one line, with values and
/// data unescaped.
#[derive(Debug, PartialEq)]
struct WorkflowCommand {
    name: String,
    properties: Vec<(String, String)>,
    data: String,
}

fn parse_command(line: &str) -> Result<WorkflowCommand, String> {
    let rest = line.strip_prefix("::").ok_or("no leading `::`")?;
    let (head, data) = rest.split_once("::").ok_or("no `::` before the data")?;
    if line.contains(['\r', '\n']) {
        return Err("a raw line break".into());
    }
    let (name, properties) = match head.split_once(' ') {
        Some((name, properties)) => (name, properties),
        None => (head, ""),
    };
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-') {
        return Err(format!("bad command name `{name}`"));
    }
    let mut parsed = Vec::new();
    for property in properties.split(',').filter(|p| !p.is_empty()) {
        let (key, value) = property
            .split_once('=')
            .ok_or(format!("`{property}` has no `=`"))?;
        parsed.push((key.to_string(), unescape(value)?));
    }
    Ok(WorkflowCommand {
        name: name.to_string(),
        properties: parsed,
        data: unescape(data)?,
    })
}

/// The runner's unescaping; any other `%` sequence is left as it is by the
/// runner, so the writer must never produce one.
fn unescape(text: &str) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find('%') {
        out.push_str(&rest[..at]);
        let code = rest.get(at..at + 3).ok_or("a cut-off escape")?;
        out.push(match code {
            "%25" => '%',
            "%0D" => '\r',
            "%0A" => '\n',
            "%3A" => ':',
            "%2C" => ',',
            _ => return Err(format!("unknown escape `{code}`")),
        });
        rest = &rest[at + 3..];
    }
    out.push_str(rest);
    Ok(out)
}

#[test]
fn workflow_command_parser_reads_the_runners_grammar() {
    let parsed =
        parse_command("::error file=a%2Cb.txt,line=2,title=x%3A%3Ay::50%25 off%0Ahelp").unwrap();
    assert_eq!(parsed.name, "error");
    assert_eq!(
        parsed.properties,
        [
            ("file".to_string(), "a,b.txt".to_string()),
            ("line".to_string(), "2".to_string()),
            ("title".to_string(), "x::y".to_string()),
        ]
    );
    assert_eq!(parsed.data, "50% off\nhelp");
    assert!(parse_command("error::x").is_err());
    assert!(parse_command("::error file=a::100%").is_err());
    assert!(parse_command("::error file::x").is_err());
}

#[test]
fn github_commands_carry_what_json_carries() {
    let output = check("github");
    assert_eq!(output.status.code(), Some(2));
    let text = stdout(&output);
    let entries = json_entries();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), entries.len(), "{text}");
    for (line, entry) in lines.iter().zip(&entries) {
        let command = parse_command(line).unwrap_or_else(|e| panic!("{e}: {line}"));
        let level = match entry["severity"].as_str().unwrap() {
            "advice" => "notice",
            other => other,
        };
        assert_eq!(command.name, level);
        let property = |key: &str| {
            command
                .properties
                .iter()
                .find(|(k, _)| k == key)
                .map(|(_, v)| v.as_str())
        };
        let keys: Vec<&str> = command.properties.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(property("file"), entry["file"].as_str());
        assert_eq!(property("title"), entry["code"].as_str());
        match entry["labels"].as_array().unwrap().first() {
            Some(label) => {
                assert_eq!(
                    keys,
                    ["file", "line", "col", "endLine", "endColumn", "title"]
                );
                assert_eq!(property("line"), Some(&*label["line"].to_string()));
                assert_eq!(property("col"), Some(&*label["column"].to_string()));
                let (start, end): (u64, u64) = (
                    property("col").unwrap().parse().unwrap(),
                    property("endColumn").unwrap().parse().unwrap(),
                );
                if property("endLine") == property("line") {
                    assert!(end >= start, "{line}");
                }
            }
            None => assert_eq!(keys, ["file", "title"]),
        }
        let message = entry["message"].as_str().unwrap();
        let expected = match entry["help"].as_str() {
            Some(help) => format!("{message}\nhelp: {help}"),
            None => message.to_string(),
        };
        assert_eq!(command.data, expected);
    }
}

#[test]
fn snapshots_of_both_formats() {
    insta::assert_snapshot!("sarif", stdout(&check("sarif")));
    insta::assert_snapshot!("github", stdout(&check("github")));
}
