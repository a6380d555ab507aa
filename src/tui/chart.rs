//! Chart data reduction: min–max decimation per screen column (an impact spike never
//! disappears), pixel de-duplication for x–y loops, axis bounds and compact tick labels.

/// Decimates `(t, y)` samples in the window `[t0, t1]` to at most two points per screen column:
/// the window is cut into `columns` equal buckets and each non-empty bucket contributes its
/// minimum and its maximum (in time order), so a single-sample spike survives at any zoom.
///
/// `t` must be non-decreasing (event instants may repeat a time). Samples outside the window
/// and non-finite values are dropped. When the window holds at most `2 * columns` samples they
/// are returned unchanged.
pub fn downsample_minmax(
    t: &[f64],
    y: &[f64],
    t0: f64,
    t1: f64,
    columns: usize,
) -> Vec<(f64, f64)> {
    let n = t.len().min(y.len());
    let t = &t[..n];
    let lo = t.partition_point(|&x| x < t0);
    let hi = t.partition_point(|&x| x <= t1);
    if lo >= hi || columns == 0 {
        return Vec::new();
    }
    let finite = |i: usize| y[i].is_finite();
    if hi - lo <= 2 * columns || t1 <= t0 {
        return (lo..hi)
            .filter(|&i| finite(i))
            .map(|i| (t[i], y[i]))
            .collect();
    }
    let width = t1 - t0;
    let bucket = |x: f64| (((x - t0) / width * columns as f64) as usize).min(columns - 1);
    let mut out = Vec::with_capacity(2 * columns + 2);
    let mut cur = usize::MAX;
    let (mut imin, mut imax) = (usize::MAX, usize::MAX);
    let flush = |out: &mut Vec<(f64, f64)>, imin: usize, imax: usize| {
        if imin == usize::MAX {
            return;
        }
        let (a, b) = if imin <= imax {
            (imin, imax)
        } else {
            (imax, imin)
        };
        out.push((t[a], y[a]));
        if b != a {
            out.push((t[b], y[b]));
        }
    };
    for i in lo..hi {
        if !finite(i) {
            continue;
        }
        let b = bucket(t[i]);
        if b != cur {
            flush(&mut out, imin, imax);
            cur = b;
            imin = i;
            imax = i;
        } else {
            if y[i] < y[imin] {
                imin = i;
            }
            if y[i] > y[imax] {
                imax = i;
            }
        }
    }
    flush(&mut out, imin, imax);
    out
}

/// Drops consecutive points that fall into the same plotting pixel of an `res_x × res_y` grid
/// over the given bounds (a lossless reduction at screen resolution for x–y curves such as
/// force–deformation loops). The last point is always kept.
pub fn dedup_pixels(
    points: impl IntoIterator<Item = (f64, f64)>,
    xb: [f64; 2],
    yb: [f64; 2],
    res_x: usize,
    res_y: usize,
) -> Vec<(f64, f64)> {
    let sx = (res_x.max(2) - 1) as f64 / (xb[1] - xb[0]).max(f64::MIN_POSITIVE);
    let sy = (res_y.max(2) - 1) as f64 / (yb[1] - yb[0]).max(f64::MIN_POSITIVE);
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut last_px = (i64::MIN, i64::MIN);
    let mut pending: Option<(f64, f64)> = None;
    for (x, y) in points {
        if !x.is_finite() || !y.is_finite() {
            continue;
        }
        let px = (
            ((x - xb[0]) * sx).round() as i64,
            ((y - yb[0]) * sy).round() as i64,
        );
        if px != last_px {
            out.push((x, y));
            last_px = px;
            pending = None;
        } else {
            pending = Some((x, y));
        }
    }
    if let Some(p) = pending {
        out.push(p);
    }
    out
}

/// Index range of samples with `t0 <= t <= t1`.
pub fn window(t: &[f64], t0: f64, t1: f64) -> std::ops::Range<usize> {
    t.partition_point(|&x| x < t0)..t.partition_point(|&x| x <= t1)
}

/// Index of the last sample at or before `tc` (the first sample when `tc` precedes them all).
pub fn at_or_before(t: &[f64], tc: f64) -> Option<usize> {
    if t.is_empty() {
        return None;
    }
    Some(t.partition_point(|&x| x <= tc).saturating_sub(1))
}

/// Padded bounds of a set of values; a flat or empty set gets a small symmetric range.
pub fn bounds<'a>(values: impl IntoIterator<Item = &'a f64>) -> [f64; 2] {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in values {
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if lo > hi {
        return [-1.0, 1.0];
    }
    let span = hi - lo;
    if span <= 1e-12 * lo.abs().max(hi.abs()) || span == 0.0 {
        let d = if lo.abs() > 0.0 { lo.abs() * 0.1 } else { 1e-6 };
        return [lo - d, hi + d];
    }
    [lo - 0.05 * span, hi + 0.05 * span]
}

/// A number in at most `width` characters (compact decimal or scientific notation).
pub fn fmt_num(v: f64, width: usize) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        for prec in (0..=6).rev() {
            let s = format!("{v:.prec$}");
            let s = if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                s
            };
            if s.len() <= width {
                return s;
            }
        }
    }
    for prec in (0..=4).rev() {
        let s = format!("{v:.prec$e}");
        if s.len() <= width {
            return s;
        }
    }
    format!("{v:.0e}")
}

/// A number with `sig` significant digits (decimal for 1e-3 ≤ |v| < 1e5, else scientific).
pub fn fmt_sig(v: f64, sig: usize) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let sig = sig.max(1);
    let e = v.abs().log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (sig as i32 - 1 - e).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.prec$e}", prec = sig - 1)
    }
}

/// Screen column (0-based, in a plot `width` cells wide) of time `t`, mirroring how ratatui's
/// canvas maps x to cells (`round(frac · (res − 1))` on a grid of `per_cell` points per cell).
pub fn column_of(t: f64, t0: f64, t1: f64, width: usize, per_cell: usize) -> Option<usize> {
    if width == 0 || t1 <= t0 || t < t0 || t > t1 {
        return None;
    }
    let res = (width * per_cell) as f64;
    let px = ((t - t0) * (res - 1.0) / (t1 - t0)).round() as usize;
    Some((px / per_cell).min(width - 1))
}

/// A 1-2-5 scale factor near `x` (> 0).
pub fn nice_factor(x: f64) -> f64 {
    if !x.is_finite() || x <= 0.0 {
        return 1.0;
    }
    let e = x.log10().floor();
    let base = 10f64.powf(e);
    let m = x / base;
    let n = if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    };
    n * base
}
