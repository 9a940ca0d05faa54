//! Opening a page in the user's browser (`preview --open`): the command in
//! `$BROWSER` (as Python's `webbrowser` and the `webbrowser` crate read it:
//! `:`-separated commands, `%s` for the URL, else the URL last), or the
//! platform's opener (`xdg-open`, `open`, `start`).
//!
//! The command is run here rather than through the `webbrowser` crate
//! because that crate spawns a graphical browser and never looks at how it
//! ended, so a browser that fails would be silent. Here the caller gets the
//! command line it ran and waits for its exit status off the main thread
//! ([`Launch::wait`]), to say which command failed and how.

use std::process::{Child, Command, ExitStatus, Stdio};

/// A browser command that could not be started.
#[derive(Debug, thiserror::Error)]
#[error("cannot run the browser command `{command}`: {source}")]
pub struct LaunchError {
    pub command: String,
    pub source: std::io::Error,
}

/// A browser command that ended unsuccessfully.
#[derive(Debug, thiserror::Error)]
#[error("the browser command `{command}` failed ({status})")]
pub struct BrowserFailed {
    pub command: String,
    pub status: ExitStatus,
}

/// A browser command started on a URL.
#[derive(Debug)]
pub struct Launch {
    /// The command line, words joined by spaces, for messages.
    pub command: String,
    child: Child,
}

impl Launch {
    /// Wait for the command to end: an error when it failed. A browser
    /// that keeps running (no opener to hand over to) ends with the user.
    pub fn wait(mut self) -> Result<(), BrowserFailed> {
        match self.child.wait() {
            Ok(status) if !status.success() => Err(BrowserFailed {
                command: self.command,
                status,
            }),
            _ => Ok(()),
        }
    }
}

/// Start the browser on `url`: the first command of `$BROWSER` that starts,
/// else the platform's opener.
pub fn launch(url: &str) -> Result<Launch, LaunchError> {
    let commands = command_lines(std::env::var("BROWSER").ok().as_deref(), url);
    let mut last = None;
    for words in commands {
        let command = words.join(" ");
        let started = Command::new(&words[0])
            .args(&words[1..])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn();
        match started {
            Ok(child) => return Ok(Launch { command, child }),
            Err(source) => last = Some(LaunchError { command, source }),
        }
    }
    Err(last.expect("there is always at least one command"))
}

/// The command lines to try, in order: those of `browser` (the value of
/// `$BROWSER`), or the platform's opener when it names none.
fn command_lines(browser: Option<&str>, url: &str) -> Vec<Vec<String>> {
    let from_env: Vec<Vec<String>> = browser
        .unwrap_or("")
        .split(':')
        .filter(|entry| !entry.trim().is_empty())
        .map(|entry| with_url(entry, url))
        .collect();
    if from_env.is_empty() {
        vec![opener(url)]
    } else {
        from_env
    }
}

/// One `$BROWSER` entry's words with `%s` replaced by the URL (`%c` by `:`
/// and `%%` by `%`), or the URL appended when no word holds `%s`.
fn with_url(entry: &str, url: &str) -> Vec<String> {
    let mut placed = false;
    let mut words: Vec<String> = entry
        .split_whitespace()
        .map(|word| {
            let escaped = word.replace("%%", "\u{0}");
            placed |= escaped.contains("%s");
            escaped
                .replace("%s", url)
                .replace("%c", ":")
                .replace('\u{0}', "%")
        })
        .collect();
    if !placed {
        words.push(url.to_string());
    }
    words
}

/// The platform's command that opens a URL in the default browser.
fn opener(url: &str) -> Vec<String> {
    let words: &[&str] = if cfg!(target_os = "macos") {
        &["open"]
    } else if cfg!(windows) {
        &["cmd", "/C", "start", ""]
    } else {
        &["xdg-open"]
    };
    words
        .iter()
        .map(|word| word.to_string())
        .chain([url.to_string()])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn browser_entries_place_the_url_or_append_it() {
        let url = "http://127.0.0.1:8000/";
        assert_eq!(
            command_lines(Some("firefox --new-tab %s:lynx"), url),
            [vec!["firefox", "--new-tab", url], vec!["lynx", url]]
        );
        assert_eq!(
            command_lines(Some("w3m %%s%c"), url),
            [vec!["w3m", "%s:", url]]
        );
        assert_eq!(command_lines(Some(""), url), [opener(url)]);
        assert_eq!(command_lines(None, url).len(), 1);
    }
}
