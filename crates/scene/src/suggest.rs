//! "Did you mean" suggestions: the nearest known name to a misspelt word.

/// The largest edit distance at which a known name is still suggested.
pub const MAX_DISTANCE: usize = 2;

/// The candidate closest to `word` by Levenshtein distance, with that
/// distance, if any candidate is within [`MAX_DISTANCE`]. Ties go to the
/// earlier candidate, so suggestions are deterministic.
pub fn nearest<'a>(word: &str, candidates: &[&'a str]) -> Option<(&'a str, usize)> {
    let word = word.to_lowercase();
    candidates
        .iter()
        .map(|&c| (c, strsim::levenshtein(&word, c)))
        .filter(|&(_, d)| d <= MAX_DISTANCE)
        .min_by_key(|&(_, d)| d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_within_distance() {
        assert_eq!(nearest("colour", &["color", "center"]), Some(("color", 1)));
        assert_eq!(nearest("SPHERE", &["sphere"]), Some(("sphere", 0)));
        assert_eq!(nearest("xyzzy", &["color", "center"]), None);
    }
}
