//! `check --format github`: one GitHub Actions workflow command per
//! diagnostic, which the runner turns into an annotation on the file:
//!
//! ```text
//! ::error file=scene.txt,line=5,col=3,endLine=5,endColumn=8,title=scene%3A%3Aunknown_attribute::unknown attribute `centre` in `sphere`%0Ahelp: did you mean `center`?
//! ```
//!
//! The level is `error`, `warning` or `notice`; the position is the first
//! label's, `endColumn` being the column of its last character; the title is
//! the code. Escaping follows the runner's own toolkit: in the message, `%`,
//! CR and LF become `%25`, `%0D` and `%0A` (so a help line stays in the same
//! annotation); in property values, `:` and `,` also become `%3A` and `%2C`.

use super::Finding;

/// The workflow command for `finding`, without a line break.
pub fn command(finding: &Finding) -> String {
    let d = &finding.diagnostic;
    let level = match d.severity {
        "error" => "error",
        "warning" => "warning",
        _ => "notice",
    };
    let mut properties = vec![("file", d.file.clone())];
    if let Some(region) = finding.regions.first() {
        properties.extend([
            ("line", region.start.0.to_string()),
            ("col", region.start.1.to_string()),
            ("endLine", region.last.0.to_string()),
            ("endColumn", region.last.1.to_string()),
        ]);
    }
    properties.push(("title", d.code.clone()));
    let properties: Vec<String> = properties
        .iter()
        .map(|(key, value)| format!("{key}={}", escape_property(value)))
        .collect();
    let message = match &d.help {
        Some(help) => format!("{}\nhelp: {help}", d.message),
        None => d.message.clone(),
    };
    format!(
        "::{level} {}::{}",
        properties.join(","),
        escape_data(&message)
    )
}

/// The runner's escaping of a command's message.
pub fn escape_data(text: &str) -> String {
    text.replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A")
}

/// The runner's escaping of a property value.
pub fn escape_property(text: &str) -> String {
    escape_data(text).replace(':', "%3A").replace(',', "%2C")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping_follows_the_toolkit() {
        assert_eq!(escape_data("100% a\r\nb: c, d"), "100%25 a%0D%0Ab: c, d");
        assert_eq!(escape_property("a:b,c%\n"), "a%3Ab%2Cc%25%0A");
        // `%` first, so an escape is never escaped twice.
        assert_eq!(escape_data("%0A"), "%250A");
    }
}
