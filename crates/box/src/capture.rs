//! Capturing a program's stdout or stderr up to a bound: a thread reads
//! the pipe to its end, keeps the first bytes and counts the rest, so a
//! program that floods its output neither blocks nor fills memory.

use std::io::Read;
use std::sync::mpsc;
use std::time::Duration;

/// What was kept of a stream.
#[derive(Clone, Debug, Default)]
pub struct Captured {
    /// The first bytes, at most the bound.
    pub kept: Vec<u8>,
    /// Every byte the program wrote.
    pub total: u64,
}

impl Captured {
    /// The kept bytes as text, with a note when some were cut.
    pub fn text(&self) -> String {
        let mut text = String::from_utf8_lossy(&self.kept).into_owned();
        if self.total > self.kept.len() as u64 {
            text.push_str(&format!(
                "\n[… {} more bytes not kept]",
                self.total - self.kept.len() as u64
            ));
        }
        text
    }
}

/// A stream being read.
pub struct Reading(Option<mpsc::Receiver<Captured>>);

/// Start reading `stream`, keeping at most `bound` bytes.
pub fn spawn(stream: Option<impl Read + Send + 'static>, bound: usize) -> Reading {
    let Some(mut stream) = stream else {
        return Reading(None);
    };
    let (send, receive) = mpsc::channel();
    std::thread::spawn(move || {
        let mut captured = Captured::default();
        let mut buffer = [0u8; 16 * 1024];
        while let Ok(n @ 1..) = stream.read(&mut buffer) {
            let room = bound.saturating_sub(captured.kept.len()).min(n);
            captured.kept.extend_from_slice(&buffer[..room]);
            captured.total += n as u64;
        }
        let _ = send.send(captured);
    });
    Reading(Some(receive))
}

impl Reading {
    /// What was read, once the stream has ended. A stream still held open
    /// (by a process that escaped the kill) is given up after a second.
    pub fn finish(self) -> Captured {
        self.0
            .and_then(|r| r.recv_timeout(Duration::from_secs(1)).ok())
            .unwrap_or_default()
    }
}
