//! Adding and removing the elements of a bridge's lists from the form (`+`, `-` on a field of
//! the element): a frame with its bents (and a joint with it, so that there is one joint fewer
//! than frames), a bent, a run; a joint's key (`+` on a joint without one copies the file's
//! first key line, `-` removes it). Edits of the draft's text, line by line:
//! comments and the layout of the rest are kept.

/// A table header line: its line index, its dotted name and whether it is `[[…]]`.
struct Header {
    line: usize,
    name: String,
}

fn headers(lines: &[&str]) -> Vec<Header> {
    let mut out = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let t = l.trim();
        if let Some(rest) = t.strip_prefix("[[") {
            if let Some(name) = rest.split("]]").next() {
                out.push(Header {
                    line: i,
                    name: name.trim().to_string(),
                });
            }
        } else if let Some(rest) = t.strip_prefix('[')
            && let Some(name) = rest.split(']').next()
        {
            out.push(Header {
                line: i,
                name: name.trim().to_string(),
            });
        }
    }
    out
}

/// Lines [start, end) of the n-th `[[name]]` element (its sub-tables `name.…` included, the
/// comments and blank lines just before the next header left out).
fn block(lines: &[&str], name: &str, n: usize, within: (usize, usize)) -> Option<(usize, usize)> {
    let hs = headers(lines);
    let mine: Vec<&Header> = (hs.iter())
        .filter(|h| h.name == name && h.line >= within.0 && h.line < within.1)
        .collect();
    let start = mine.get(n)?.line;
    let child = format!("{name}.");
    let mut end = (hs.iter())
        .find(|h| h.line > start && !h.name.starts_with(&child))
        .map_or(lines.len(), |h| h.line)
        .min(within.1);
    while end > start + 1 && {
        let t = lines[end - 1].trim();
        t.is_empty() || t.starts_with('#')
    } {
        end -= 1;
    }
    Some((start, end))
}

fn count(lines: &[&str], name: &str) -> usize {
    headers(lines).iter().filter(|h| h.name == name).count()
}

/// The `name = "…"` values of a text (to keep copied names distinct).
fn names(lines: &[&str]) -> Vec<String> {
    lines.iter().filter_map(|l| name_of(l)).collect()
}

fn name_of(line: &str) -> Option<String> {
    let t = line.trim();
    let rest = t
        .strip_prefix("name")?
        .trim_start()
        .strip_prefix('=')?
        .trim();
    let v = rest.strip_prefix('"')?;
    Some(v[..v.find('"')?].to_string())
}

/// A copy of `block` whose `name = "X"` lines read `X_copy` (or `X_copy2`, … if taken).
fn renamed(block: &[&str], taken: &[String]) -> Vec<String> {
    block
        .iter()
        .map(|l| match name_of(l) {
            Some(n) => {
                let mut new = format!("{n}_copy");
                let mut k = 2;
                while taken.contains(&new) {
                    new = format!("{n}_copy{k}");
                    k += 1;
                }
                l.replacen(&format!("\"{n}\""), &format!("\"{new}\""), 1)
            }
            None => l.to_string(),
        })
        .collect()
}

/// The list element a form field belongs to: (list, index, the enclosing frame for a frame's
/// bent).
fn element(path: &str) -> Option<(&'static str, usize, Option<usize>)> {
    let s: Vec<&str> = path.split('.').collect();
    let n = |i: usize| s.get(i).and_then(|x| x.parse::<usize>().ok());
    match s.as_slice() {
        ["frame", _, "bent", _, ..] => Some(("frame.bent", n(3)?, Some(n(1)?))),
        ["frame", _, ..] => Some(("frame", n(1)?, None)),
        ["joint", _, "key", ..] => Some(("joint.key", n(1)?, None)),
        ["joint", _, ..] => Some(("joint", n(1)?, None)),
        ["bent", _, ..] => Some(("bent", n(1)?, None)),
        ["run", _, ..] => Some(("run", n(1)?, None)),
        ["abutment", "key", ..] => Some(("abutment.key", 0, None)),
        _ => None,
    }
}

fn join(lines: Vec<String>, text: &str) -> String {
    let mut out = lines.join("\n");
    if text.ends_with('\n') {
        out.push('\n');
    }
    out
}

/// The draft with a copy of the list element of `path` after it (a frame: its copy and a copy
/// of a joint next to it), and what was done.
pub fn duplicate(text: &str, path: &str) -> Result<(String, String), String> {
    let lines: Vec<&str> = text.lines().collect();
    let all = (0, lines.len());
    let Some((list, n, frame)) = element(path) else {
        return Err(format!(
            "{path} is not in a list (frames, bents, joints, runs)"
        ));
    };
    let taken = names(&lines);
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    let missing = || format!("no element {n} of {list}");
    match list {
        "frame" => {
            let (a, b) = block(&lines, "frame", n, all).ok_or_else(missing)?;
            let joints = count(&lines, "joint");
            if joints == 0 {
                return Err(
                    "a bridge of one frame has no joint to copy: add a [[joint]] \
                            in the file, then duplicate the frame"
                        .into(),
                );
            }
            let j = n.min(joints - 1);
            let (ja, jb) = block(&lines, "joint", j, all).ok_or_else(missing)?;
            let frame_copy = renamed(&lines[a..b], &taken);
            let joint_copy: Vec<String> = lines[ja..jb].iter().map(|l| l.to_string()).collect();
            // the later insertion first, so the earlier indices hold
            let mut inserts = [(b, frame_copy), (jb, joint_copy)];
            inserts.sort_by_key(|x| std::cmp::Reverse(x.0));
            for (at, mut copy) in inserts {
                copy.insert(0, String::new());
                out.splice(at..at, copy);
            }
            Ok((
                join(out, text),
                format!("frame {} copied, with joint {}", n + 1, j + 1),
            ))
        }
        "frame.bent" | "bent" | "run" => {
            let within = match frame {
                Some(f) => block(&lines, "frame", f, all).ok_or_else(missing)?,
                None => all,
            };
            let (a, b) = block(&lines, list, n, within).ok_or_else(missing)?;
            let mut copy = renamed(&lines[a..b], &taken);
            copy.insert(0, String::new());
            out.splice(b..b, copy);
            let what = list.rsplit('.').next().unwrap_or(list);
            Ok((join(out, text), format!("{what} {} copied", n + 1)))
        }
        "joint" => add_key(&lines, n, text),
        "joint.key" => Err(format!("joint {} has its key", n + 1)),
        _ => Err(format!("{path}: nothing to copy")),
    }
}

/// A `key = { … }` line.
fn is_key_line(line: &str) -> bool {
    let t = line.trim_start();
    t.strip_prefix("key")
        .is_some_and(|r| r.trim_start().starts_with('='))
}

/// A joint without a key gets a copy of the first key line of the file (a joint's or the
/// abutment's): keys are added as a list of the joints.
fn add_key(lines: &[&str], n: usize, text: &str) -> Result<(String, String), String> {
    let (a, b) =
        block(lines, "joint", n, (0, lines.len())).ok_or_else(|| format!("no joint {}", n + 1))?;
    if lines[a..b].iter().any(|l| is_key_line(l)) {
        return Err(format!("joint {} has its key", n + 1));
    }
    let key = (lines.iter().find(|l| is_key_line(l)))
        .ok_or("no key in the file to copy: write one (joint.N.key = { gap, stiffness, capacity, failure_displacement })")?;
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    out.insert(b, key.trim_start().to_string());
    Ok((
        join(out, text),
        format!("joint {} keyed (a copy of the file's first key)", n + 1),
    ))
}

/// The draft without the list element of `path` (a frame: with the joint before it, or after
/// the first), and what was done.
pub fn remove(text: &str, path: &str) -> Result<(String, String), String> {
    let lines: Vec<&str> = text.lines().collect();
    let all = (0, lines.len());
    let Some((list, n, frame)) = element(path) else {
        return Err(format!(
            "{path} is not in a list (frames, bents, joints, runs, keys)"
        ));
    };
    let missing = || format!("no element {n} of {list}");
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    let cut = |(a, b): (usize, usize), out: &mut Vec<String>| {
        out.drain(a..b);
    };
    match list {
        "frame" => {
            if count(&lines, "frame") < 2 {
                return Err("the bridge's only frame cannot be removed".into());
            }
            let (a, b) = block(&lines, "frame", n, all).ok_or_else(missing)?;
            let j = n.saturating_sub(1);
            let joint = block(&lines, "joint", j, all).ok_or_else(missing)?;
            let mut spans = [(a, b), joint];
            spans.sort_by_key(|x| std::cmp::Reverse(x.0));
            for s in spans {
                cut(s, &mut out);
            }
            Ok((
                join(out, text),
                format!("frame {} removed, with joint {}", n + 1, j + 1),
            ))
        }
        "frame.bent" | "bent" | "run" => {
            let within = match frame {
                Some(f) => block(&lines, "frame", f, all).ok_or_else(missing)?,
                None => all,
            };
            cut(
                block(&lines, list, n, within).ok_or_else(missing)?,
                &mut out,
            );
            let what = list.rsplit('.').next().unwrap_or(list);
            Ok((join(out, text), format!("{what} {} removed", n + 1)))
        }
        "joint.key" | "abutment.key" => {
            let (table, at) = match list {
                "joint.key" => ("joint", block(&lines, "joint", n, all).ok_or_else(missing)?),
                _ => {
                    let hs = headers(&lines);
                    let h = hs
                        .iter()
                        .position(|h| h.name == "abutment")
                        .ok_or_else(missing)?;
                    let end = hs.get(h + 1).map_or(lines.len(), |x| x.line);
                    ("abutment", (hs[h].line, end))
                }
            };
            let key = (at.0..at.1)
                .find(|&i| is_key_line(lines[i]))
                .ok_or_else(|| format!("{table} has no key line"))?;
            cut((key, key + 1), &mut out);
            Ok((join(out, text), format!("{table} key removed")))
        }
        "joint" => {
            Err("a joint goes with a frame: remove the frame (`-` on one of its fields)".into())
        }
        _ => Err(format!("{path}: nothing to remove")),
    }
}
