//! The text edits behind each [`Mutation`]: numbers, lines, tables and arrays of a TOML model
//! file; header, data and lines of an AT2 record.

use crate::mutate::{Mutation, NewNumber};
use proptest::sample::Index;

/// Byte ranges of the numbers of a TOML text (outside strings and comments).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let (mut i, mut in_str, mut comment) = (0, false, false);
    while i < b.len() {
        let c = b[i];
        if c == b'\n' {
            comment = false;
            in_str = false;
        }
        if comment || c == b'"' || in_str || c == b'#' {
            in_str ^= c == b'"' && !comment;
            comment |= c == b'#' && !in_str;
            i += 1;
            continue;
        }
        let prev_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        let starts = c.is_ascii_digit()
            || ((c == b'-' || c == b'+') && b.get(i + 1).is_some_and(|d| d.is_ascii_digit()));
        if starts && !prev_word {
            let mut j = i + 1;
            while j < b.len() && (b[j].is_ascii_alphanumeric() || b"+-._".contains(&b[j])) {
                j += 1;
            }
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

fn new_number(tok: &str, n: &NewNumber) -> String {
    match n {
        NewNumber::Literal(l) => l.to_string(),
        NewNumber::Negate => match tok.strip_prefix(['-', '+']) {
            Some(rest) if tok.starts_with('-') => rest.to_string(),
            Some(rest) => format!("-{rest}"),
            None => format!("-{tok}"),
        },
        NewNumber::Scale(k) => {
            let integer = !tok.contains(['.', 'e', 'E']);
            match (integer, tok.parse::<i128>()) {
                (true, Ok(v)) if *k >= 0 => v
                    .saturating_mul(10i128.saturating_pow(*k as u32))
                    .to_string(),
                (true, Ok(v)) => (v / 10i128.pow(k.unsigned_abs().min(30))).to_string(),
                _ => match tok.replace('_', "").parse::<f64>() {
                    Ok(v) => float(v * 10f64.powi(*k)),
                    Err(_) => tok.to_string(),
                },
            }
        }
    }
}

/// A float as TOML writes it.
fn float(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{v:?}")
    }
}

fn pick(i: &Index, n: usize) -> Option<usize> {
    (n > 0).then(|| i.index(n))
}

fn lines(text: &str) -> Vec<String> {
    text.lines().map(str::to_string).collect()
}

fn join(lines: &[String]) -> String {
    let mut s = lines.join("\n");
    s.push('\n');
    s
}

fn line_edit(text: &str, i: &Index, duplicate: bool) -> String {
    let mut l = lines(text);
    if let Some(k) = pick(i, l.len()) {
        if duplicate {
            l.insert(k, l[k].clone());
        } else {
            l.remove(k);
        }
    }
    join(&l)
}

fn truncate(text: &str, i: &Index) -> String {
    let mut at = i.index(text.len() + 1);
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    text[..at].to_string()
}

/// The blocks of a TOML text: the lines before the first table, then one per table header.
fn tables(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut pre = Vec::new();
    let mut blocks: Vec<Vec<String>> = Vec::new();
    for l in text.lines() {
        if l.trim_start().starts_with('[') {
            blocks.push(vec![l.to_string()]);
        } else if let Some(b) = blocks.last_mut() {
            b.push(l.to_string());
        } else {
            pre.push(l.to_string());
        }
    }
    (pre, blocks)
}

fn swap_tables(text: &str, a: &Index, b: &Index) -> String {
    let (mut all, mut blocks) = tables(text);
    if let (Some(x), Some(y)) = (pick(a, blocks.len()), pick(b, blocks.len())) {
        blocks.swap(x, y);
    }
    all.extend(blocks.into_iter().flatten());
    join(&all)
}

/// One-line arrays `= [ … ]` of a TOML text: drop the last element or repeat the first.
fn array_length(text: &str, i: &Index, longer: bool) -> String {
    let mut l = lines(text);
    let arrays: Vec<usize> = (0..l.len())
        .filter(|&k| l[k].contains("= [") && l[k].trim_end().ends_with(']'))
        .collect();
    if let Some(k) = pick(i, arrays.len()).map(|j| arrays[j]) {
        let line = &l[k];
        let open = line.find("= [").unwrap() + 3;
        let close = line.rfind(']').unwrap();
        let mut items: Vec<String> = line[open..close].split(',').map(str::to_string).collect();
        if longer {
            items.insert(0, items[0].clone());
        } else {
            items.pop();
        }
        l[k] = format!("{}{}]", &line[..open], items.join(","));
    }
    join(&l)
}

fn set_method(text: &str, method: &str) -> String {
    let (mut all, blocks) = tables(text);
    let entry = format!("method = \"{method}\"");
    let mut found = false;
    for mut b in blocks {
        if b[0].trim() == "[solver]" {
            b.retain(|l| !l.trim_start().starts_with("method"));
            b.insert(1, entry.clone());
            found = true;
        }
        all.extend(b);
    }
    if !found {
        all.push("[solver]".into());
        all.push(entry);
    }
    join(&all)
}

/// `m` applied to a TOML model text.
pub fn model(text: &str, m: &Mutation) -> String {
    match m {
        Mutation::Number(i, n) => {
            let nums = numbers(text);
            match pick(i, nums.len()).map(|k| nums[k]) {
                Some((a, b)) => {
                    format!("{}{}{}", &text[..a], new_number(&text[a..b], n), &text[b..])
                }
                None => text.to_string(),
            }
        }
        Mutation::DeleteLine(i) => line_edit(text, i, false),
        Mutation::DuplicateLine(i) => line_edit(text, i, true),
        Mutation::SwapTables(a, b) => swap_tables(text, a, b),
        Mutation::JunkKey(i, junk) => {
            let mut l = lines(text);
            let k = i.index(l.len() + 1);
            l.insert(k, junk.to_string());
            join(&l)
        }
        Mutation::Truncate(i) => truncate(text, i),
        Mutation::ArrayLength(i, longer) => array_length(text, i, *longer),
        Mutation::Method(name) => set_method(text, name),
        _ => text.to_string(),
    }
}

/// The line of an AT2 text holding NPTS and DT (the 4th, or the first naming NPTS).
fn header_line(l: &[String]) -> Option<usize> {
    l.iter()
        .position(|s| s.to_ascii_uppercase().contains("NPTS"))
        .or((l.len() > 3).then_some(3))
}

fn set_header(line: &str, npts: bool, value: &str) -> String {
    let up = line.to_ascii_uppercase();
    let key = if npts { "NPTS" } else { "DT" };
    let Some(k) = up.find(key) else {
        return format!("{line} {key}= {value}");
    };
    let mut at = k + key.len();
    let b = line.as_bytes();
    while at < b.len() && (b[at] == b'=' || b[at] == b' ') {
        at += 1;
    }
    let mut end = at;
    while end < b.len() && !b" ,\t".contains(&b[end]) {
        end += 1;
    }
    format!("{}{value}{}", &line[..at], &line[end..])
}

/// `m` applied to an AT2 record text.
pub fn at2(text: &str, m: &Mutation) -> String {
    let mut l = lines(text);
    let head = header_line(&l).map_or(0, |h| h + 1);
    match m {
        Mutation::At2Header(npts, v) => {
            if let Some(h) = header_line(&l) {
                l[h] = set_header(&l[h], *npts, v);
            }
        }
        Mutation::At2Truncate(i) => {
            let keep = head + i.index(l.len().saturating_sub(head) + 1);
            l.truncate(keep.min(l.len()));
        }
        Mutation::At2Token(i, tok) => {
            let toks: Vec<(usize, usize)> = (head..l.len())
                .flat_map(|k| (0..l[k].split_whitespace().count()).map(move |j| (k, j)))
                .collect();
            if let Some((k, j)) = pick(i, toks.len()).map(|x| toks[x]) {
                let mut words: Vec<&str> = l[k].split_whitespace().collect();
                words[j] = tok;
                l[k] = format!("  {}", words.join("  "));
            }
        }
        Mutation::At2Line(i, dup) => return line_edit(text, i, *dup),
        _ => {}
    }
    join(&l)
}
