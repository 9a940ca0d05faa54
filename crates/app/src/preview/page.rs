//! The page `/` serves: one HTML file with its style and script inline,
//! compiled into the binary, so the preview needs no network and no files
//! beside the binary.

/// The page: it listens on `/events` and redraws the image, the statistics
/// and the diagnostics from each update, without reloading.
pub const PAGE: &str = include_str!("page.html");
