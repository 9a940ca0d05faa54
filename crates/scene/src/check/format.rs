//! Numbers as help lines and `--fix` write them: short, valid scene-language
//! numbers. [`number`] keeps 12 significant digits, for a fix that must
//! keep the image (a projected `headup`); [`short`] keeps three after the
//! whole part, for a fix that guesses a value (`0.333`, not
//! `0.333333333333`).

/// `x` rounded to 12 significant digits, in the shortest form that reads
/// back as that value: `0.8`, `-0.4`, `16384`, `1e-7`.
pub fn number(x: f64) -> String {
    rounded_to(x, 12)
}

/// `x` with at most three significant digits, but all of its whole part:
/// `0.333`, `0.00123`, `1.23`, `16384`, `0.7`.
pub fn short(x: f64) -> String {
    let whole_digits = if x.abs() >= 1.0 {
        x.abs().log10().floor() as usize + 1
    } else {
        0
    };
    rounded_to(x, whole_digits.max(3))
}

/// `x` rounded to `digits` significant digits, in the shortest form that
/// reads back as that value.
fn rounded_to(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        // −0 prints as 0; non-finite values never reach here from a scene.
        return "0".to_string();
    }
    let precision = digits.clamp(1, 17) - 1;
    let rounded: f64 = format!("{x:.precision$e}").parse().unwrap_or(x);
    let magnitude = rounded.abs();
    if rounded == 0.0 {
        "0".to_string()
    } else if (1e-5..1e15).contains(&magnitude) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// Three numbers separated by spaces, 12 significant digits each.
pub fn vector(v: [f64; 3]) -> String {
    v.map(number).join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_numbers_are_short_and_valid() {
        assert_eq!(number(0.8), "0.8");
        assert_eq!(number(1.0 - 0.2), "0.8");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(16384.0), "16384");
        assert_eq!(number(1.0 / 3.0), "0.333333333333");
        assert_eq!(number(1e-7), "1e-7");
        assert_eq!(number(-2.5e300), "-2.5e300");
        assert_eq!(vector([0.0, 0.5, -0.5]), "0 0.5 -0.5");
    }

    #[test]
    fn guesses_keep_three_digits_and_the_whole_part() {
        assert_eq!(short(1.0 / 3.0), "0.333");
        assert_eq!(short(2.0 / 3.0), "0.667");
        assert_eq!(short(0.7), "0.7");
        assert_eq!(short(16384.0), "16384");
        assert_eq!(short(123.456), "123");
        assert_eq!(short(1.23456), "1.23");
        assert_eq!(short(0.0012345), "0.00123");
        assert_eq!(short(-0.5), "-0.5");
        assert_eq!(short(1e-9), "1e-9");
    }
}
