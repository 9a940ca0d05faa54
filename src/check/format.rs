//! Numbers as help lines and `--fix` write them: short, valid scene-language
//! numbers that read back to within 12 significant digits.

/// `x` rounded to 12 significant digits, in the shortest form that reads
/// back as that value: `0.8`, `-0.4`, `16384`, `1e-7`.
pub fn number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        // −0 prints as 0; non-finite values never reach here from a scene.
        return "0".to_string();
    }
    let rounded: f64 = format!("{x:.11e}").parse().unwrap_or(x);
    let magnitude = rounded.abs();
    if (1e-5..1e15).contains(&magnitude) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// Three numbers separated by spaces.
pub fn vector(v: [f64; 3]) -> String {
    v.map(number).join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_and_valid() {
        assert_eq!(number(0.8), "0.8");
        assert_eq!(number(1.0 - 0.2), "0.8");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(16384.0), "16384");
        assert_eq!(number(1.0 / 3.0), "0.333333333333");
        assert_eq!(number(1e-7), "1e-7");
        assert_eq!(number(-2.5e300), "-2.5e300");
        assert_eq!(vector([0.0, 0.5, -0.5]), "0 0.5 -0.5");
    }
}
