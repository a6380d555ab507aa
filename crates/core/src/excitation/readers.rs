//! Record readers: PEER NGA `.AT2` and two-column `t a` text.

use std::path::{Path, PathBuf};

use super::error::{ExcitationError, Result};

/// Standard gravity, m/s².
pub const G: f64 = 9.80665;

/// Largest number of samples a processed motion may have (guards `pad` / `time_scale`).
pub const MAX_SAMPLES: usize = 50_000_000;

/// A uniformly sampled record, accelerations in g.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// The file it was read from.
    pub path: PathBuf,
    /// AT2: the 4 header lines; two-column: the comment lines.
    pub header: Vec<String>,
    /// Sampling interval, s.
    pub dt: f64,
    /// Accelerations, g.
    pub accel_g: Vec<f64>,
}

/// The text of a record file: a regular file of at most [`crate::input::MAX_RECORD_BYTES`].
fn read_text(path: &Path) -> Result<String> {
    read_limited(path, crate::input::MAX_RECORD_BYTES)
}

fn read_limited(path: &Path, limit: u64) -> Result<String> {
    crate::input::read_bounded(path, limit).map_err(|source| ExcitationError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Bytes one AT2 value and its blank may take at most (`-0.123456789012345E-002` and more).
const AT2_VALUE_BYTES: u64 = 40;

/// The text of an AT2 file read no further than its header's count allows: the 4 header lines
/// (from the first 64 KiB), then at most NPTS × [`AT2_VALUE_BYTES`] more; a longer file is
/// refused by its count, without reading the rest.
fn read_at2_text(path: &Path) -> Result<String> {
    let io = |source| ExcitationError::Io {
        path: path.to_path_buf(),
        source,
    };
    let (head, _) = crate::input::read_prefix(path, 64 << 10).map_err(io)?;
    // the 4 header lines only (the values after them are read again below)
    let lines_end = (head.iter().enumerate())
        .filter(|&(_, &b)| b == b'\n')
        .nth(3)
        .map_or(head.len(), |(i, _)| i + 1);
    let head = String::from_utf8_lossy(&head[..lines_end]);
    let Some(npts) = head
        .lines()
        .nth(3)
        .and_then(|l| parse_npts_dt(l).ok())
        .map(|(n, _)| n)
    else {
        // no count to bound it: the parser says what is wrong with the header
        return read_limited(path, 64 << 10);
    };
    let limit = (64 << 10) + npts as u64 * AT2_VALUE_BYTES;
    crate::input::read_bounded(path, limit).map_err(|e| match e.kind() {
        std::io::ErrorKind::InvalidInput if !e.to_string().contains("regular") => {
            ExcitationError::Header {
                path: path.to_path_buf(),
                line: 4,
                reason: format!(
                    "NPTS = {npts}, but the file is longer than {npts} values can be \
                     ({limit} bytes): refused without reading the rest"
                ),
            }
        }
        _ => io(e),
    })
}

/// 10^k, k = 0..=22: every one exact in f64.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// `[±]digits[.digits][E|e[±]digits]` as m·10^e with m ≤ 2^53 and |e| ≤ 22: one correctly
/// rounded product or quotient of two exact f64 (Clinger 1990), the value `str::parse` gives;
/// None for any other text.
fn parse_short(tok: &[u8]) -> Option<f64> {
    let (neg, mut rest) = match tok {
        [b'-', r @ ..] => (true, r),
        [b'+', r @ ..] => (false, r),
        r => (false, r),
    };
    let (mut m, mut digits, mut frac, mut point) = (0u64, 0u32, 0i32, false);
    while let [b, r @ ..] = rest {
        match b {
            b'0'..=b'9' if digits < 19 => {
                m = 10 * m + u64::from(b - b'0');
                digits += 1;
                frac += i32::from(point);
            }
            b'.' if !point => point = true,
            b'E' | b'e' => break,
            _ => return None,
        }
        rest = r;
    }
    if digits == 0 {
        return None;
    }
    let mut e = 0i32;
    if let [_, r @ ..] = rest {
        let (eneg, mut r) = match r {
            [b'-', r @ ..] => (true, r),
            [b'+', r @ ..] => (false, r),
            r => (false, r),
        };
        if r.is_empty() || r.len() > 4 {
            return None;
        }
        while let [b @ b'0'..=b'9', rr @ ..] = r {
            e = 10 * e + i32::from(b - b'0');
            r = rr;
        }
        if !r.is_empty() {
            return None;
        }
        if eneg {
            e = -e;
        }
    }
    let e = e - frac;
    if m > 1 << 53 || e.unsigned_abs() as usize >= POW10.len() {
        return None;
    }
    let x = m as f64;
    let v = if e >= 0 {
        x * POW10[e as usize]
    } else {
        x / POW10[(-e) as usize]
    };
    Some(if neg { -v } else { v })
}

/// Finite number; Fortran `D` exponents accepted.
fn parse_num(tok: &str) -> Option<f64> {
    if let Some(v) = parse_short(tok.as_bytes()) {
        return Some(v);
    }
    let v = match tok.parse::<f64>() {
        Ok(v) => v,
        Err(_) if tok.contains(['D', 'd']) => tok.replace(['D', 'd'], "E").parse().ok()?,
        Err(_) => return None,
    };
    v.is_finite().then_some(v)
}

/// Reads a PEER NGA `.AT2` file (4 header lines, 4th `NPTS= n, DT= dt SEC`; values in g).
pub fn read_at2(path: &Path) -> Result<Record> {
    parse_at2(path, &read_at2_text(path)?)
}

/// Text after `key` followed by optional blanks and `=` or `:`; `key` must not follow a letter.
fn after_key<'a>(upper: &'a str, key: &str) -> Option<&'a str> {
    let mut from = 0;
    while let Some(k) = upper[from..].find(key) {
        let start = from + k;
        let end = start + key.len();
        let prev_ok = !upper[..start]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_ascii_alphabetic());
        let rest = upper[end..].trim_start();
        if prev_ok && let Some(r) = rest.strip_prefix(['=', ':']) {
            return Some(r.trim_start());
        }
        from = end;
    }
    None
}

fn number_token(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '+' | '-' | 'E')))
        .unwrap_or(s.len());
    &s[..end]
}

fn parse_npts(tok: &str) -> std::result::Result<usize, String> {
    tok.parse::<usize>()
        .ok()
        .or_else(|| {
            parse_num(tok)
                .filter(|v| *v >= 0.0 && v.fract() == 0.0 && *v <= MAX_SAMPLES as f64)
                .map(|v| v as usize)
        })
        .filter(|n| (1..=MAX_SAMPLES).contains(n))
        .ok_or_else(|| format!("NPTS must be an integer in 1..={MAX_SAMPLES}, found {tok:?}"))
}

fn parse_dt(tok: &str) -> std::result::Result<f64, String> {
    parse_num(tok)
        .filter(|v| *v > 0.0)
        .ok_or_else(|| format!("DT must be a positive number, found {tok:?}"))
}

/// `NPTS= 1999, DT= 0.0100 SEC` and variants (any case, no comma, `:`), or the old
/// positional `1999 0.0100 NPTS, DT` layout.
fn parse_npts_dt(line: &str) -> std::result::Result<(usize, f64), String> {
    let upper = line.to_ascii_uppercase();
    match (after_key(&upper, "NPTS"), after_key(&upper, "DT")) {
        (Some(n), Some(d)) => Ok((parse_npts(number_token(n))?, parse_dt(number_token(d))?)),
        (Some(_), None) => Err(format!("missing `DT=` in {line:?}")),
        (None, Some(_)) => Err(format!("missing `NPTS=` in {line:?}")),
        (None, None) => {
            let mut toks = line
                .split(|c: char| c.is_whitespace() || c == ',')
                .filter(|t| !t.is_empty());
            match (toks.next(), toks.next()) {
                (Some(n), Some(d)) if parse_num(n).is_some() && parse_num(d).is_some() => {
                    Ok((parse_npts(n)?, parse_dt(d)?))
                }
                _ => Err(format!("expected `NPTS= n, DT= dt SEC`, found {line:?}")),
            }
        }
    }
}

/// The blank-separated tokens of a line: split on ASCII blanks byte by byte when the whole
/// text is ASCII without vertical tabs (every record seen; the same tokens, without decoding
/// characters), else on Unicode white space.
fn tokens(line: &str, ascii: bool) -> impl Iterator<Item = &str> {
    let (a, u) = if ascii {
        (Some(line.split_ascii_whitespace()), None)
    } else {
        (None, Some(line.split_whitespace()))
    };
    a.into_iter().flatten().chain(u.into_iter().flatten())
}

/// Parses AT2 text; `path` is only used in errors and the returned [`Record`].
pub fn parse_at2(path: &Path, text: &str) -> Result<Record> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text.lines();
    let header: Vec<String> = lines.by_ref().take(4).map(str::to_owned).collect();
    if header.len() < 4 {
        return Err(ExcitationError::Header {
            path: path.to_path_buf(),
            line: header.len() + 1,
            reason: format!("expected 4 header lines, file has {}", header.len()),
        });
    }
    let (npts, dt) = parse_npts_dt(&header[3]).map_err(|reason| ExcitationError::Header {
        path: path.to_path_buf(),
        line: 4,
        reason,
    })?;
    let mut accel_g = Vec::with_capacity(npts);
    // ASCII without vertical tabs (the one ASCII blank `split_ascii_whitespace` keeps)
    let ascii = text.is_ascii() && !text.as_bytes().contains(&0x0b);
    for (k, line) in lines.enumerate() {
        for tok in tokens(line, ascii) {
            let v = parse_num(tok).ok_or_else(|| ExcitationError::Value {
                path: path.to_path_buf(),
                line: k + 5,
                token: tok.to_owned(),
            })?;
            accel_g.push(v);
        }
    }
    if accel_g.len() != npts {
        return Err(ExcitationError::Count {
            path: path.to_path_buf(),
            expected: npts,
            found: accel_g.len(),
        });
    }
    Ok(Record {
        path: path.to_path_buf(),
        header,
        dt,
        accel_g,
    })
}

/// Reads a two-column `t a` file (blank, comma or semicolon separated; `#` starts a comment).
///
/// `a` is in g unless a comment `# units: U` states U ∈ {g, m/s2, m/s^2, cm/s2, cm/s^2, gal,
/// mm/s2, mm/s^2}; values are converted to g. Times must increase uniformly: every step
/// within 0.2 % of the first and every `t_i` within `1e-3·dt` of `t_0 + i·dt`, where
/// `dt = (t_last − t_0)/(n − 1)`, else
/// [`ExcitationError::Sampling`] (no resampling). The first time is taken as the record
/// start (a nonzero `t_0` is dropped: use
/// [`Processing::lag`](super::Processing::lag) for delays).
pub fn read_two_column(path: &Path) -> Result<Record> {
    parse_two_column(path, &read_text(path)?)
}

fn unit_to_g(unit: &str) -> Option<f64> {
    Some(match unit {
        "g" => 1.0,
        "m/s2" | "m/s^2" | "m/s**2" => 1.0 / G,
        "cm/s2" | "cm/s^2" | "cm/s**2" | "gal" => 0.01 / G,
        "mm/s2" | "mm/s^2" | "mm/s**2" => 0.001 / G,
        _ => return None,
    })
}

/// Parses two-column text; see [`read_two_column`].
pub(crate) fn parse_two_column(path: &Path, text: &str) -> Result<Record> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut header = Vec::new();
    let mut factor: Option<f64> = None;
    let mut rows: Vec<(usize, f64, f64)> = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let (data, comment) = match raw.split_once('#') {
            Some((d, c)) => (d, Some(c)),
            None => (raw, None),
        };
        if let Some(c) = comment {
            header.push(raw.to_owned());
            units_directive(path, line, c, &mut factor)?;
        }
        let toks: Vec<&str> = data
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|t| !t.is_empty())
            .collect();
        if toks.is_empty() {
            continue;
        }
        if toks.len() != 2 {
            return Err(ExcitationError::Columns {
                path: path.to_path_buf(),
                line,
                expected: 2,
                found: toks.len(),
            });
        }
        let num = |tok: &str| {
            parse_num(tok).ok_or_else(|| ExcitationError::Value {
                path: path.to_path_buf(),
                line,
                token: tok.to_owned(),
            })
        };
        rows.push((line, num(toks[0])?, num(toks[1])?));
    }
    let dt = uniform_step(path, text, &rows)?;
    let f = factor.unwrap_or(1.0);
    Ok(Record {
        path: path.to_path_buf(),
        header,
        dt,
        accel_g: rows.iter().map(|r| r.2 * f).collect(),
    })
}

/// A `# units: U` comment sets the factor to g; a second, different one is an error.
fn units_directive(
    path: &Path,
    line: usize,
    comment: &str,
    factor: &mut Option<f64>,
) -> Result<()> {
    let c = comment.trim().to_ascii_lowercase();
    if let Some(rest) = c.strip_prefix("units").or_else(|| c.strip_prefix("unit"))
        && let Some(u) = rest.trim_start().strip_prefix([':', '='])
    {
        let u = u.trim();
        let f = unit_to_g(u).ok_or_else(|| ExcitationError::Header {
            path: path.to_path_buf(),
            line,
            reason: format!("unknown acceleration unit {u:?}"),
        })?;
        if factor.is_some_and(|old| old != f) {
            return Err(ExcitationError::Header {
                path: path.to_path_buf(),
                line,
                reason: "conflicting units directives".into(),
            });
        }
        *factor = Some(f);
    }
    Ok(())
}

/// The time step of (line, t, a) rows: uniform within 0.2 % step to step and `1e-3·dt`
/// overall, else [`ExcitationError::Sampling`].
fn uniform_step(path: &Path, text: &str, rows: &[(usize, f64, f64)]) -> Result<f64> {
    let sampling = |line: usize, reason: String| ExcitationError::Sampling {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let (first, last) = match (rows.first(), rows.last()) {
        (Some(f), Some(l)) if rows.len() >= 2 => (*f, *l),
        _ => {
            let line = rows.first().map_or(text.lines().count().max(1), |r| r.0);
            return Err(sampling(
                line,
                format!("need at least 2 samples, found {}", rows.len()),
            ));
        }
    };
    let step0 = rows[1].1 - first.1;
    for w in rows.windows(2) {
        let h = w[1].1 - w[0].1;
        if !(h > 0.0 && (h - step0).abs() <= 2e-3 * step0) {
            return Err(sampling(
                w[1].0,
                format!("time step {h} differs from the first step {step0}"),
            ));
        }
    }
    let dt = (last.1 - first.1) / (rows.len() - 1) as f64;
    for (i, &(line, t, _)) in rows.iter().enumerate() {
        let expect = first.1 + i as f64 * dt;
        if (t - expect).abs() > 1e-3 * dt {
            return Err(sampling(
                line,
                format!("non-uniform time step: t = {t}, expected {expect} (dt = {dt})"),
            ));
        }
    }
    Ok(dt)
}

/// By extension: `.at2` (any case) → [`read_at2`], anything else → [`read_two_column`].
pub fn read_any(path: &Path) -> Result<Record> {
    let is_at2 = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("at2"));
    if is_at2 {
        read_at2(path)
    } else {
        read_two_column(path)
    }
}

#[cfg(test)]
mod tests {
    use super::parse_short;

    /// Every text the short path reads is the value `str::parse` reads, bit for bit.
    #[test]
    fn short_numbers_read_as_str_parse_reads_them() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |m: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % m
        };
        let mut read = 0;
        for _ in 0..20_000 {
            let digits: String = (0..1 + next(19))
                .map(|_| (b'0' + next(10) as u8) as char)
                .collect();
            let at = next(digits.len() as u64 + 1) as usize;
            let sign = ["", "-", "+"][next(3) as usize];
            let mut tok = format!("{sign}{}.{}", &digits[..at], &digits[at..]);
            if next(2) == 0 {
                let e = ["E", "e"][next(2) as usize];
                let es = ["", "-", "+"][next(3) as usize];
                tok += &format!("{e}{es}{:02}", next(30));
            }
            if let Some(v) = parse_short(tok.as_bytes()) {
                assert_eq!(v.to_bits(), tok.parse::<f64>().unwrap().to_bits(), "{tok}");
                read += 1;
            }
        }
        assert!(read > 10_000, "{read}");
        assert_eq!(parse_short(b"3.4930500E-05"), Some(3.49305e-5));
        assert_eq!(
            parse_short(b"-0.0").map(f64::to_bits),
            Some((-0.0f64).to_bits())
        );
        for tok in [
            "", ".", "-", "1e", "1E+", "e5", "1.2.3", "1D-3", "inf", "NaN", "1e-23",
        ] {
            assert_eq!(parse_short(tok.as_bytes()), None, "{tok}");
        }
    }
}
