//! Fitting the student's brightness to what our renderer sees: least
//! squares with an intercept, robust to a highlight or an edge, so any
//! ambient and diffuse constants, and reflection added or blended, fit.

/// Least squares of `y` on the columns of `x` (with an intercept), then
/// again without the points whose residual is over three times the median
/// one, twice: robust to a highlight or an edge.
pub(super) fn robust_fit<const K: usize>(rows: &[([f64; K], f64)]) -> Option<Vec<f64>> {
    let mut keep: Vec<bool> = vec![true; rows.len()];
    let mut fit = None;
    for _ in 0..3 {
        let chosen: Vec<&([f64; K], f64)> = rows
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(r, _)| r)
            .collect();
        let Some(beta) = least_squares(&chosen) else {
            break;
        };
        let residuals: Vec<f64> = rows
            .iter()
            .map(|r| (r.1 - predict(&beta, &r.0)).abs())
            .collect();
        let bound = outlier_bound(residuals.clone());
        keep = residuals.iter().map(|&r| r <= bound).collect();
        fit = Some(beta);
    }
    fit
}

/// The largest absolute residual a robust fit keeps: three times the
/// median one, and at least 3 of 255 (rounding alone is never an
/// outlier). `residuals` must not be empty.
pub(super) fn outlier_bound(mut residuals: Vec<f64>) -> f64 {
    let middle = residuals.len() / 2;
    let (_, median, _) = residuals.select_nth_unstable_by(middle, f64::total_cmp);
    (3.0 * *median).max(3.0 / 255.0)
}

pub(super) fn predict(beta: &[f64], x: &[f64]) -> f64 {
    beta[0] + x.iter().zip(&beta[1..]).map(|(x, b)| x * b).sum::<f64>()
}

/// Ordinary least squares with an intercept; `None` when singular.
fn least_squares<const K: usize>(rows: &[&([f64; K], f64)]) -> Option<Vec<f64>> {
    const { assert!(K < 8, "at most seven columns") };
    let n = K + 1;
    if rows.len() < n + 2 {
        return None;
    }
    let mut m = vec![vec![0.0; n + 1]; n];
    for (x, y) in rows {
        // The row with its intercept's 1, on the stack: this runs for
        // every pixel of every fit.
        let mut v = [1.0; 8];
        v[1..n].copy_from_slice(x);
        for i in 0..n {
            for j in 0..n {
                m[i][j] += v[i] * v[j];
            }
            m[i][n] += v[i] * y;
        }
    }
    // A small ridge keeps a column that never varies (no reflection
    // seen, say) from making the system singular.
    for (i, row) in m.iter_mut().enumerate().skip(1) {
        row[i] += 1e-6;
    }
    for col in 0..n {
        let pivot = (col..n).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col].abs() < 1e-12 {
            return None;
        }
        m.swap(col, pivot);
        for row in 0..n {
            if row != col {
                let f = m[row][col] / m[col][col];
                let pivot_row = m[col].clone();
                for (value, p) in m[row].iter_mut().zip(&pivot_row).skip(col) {
                    *value -= f * p;
                }
            }
        }
    }
    Some((0..n).map(|i| m[i][n] / m[i][i]).collect())
}

/// The standard deviation of `values` (0 for none).
pub(super) fn spread(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_finds_a_line_despite_outliers() {
        let mut rows: Vec<([f64; 1], f64)> = (0..50)
            .map(|i| ([f64::from(i) / 50.0], 0.2 + 0.7 * f64::from(i) / 50.0))
            .collect();
        rows.push(([0.5], 1.0));
        let beta = robust_fit(&rows).unwrap();
        assert!(
            (beta[0] - 0.2).abs() < 1e-3 && (beta[1] - 0.7).abs() < 1e-3,
            "{beta:?}"
        );
    }
}
