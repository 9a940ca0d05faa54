//! Fitting the student's brightness to what our renderer sees: least
//! squares with an intercept, robust to a highlight or an edge, so any
//! ambient and diffuse constants, and reflection added or blended, fit.

/// Least squares of `y` on the columns of `x` (with an intercept), then
/// again without the points whose residual is over three times the median
/// one, twice: robust to a highlight or an edge.
pub(super) fn robust_fit<const K: usize>(rows: &[([f64; K], f64)]) -> Option<Vec<f64>> {
    let mut beta = least_squares(rows.iter())?;
    let mut residuals: Vec<f64> = Vec::with_capacity(rows.len());
    let mut ordered: Vec<f64> = Vec::with_capacity(rows.len());
    for _ in 0..2 {
        residuals.clear();
        residuals.extend(rows.iter().map(|r| (r.1 - predict(&beta, &r.0)).abs()));
        ordered.clear();
        ordered.extend_from_slice(&residuals);
        let bound = outlier_bound(&mut ordered);
        let kept = rows
            .iter()
            .zip(&residuals)
            .filter(|(_, &r)| r <= bound)
            .map(|(row, _)| row);
        match least_squares(kept) {
            Some(better) => beta = better,
            None => break,
        }
    }
    Some(beta)
}

/// The largest absolute residual a robust fit keeps: three times the
/// median one, and at least 3 of 255 (rounding alone is never an
/// outlier). `residuals` must not be empty; their order is lost.
pub(super) fn outlier_bound(residuals: &mut [f64]) -> f64 {
    let middle = residuals.len() / 2;
    let (_, median, _) = residuals.select_nth_unstable_by(middle, f64::total_cmp);
    (3.0 * *median).max(3.0 / 255.0)
}

pub(super) fn predict(beta: &[f64], x: &[f64]) -> f64 {
    beta[0] + x.iter().zip(&beta[1..]).map(|(x, b)| x * b).sum::<f64>()
}

/// Ordinary least squares with an intercept; `None` when singular.
fn least_squares<'a, const K: usize>(
    rows: impl Iterator<Item = &'a ([f64; K], f64)>,
) -> Option<Vec<f64>> {
    const { assert!(K < 8, "at most seven columns") };
    let n = K + 1;
    // The normal equations, augmented by their right-hand side, on the
    // stack: this runs for every pixel of every fit.
    let mut m = [[0.0; 9]; 8];
    let mut count = 0;
    for (x, y) in rows {
        let mut v = [1.0; 8];
        v[1..n].copy_from_slice(x);
        // The matrix is symmetric: its upper triangle, mirrored below.
        for i in 0..n {
            for j in i..n {
                m[i][j] += v[i] * v[j];
            }
            m[i][n] += v[i] * y;
        }
        count += 1;
    }
    for i in 1..n {
        let (above, below) = m.split_at_mut(i);
        for (j, row) in above.iter().enumerate() {
            below[0][j] = row[i];
        }
    }
    if count < n + 2 {
        return None;
    }
    // A small ridge keeps a column that never varies (no reflection
    // seen, say) from making the system singular.
    for (i, row) in m.iter_mut().enumerate().take(n).skip(1) {
        row[i] += 1e-6;
    }
    for col in 0..n {
        let pivot = (col..n).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col].abs() < 1e-12 {
            return None;
        }
        m.swap(col, pivot);
        let pivot_row = m[col];
        for (row, values) in m.iter_mut().enumerate().take(n) {
            if row != col {
                let f = values[col] / pivot_row[col];
                for (value, p) in values.iter_mut().zip(&pivot_row).take(n + 1).skip(col) {
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
